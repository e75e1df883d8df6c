#include "scene/scene_accel.h"

#include <tbb/parallel_for.h>

#include <cmath>

#include "build/binned_sah_builder.h"
#include "scene/primitive_collection.h"
#include "traversal/bvh2_traverse.h"

namespace obvh {
namespace {

bool isUsableBox(const Box3f& b) {
  const float c[6] = {b.lower.x, b.lower.y, b.lower.z, b.upper.x, b.upper.y, b.upper.z};
  for (float v : c)
    if (!std::isfinite(v)) return false;
  return !b.empty();
}

// Embree instancing is one level deep in Debian's build: instances inside instanced scenes are skipped.
constexpr int kMaxInstanceLevel = 1;

}  // namespace

void SceneAccel::build(const SceneDesc& desc, const BuildOptions& options) {
  owner_ = desc.owner;
  geometryMasks_.assign(desc.geometryIdLimit, 0u);
  for (const MeshDesc& mesh : desc.meshes) geometryMasks_[mesh.geomID] = mesh.mask;
  for (const InstanceDesc& inst : desc.instances) geometryMasks_[inst.geomID] = inst.mask;
  for (const UserGeometryDesc& user : desc.userGeometries) geometryMasks_[user.geomID] = user.mask;
  intersectFiltered_ = desc.intersectFiltered;
  occlusionFiltered_ = desc.occlusionFiltered;
  intersectFiltered_.resize(desc.geometryIdLimit, 0);
  occlusionFiltered_.resize(desc.geometryIdLimit, 0);

  CollectedPrimitives collected = collectPrimitives(desc.meshes);
  triangleBvh_ = buildBinnedSah(collected.refs, options);
  triangles_.resize(triangleBvh_.primIndices.size());
  tbb::parallel_for(size_t(0), triangles_.size(),
                    [&](size_t i) { triangles_[i] = collected.triangles[triangleBvh_.primIndices[i]]; });

  std::vector<ObjectRef> objects;
  std::vector<PrimRef> objectRefs;
  instances_.clear();
  for (const InstanceDesc& inst : desc.instances) {
    if (!inst.child) continue;
    const Box3f world = inst.localToWorld.xfmBounds(inst.child->bounds());
    if (!isUsableBox(world)) continue;
    objectRefs.push_back({world, uint32_t(objects.size())});
    objects.push_back({ObjectKind::Instance, uint32_t(instances_.size()), 0});
    instances_.push_back({inst.child, Affine3d::inverseOf(inst.localToWorld), inst.geomID});
  }
  for (const UserGeometryDesc& user : desc.userGeometries)
    for (size_t prim = 0; prim < user.primitiveBounds.size(); ++prim) {
      if (!isUsableBox(user.primitiveBounds[prim])) continue;
      objectRefs.push_back({user.primitiveBounds[prim], uint32_t(objects.size())});
      objects.push_back({ObjectKind::UserPrimitive, user.geomID, uint32_t(prim)});
    }
  objectBvh_ = buildBinnedSah(objectRefs, options);
  objects_.resize(objectBvh_.primIndices.size());
  for (size_t i = 0; i < objects_.size(); ++i) objects_[i] = objects[objectBvh_.primIndices[i]];

  bounds_ = Box3f{};
  if (!triangleBvh_.empty()) bounds_.extend(triangleBvh_.nodes[0].bounds);
  if (!objectBvh_.empty()) bounds_.extend(objectBvh_.nodes[0].bounds);
  triangleView_ = TriangleBvhView{};
  if (!triangleBvh_.empty())
    triangleView_ = {triangleBvh_.nodes.data(), triangles_.data(), geometryMasks_.data(),
                     intersectFiltered_.data(),  occlusionFiltered_.data(), owner_};
}

Ray SceneAccel::toLocal(const Instance& instance, const Ray& ray) {
  Ray local = ray;
  local.org = instance.worldToLocal.xfmPoint(ray.org);
  local.dir = instance.worldToLocal.xfmVector(ray.dir);
  return local;
}

bool SceneAccel::intersectObject(const ObjectRef& object, Ray& ray, Hit& hit, const QueryState& state) const {
  if (object.kind == ObjectKind::UserPrimitive) {
    if ((geometryMasks_[object.index] & ray.mask) == 0 || !state.callbacks) return false;
    return state.callbacks->intersectUser(owner_, object.index, object.primID, ray, hit, state);
  }
  const Instance& instance = instances_[object.index];
  if ((geometryMasks_[instance.geomID] & ray.mask) == 0 || state.instanceLevel >= kMaxInstanceLevel) return false;
  Ray local = toLocal(instance, ray);
  QueryState inner = state;
  inner.instID = instance.geomID;
  inner.instanceLevel = state.instanceLevel + 1;
  if (!instance.child->intersect(local, hit, inner)) return false;
  ray.tfar = local.tfar;  // t is the same parameter in both spaces: the direction is transformed, not normalized
  return true;
}

bool SceneAccel::occludedObject(const ObjectRef& object, const Ray& ray, const QueryState& state) const {
  if (object.kind == ObjectKind::UserPrimitive) {
    if ((geometryMasks_[object.index] & ray.mask) == 0 || !state.callbacks) return false;
    Ray copy = ray;
    return state.callbacks->occludedUser(owner_, object.index, object.primID, copy, state);
  }
  const Instance& instance = instances_[object.index];
  if ((geometryMasks_[instance.geomID] & ray.mask) == 0 || state.instanceLevel >= kMaxInstanceLevel) return false;
  QueryState inner = state;
  inner.instID = instance.geomID;
  inner.instanceLevel = state.instanceLevel + 1;
  return instance.child->occluded(toLocal(instance, ray), inner);
}

bool SceneAccel::intersect(Ray& ray, Hit& hit, const QueryState& state) const {
  bool found = !triangleView_.empty() && intersectClosest(triangleView_, ray, hit, state);
  if (objectBvh_.empty()) return found;
  traverseBvh2(objectBvh_.nodes.data(), ray, [&](const Bvh2Node& leaf) {
    for (uint32_t i = 0; i < leaf.primCount; ++i)
      if (intersectObject(objects_[leaf.firstChildOrPrim + i], ray, hit, state)) found = true;
    return false;
  });
  return found;
}

bool SceneAccel::occluded(const Ray& ray, const QueryState& state) const {
  if (!triangleView_.empty() && intersectAny(triangleView_, ray, state)) return true;
  if (objectBvh_.empty()) return false;
  bool found = false;
  traverseBvh2(objectBvh_.nodes.data(), ray, [&](const Bvh2Node& leaf) {
    for (uint32_t i = 0; i < leaf.primCount; ++i)
      if (occludedObject(objects_[leaf.firstChildOrPrim + i], ray, state)) {
        found = true;
        return true;
      }
    return false;
  });
  return found;
}

SceneStats SceneAccel::stats() const {
  SceneStats s;
  s.primitiveCount = triangles_.size() + objects_.size();
  s.nodeCount = triangleBvh_.nodes.size() + objectBvh_.nodes.size();
  for (const Bvh2Node& node : triangleBvh_.nodes) s.leafCount += node.isLeaf() ? 1 : 0;
  for (const Bvh2Node& node : objectBvh_.nodes) s.leafCount += node.isLeaf() ? 1 : 0;
  s.memoryBytes = s.nodeCount * sizeof(Bvh2Node) + triangles_.size() * sizeof(StoredTriangle) +
                  objects_.size() * sizeof(ObjectRef) + instances_.size() * sizeof(Instance) +
                  geometryMasks_.size() * (sizeof(uint32_t) + 2);
  return s;
}

}  // namespace obvh
