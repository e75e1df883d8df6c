// The object BVH's primitives, tested one by one: instances of other scenes (moving ones placed
// at the ray's time), user-geometry primitives, sphere points and flat curve segments, and the
// triangles of motion-blurred meshes.
#include <algorithm>
#include <cmath>

#include "scene/scene_accel.h"
#include "scene/shape_controls.h"
#include "scene/time_segment.h"
#include "traversal/bvh2_traverse.h"

namespace obvh {
namespace {

// Embree instancing is one level deep in Debian's build: instances inside instanced scenes are skipped.
constexpr int kMaxInstanceLevel = 1;

// s when the transform's linear part is s times a rotation, else 0.
float uniformScaleOf(const Affine3f& a) {
  const float xx = dot(a.vx, a.vx), yy = dot(a.vy, a.vy), zz = dot(a.vz, a.vz);
  const float tolerance = 1e-5f * (xx + yy + zz);
  const bool orthogonal = std::fabs(dot(a.vx, a.vy)) <= tolerance && std::fabs(dot(a.vx, a.vz)) <= tolerance &&
                          std::fabs(dot(a.vy, a.vz)) <= tolerance;
  const bool uniform = std::fabs(xx - yy) <= tolerance && std::fabs(xx - zz) <= tolerance;
  return orthogonal && uniform ? std::sqrt(xx) : 0.f;
}

// Frobenius norm: an upper bound of how much the linear part can stretch a length.
float operatorNormBound(const Affine3d& a) {
  double sum = 0.0;
  for (const auto& row : a.l)
    for (double v : row) sum += v * v;
  return float(std::sqrt(sum));
}

}  // namespace

SceneAccel::Instance SceneAccel::makeInstance(const SceneAccel* child, const Affine3f& localToWorld, uint32_t geomID) {
  const Affine3d worldToLocal = Affine3d::inverseOf(localToWorld);
  // Embree's similarity scale is that of the world-to-instance direction.
  const float scale = uniformScaleOf(localToWorld);
  return {child, worldToLocal, geomID, localToWorld, scale > 0.f ? 1.f / scale : 0.f, operatorNormBound(worldToLocal), {}};
}

const SceneAccel::Instance* SceneAccel::placedAt(const Instance& instance, float time, Instance& storage) {
  if (!instance.motion.moving()) return &instance;
  Affine3f localToWorld;
  if (!instance.motion.at(time, localToWorld)) return nullptr;
  storage = makeInstance(instance.child, localToWorld, instance.geomID);
  return &storage;
}

Ray SceneAccel::toLocal(const Instance& instance, const Ray& ray) {
  Ray local = ray;
  local.org = instance.worldToLocal.xfmPoint(ray.org);
  local.dir = instance.worldToLocal.xfmVector(ray.dir);
  return local;
}

bool SceneAccel::shapeAt(const ShapePrimitive& shape, float time, ShapeVertex out[4]) const {
  const int count = controlPointCount(shape.kind);
  if (shape.stepCount < 2) {
    std::copy(shape.v, shape.v + count, out);
    return true;
  }
  TimeSegment s;
  if (!timeSegment(time, shape.timeStart, shape.timeEnd, shape.stepCount, s)) return false;
  const float f = s.f, g = 1.f - f;
  const ShapeVertex* from = &shapeSteps_[shape.firstStep + size_t(count) * size_t(s.segment)];
  const ShapeVertex* to = from + count;
  for (int k = 0; k < count; ++k) out[k] = {from[k].p * g + to[k].p * f, from[k].r * g + to[k].r * f};
  return true;
}

bool SceneAccel::intersectShape(const ShapePrimitive& shape, Ray& ray, Hit& hit, const QueryState& state,
                                bool occlusion) const {
  if ((geometryMasks_[shape.geomID] & ray.mask) == 0) return false;
  ShapeVertex controls[4];
  if (!shapeAt(shape, ray.time, controls)) return false;
  ShapeHit sh;
  if (!intersectShapeControls(shape.kind, ray, controls, shape.ribbonQuads, sh)) return false;
  Hit candidate;
  candidate.Ng = sh.Ng;
  candidate.u = sh.u;
  candidate.v = sh.v;
  candidate.geomID = shape.geomID;
  candidate.primID = shape.primID;
  candidate.instID = state.instID;
  const std::vector<uint8_t>& filtered = occlusion ? occlusionFiltered_ : intersectFiltered_;
  if (needsFilter(filtered.data(), shape.geomID, state) && !state.callbacks->acceptHit(owner_, ray, candidate, sh.t, occlusion))
    return false;
  if (!occlusion) {
    ray.tfar = sh.t;
    hit = candidate;
  }
  return true;
}

bool SceneAccel::intersectMotionTriangle(const MotionTriangle& motion, Ray& ray, Hit& hit, const QueryState& state,
                                         bool occlusion, WatertightRayOnDemand& watertight) const {
  // The triangle at the ray's time, tested as a leaf of one triangle (masks, filters, Embree's hit).
  StoredTriangle tri;
  if (!motion.at(motion_.vertices, ray.time, tri)) return false;
  TriangleSet set = motionSet_;
  set.triangles = &tri;
  const WatertightRay& wr = watertight.of(ray, set);
  return occlusion ? intersectLeafAny(set, 0, 1, wr, ray, state) : intersectLeafClosest(set, 0, 1, wr, ray, hit, state);
}

bool SceneAccel::intersectObject(const ObjectRef& object, Ray& ray, Hit& hit, const QueryState& state,
                                 WatertightRayOnDemand& watertight) const {
  if (object.kind == ObjectKind::Shape) return intersectShape(shapes_[object.index], ray, hit, state, false);
  if (object.kind == ObjectKind::MotionTriangle)
    return intersectMotionTriangle(motion_.triangles[object.index], ray, hit, state, false, watertight);
  if (object.kind == ObjectKind::UserPrimitive) {
    if ((geometryMasks_[object.index] & ray.mask) == 0 || !state.callbacks) return false;
    return state.callbacks->intersectUser(owner_, object.index, object.primID, ray, hit, state);
  }
  Instance storage;
  const Instance* placed = placedAt(instances_[object.index], ray.time, storage);
  if (!placed) return false;
  const Instance& instance = *placed;
  if ((geometryMasks_[instance.geomID] & ray.mask) == 0 || state.instanceLevel >= kMaxInstanceLevel) return false;
  Ray local = toLocal(instance, ray);
  QueryState inner = state;
  inner.instID = instance.geomID;
  inner.instanceLevel = state.instanceLevel + 1;
  if (!instance.child->intersect(local, hit, inner)) return false;
  ray.tfar = local.tfar;  // t is the same parameter in both spaces: the direction is transformed, not normalized
  return true;
}

bool SceneAccel::occludedObject(const ObjectRef& object, const Ray& ray, const QueryState& state,
                                WatertightRayOnDemand& watertight) const {
  if (object.kind == ObjectKind::MotionTriangle) {
    Ray copy = ray;
    Hit unused;
    return intersectMotionTriangle(motion_.triangles[object.index], copy, unused, state, true, watertight);
  }
  if (object.kind == ObjectKind::Shape) {
    Ray copy = ray;
    Hit unused;
    return intersectShape(shapes_[object.index], copy, unused, state, true);
  }
  if (object.kind == ObjectKind::UserPrimitive) {
    if ((geometryMasks_[object.index] & ray.mask) == 0 || !state.callbacks) return false;
    Ray copy = ray;
    return state.callbacks->occludedUser(owner_, object.index, object.primID, copy, state);
  }
  Instance storage;
  const Instance* placed = placedAt(instances_[object.index], ray.time, storage);
  if (!placed) return false;
  const Instance& instance = *placed;
  if ((geometryMasks_[instance.geomID] & ray.mask) == 0 || state.instanceLevel >= kMaxInstanceLevel) return false;
  QueryState inner = state;
  inner.instID = instance.geomID;
  inner.instanceLevel = state.instanceLevel + 1;
  return instance.child->occluded(toLocal(instance, ray), inner);
}

bool SceneAccel::intersectObjects(Ray& ray, Hit& hit, const QueryState& state) const {
  if (objectBvh_.empty()) return false;
  bool found = false;
  WatertightRayOnDemand watertight;
  traverseBvh2(objectBvh_.nodes.data(), ray, [&](const Bvh2Node& leaf) {
    for (uint32_t i = 0; i < leaf.primCount; ++i)
      if (intersectObject(objects_[leaf.firstChildOrPrim + i], ray, hit, state, watertight)) found = true;
    return false;
  });
  return found;
}

bool SceneAccel::occludedObjects(const Ray& ray, const QueryState& state) const {
  if (objectBvh_.empty()) return false;
  bool found = false;
  WatertightRayOnDemand watertight;
  traverseBvh2(objectBvh_.nodes.data(), ray, [&](const Bvh2Node& leaf) {
    for (uint32_t i = 0; i < leaf.primCount; ++i)
      if (occludedObject(objects_[leaf.firstChildOrPrim + i], ray, state, watertight)) {
        found = true;
        return true;
      }
    return false;
  });
  return found;
}

}  // namespace obvh
