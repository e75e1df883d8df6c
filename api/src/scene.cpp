#include "scene.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "api_error.h"
#include "intersect/ribbon_curve.h"

namespace obvh::api {

Scene::~Scene() {
  if (reportedMemory_ == 0) return;
  try {
    device_->reportMemory(-ssize_t(reportedMemory_), true);
  } catch (...) {
  }
}

unsigned Scene::attach(Geometry* geometry) {
  std::lock_guard<std::mutex> lock(mutex_);
  unsigned id = 0;
  while (id < geometries_.size() && geometries_[id]) ++id;  // lowest free ID, as Embree hands them out
  if (id == geometries_.size()) geometries_.emplace_back();
  geometries_[id] = Ref<Geometry>(geometry);
  markModified();
  return id;
}

void Scene::attachById(Geometry* geometry, unsigned geomID) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (geomID == RTC_INVALID_GEOMETRY_ID) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid argument");
  if (geomID < geometries_.size() && geometries_[geomID])
    fail(RTC_ERROR_INVALID_OPERATION, "invalid geometry ID provided");
  if (geomID >= geometries_.size()) geometries_.resize(size_t(geomID) + 1);
  geometries_[geomID] = Ref<Geometry>(geometry);
  markModified();
}

void Scene::detach(unsigned geomID) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (geomID >= geometries_.size()) fail(RTC_ERROR_INVALID_OPERATION, "invalid geometry ID");
  if (!geometries_[geomID]) fail(RTC_ERROR_INVALID_OPERATION, "invalid geometry");
  geometries_[geomID] = Ref<Geometry>();
  markModified();
}

Geometry* Scene::geometry(unsigned geomID) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (geomID >= geometries_.size()) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid geometry ID");
  return geometries_[geomID].get();
}

void Scene::setFlags(int flags) {
  flags_ = flags;
  markModified();
}

void Scene::setBuildQuality(int quality) {
  // REFIT is a per-geometry quality; scenes accept only the three build levels.
  if (quality != RTC_BUILD_QUALITY_LOW && quality != RTC_BUILD_QUALITY_MEDIUM && quality != RTC_BUILD_QUALITY_HIGH)
    fail(RTC_ERROR_UNKNOWN, "invalid build quality");
  quality_ = quality;
  markModified();
}

void Scene::setProgressMonitor(RTCProgressMonitorFunction fn, void* userPtr) {
  std::lock_guard<std::mutex> lock(mutex_);
  progress_ = fn;
  progressUserPtr_ = userPtr;
}

bool Scene::needsRebuild() const {
  if (modified_ || builtModificationCounters_.size() != geometries_.size()) return true;
  for (size_t id = 0; id < geometries_.size(); ++id) {
    const Geometry* g = geometries_[id].get();
    if (!g) continue;
    if (g->modificationCounter() != builtModificationCounters_[id]) return true;
    if (g->instancedScene() && g->instancedScene()->buildGeneration() != builtChildGenerations_[id]) return true;
  }
  return false;
}

namespace {

MeshDesc meshOf(const Geometry& g, uint32_t geomID) {
  const BufferView& index = g.indexBuffer();
  const BufferView& vertex = g.vertexBuffer();
  MeshDesc mesh;
  mesh.vertices = vertex.data();
  mesh.vertexStride = vertex.byteStride;
  mesh.vertexCount = vertex.itemCount;
  mesh.indices = index.data();
  mesh.indexStride = index.byteStride;
  mesh.primCount = index.itemCount;
  mesh.topology = g.isGridMesh() ? MeshTopology::Grids : g.isQuadMesh() ? MeshTopology::Quads : MeshTopology::Triangles;
  mesh.geomID = geomID;
  mesh.mask = g.mask();
  if (g.timeStepCount() > 1) {
    for (unsigned step = 0; step < g.timeStepCount(); ++step) mesh.timeStepVertices.push_back(g.vertexBuffer(step).data());
    mesh.timeStart = g.timeStart();
    mesh.timeEnd = g.timeEnd();
  }
  return mesh;
}

// A subdivision geometry is traced as the tessellation its commit made (none without its buffers).
bool subdivisionMeshOf(const Geometry& g, uint32_t geomID, MeshDesc& mesh) {
  const obvh::SubdivTessellation* t = g.subdivision().tessellation();
  if (!t || t->cells.empty()) return false;
  mesh.vertices = reinterpret_cast<const unsigned char*>(t->vertices.data());
  mesh.vertexStride = sizeof(Vec3f);
  mesh.vertexCount = t->vertices.size();
  mesh.indices = reinterpret_cast<const unsigned char*>(t->cellCorners.data());
  mesh.indexStride = 4 * sizeof(uint32_t);
  mesh.primCount = t->cells.size();
  mesh.subdivCells = t->cells.data();
  mesh.topology = MeshTopology::SubdivCells;
  mesh.geomID = geomID;
  mesh.mask = g.mask();
  if (!g.subdivision().laterSteps().empty()) {
    mesh.timeStepVertices.push_back(mesh.vertices);
    for (const std::vector<Vec3f>& step : g.subdivision().laterSteps())
      mesh.timeStepVertices.push_back(reinterpret_cast<const unsigned char*>(step.data()));
    mesh.timeStart = g.timeStart();
    mesh.timeEnd = g.timeEnd();
  }
  return true;
}

// The vertex buffers of every time step are set and all of one size (Embree's geometry
// verification); else nothing of the geometry is built.
bool timeStepVerticesComplete(const Geometry& g) {
  for (unsigned step = 0; step < g.timeStepCount(); ++step) {
    const BufferView& v = g.vertexBuffer(step);
    if (!v.bound() || !v.data() || v.itemCount != g.vertexBuffer().itemCount) return false;
  }
  return true;
}

// A mesh is built when its primitive buffer is set too.
bool meshBuffersComplete(const Geometry& g) {
  return g.indexBuffer().bound() && g.indexBuffer().data() && timeStepVerticesComplete(g);
}

// Sphere points and curves: their float4 vertices (and a curve's segment indices) are copied, as the
// backend keeps its own copy of every primitive it intersects.
ShapeVertex shapeVertexAt(const BufferView& buffer, size_t i) {
  float v[4];
  std::memcpy(v, buffer.data() + i * buffer.byteStride, sizeof v);
  return {{v[0], v[1], v[2]}, v[3]};
}

// Hermite segments become the Bezier segments Embree makes of them, rounded in float as it rounds
// them: (p0, p0 + t0/3, p1 - t1/3, p1), radii alike; four vertices a segment. A segment whose
// vertices or tangents lie past their buffers is skipped (its start points past the vertices).
void hermiteAsBezier(const Geometry& g, ShapeGeometryDesc& desc) {
  const BufferView& index = g.indexBuffer();
  const size_t segments = index.data() ? index.itemCount : 0;
  for (unsigned step = 0; step < g.timeStepCount(); ++step) {
    const BufferView& tangent = g.tangentBuffer(step);
    if (!tangent.bound() || !tangent.data()) return;
  }
  desc.vertices.assign(4 * segments, ShapeVertex{});
  desc.laterSteps.assign(g.timeStepCount() - 1, desc.vertices);
  desc.segments.assign(segments, 0xFFFFFFFFu);
  const auto third = [](const ShapeVertex& p, const ShapeVertex& t, float sign) {
    const float s = sign / 3.f;
    return ShapeVertex{{std::fma(s, t.p.x, p.p.x), std::fma(s, t.p.y, p.p.y), std::fma(s, t.p.z, p.p.z)},
                       std::fma(s, t.r, p.r)};
  };
  for (size_t k = 0; k < segments; ++k) {
    uint32_t first;
    std::memcpy(&first, index.data() + k * index.byteStride, sizeof first);
    const uint64_t last = uint64_t(first) + 1;
    bool inside = last < g.vertexBuffer().itemCount;
    for (unsigned step = 0; step < g.timeStepCount(); ++step) inside &= last < g.tangentBuffer(step).itemCount;
    if (!inside) continue;
    desc.segments[k] = uint32_t(4 * k);
    for (unsigned step = 0; step < g.timeStepCount(); ++step) {
      const BufferView &vertex = g.vertexBuffer(step), &tangent = g.tangentBuffer(step);
      const ShapeVertex p0 = shapeVertexAt(vertex, first), p1 = shapeVertexAt(vertex, last);
      const ShapeVertex t0 = shapeVertexAt(tangent, first), t1 = shapeVertexAt(tangent, last);
      ShapeVertex* out = &(step == 0 ? desc.vertices : desc.laterSteps[step - 1])[4 * k];
      out[0] = p0, out[1] = third(p0, t0, 1.f), out[2] = third(p1, t1, -1.f), out[3] = p1;
    }
  }
}

ShapeGeometryDesc shapeOf(const Geometry& g, uint32_t geomID) {
  ShapeGeometryDesc desc;
  desc.kind = g.shapeKind();
  desc.geomID = geomID;
  desc.mask = g.mask();
  desc.ribbonQuads = obvh::ribbonQuadCount(g.tessellationRate());
  const auto copyStep = [&](unsigned step, std::vector<ShapeVertex>& out) {
    const BufferView& vertex = g.vertexBuffer(step);
    out.resize(vertex.itemCount);
    for (size_t i = 0; i < vertex.itemCount; ++i) out[i] = shapeVertexAt(vertex, i);
  };
  if (!timeStepVerticesComplete(g)) return desc;
  desc.timeStart = g.timeStart(), desc.timeEnd = g.timeEnd();
  if (g.isHermite()) {
    hermiteAsBezier(g, desc);
    return desc;
  }
  copyStep(0, desc.vertices);
  desc.laterSteps.resize(g.timeStepCount() - 1);
  for (unsigned step = 1; step < g.timeStepCount(); ++step) copyStep(step, desc.laterSteps[step - 1]);
  const BufferView& index = g.indexBuffer();
  if (desc.kind != ShapeKind::Sphere && index.data()) {
    desc.segments.resize(index.itemCount);
    for (size_t i = 0; i < index.itemCount; ++i) std::memcpy(&desc.segments[i], index.data() + i * index.byteStride, 4);
  }
  return desc;
}

UserGeometryDesc userGeometryOf(const Geometry& g, uint32_t geomID) {
  UserGeometryDesc desc;
  desc.geomID = geomID;
  desc.mask = g.mask();
  const UserCallbacks& user = g.user();
  if (!user.bounds) return desc;
  desc.primitiveBounds.resize(user.primitiveCount);
  for (unsigned prim = 0; prim < user.primitiveCount; ++prim) {
    // A moving primitive's bounds over every time step (the callback's timeStep argument).
    Box3f& box = desc.primitiveBounds[prim];
    for (unsigned step = 0; step < g.timeStepCount(); ++step) {
      RTCBounds b{};
      RTCBoundsFunctionArguments args{g.userData(), prim, step, &b};
      user.bounds(&args);
      if (!(b.lower_x <= b.upper_x && b.lower_y <= b.upper_y && b.lower_z <= b.upper_z)) {
        box = Box3f{};
        break;
      }
      box.extend({b.lower_x, b.lower_y, b.lower_z});
      box.extend({b.upper_x, b.upper_y, b.upper_z});
    }
  }
  return desc;
}

}  // namespace

// Embree refits geometries whose build quality is RTC_BUILD_QUALITY_REFIT when only their vertices
// changed; obvh refits when every geometry of the scene asks for it and the set is unchanged
// (SceneAccel::refit checks the rest and falls back to a build).
bool Scene::wantsRefit() const {
  if (builtGeometries_.size() != geometries_.size()) return false;
  for (size_t id = 0; id < geometries_.size(); ++id)
    if (builtGeometries_[id].get() != geometries_[id].get()) return false;
  return refitsLater();
}

// Whether a later commit of the same geometries would refit (wantsRefit): every geometry a triangle
// or quad mesh of RTC_BUILD_QUALITY_REFIT. Only then does a build keep what a refit needs.
bool Scene::refitsLater() const {
  bool any = false;
  for (const Ref<Geometry>& g : geometries_) {
    if (!g) continue;
    const bool mesh = g->type() == RTC_GEOMETRY_TYPE_TRIANGLE || g->type() == RTC_GEOMETRY_TYPE_QUAD;
    if (!mesh || g->buildQuality() != RTC_BUILD_QUALITY_REFIT) return false;
    any = true;
  }
  return any;
}

void Scene::rebuild() {
  // Single rays take the general path until a commit ends well: a build that fails (a memory
  // monitor's cancel) may leave a tree the direct path must not trace.
  directEntry_ = nullptr;
  const bool refit = wantsRefit();
  SceneDesc desc;
  desc.owner = this;
  desc.geometryIdLimit = uint32_t(geometries_.size());
  desc.intersectFiltered.assign(geometries_.size(), 0);
  desc.occlusionFiltered.assign(geometries_.size(), 0);
  const bool masksOff = !device_->config().rayMasks;
  builtModificationCounters_.assign(geometries_.size(), 0);
  builtChildGenerations_.assign(geometries_.size(), 0);
  builtGeometries_ = geometries_;
  needsCallbacks_ = false;
  for (size_t id = 0; id < geometries_.size(); ++id) {
    Geometry* g = geometries_[id].get();
    if (!g) continue;
    builtModificationCounters_[id] = g->modificationCounter();
    if (!g->enabled()) continue;
    desc.intersectFiltered[id] = g->intersectFilter() != nullptr;
    desc.occlusionFiltered[id] = g->occludedFilter() != nullptr;
    needsCallbacks_ |= desc.intersectFiltered[id] || desc.occlusionFiltered[id];
    switch (g->type()) {
      case RTC_GEOMETRY_TYPE_TRIANGLE:
      case RTC_GEOMETRY_TYPE_QUAD:
      case RTC_GEOMETRY_TYPE_GRID:
        if (meshBuffersComplete(*g)) desc.meshes.push_back(meshOf(*g, uint32_t(id)));
        break;
      case RTC_GEOMETRY_TYPE_SUBDIVISION: {
        MeshDesc mesh;
        if (subdivisionMeshOf(*g, uint32_t(id), mesh)) desc.meshes.push_back(mesh);
        break;
      }
      case RTC_GEOMETRY_TYPE_SPHERE_POINT:
      case RTC_GEOMETRY_TYPE_FLAT_LINEAR_CURVE:
      case RTC_GEOMETRY_TYPE_ROUND_BEZIER_CURVE:
      case RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE:
      case RTC_GEOMETRY_TYPE_ROUND_CATMULL_ROM_CURVE:
      case RTC_GEOMETRY_TYPE_FLAT_BEZIER_CURVE:
      case RTC_GEOMETRY_TYPE_FLAT_BSPLINE_CURVE:
      case RTC_GEOMETRY_TYPE_FLAT_CATMULL_ROM_CURVE:
      case RTC_GEOMETRY_TYPE_ROUND_HERMITE_CURVE:
      case RTC_GEOMETRY_TYPE_FLAT_HERMITE_CURVE:
        desc.shapes.push_back(shapeOf(*g, uint32_t(id)));
        break;
      case RTC_GEOMETRY_TYPE_USER:
        desc.userGeometries.push_back(userGeometryOf(*g, uint32_t(id)));
        needsCallbacks_ = true;
        break;
      case RTC_GEOMETRY_TYPE_INSTANCE: {
        Scene* child = g->instancedScene();
        if (!child) fail(RTC_ERROR_INVALID_OPERATION, "instance has no instanced scene");
        if (child == this) fail(RTC_ERROR_INVALID_OPERATION, "a scene cannot instance itself");
        child->requireCommitted();
        builtChildGenerations_[id] = child->buildGeneration();
        needsCallbacks_ |= child->needsCallbacks();
        desc.instances.push_back({&child->accel(), g->transform(), uint32_t(id), g->mask(), g->instanceMotion()});
        break;
      }
      default:
        break;
    }
  }
  if (masksOff) {
    for (MeshDesc& m : desc.meshes) m.mask = 0xFFFFFFFFu;
    for (ShapeGeometryDesc& s : desc.shapes) s.mask = 0xFFFFFFFFu;
    for (InstanceDesc& i : desc.instances) i.mask = 0xFFFFFFFFu;
    for (UserGeometryDesc& u : desc.userGeometries) u.mask = 0xFFFFFFFFu;
  }
  BuildOptions options;
  options.layout = device_->config().accel;
  options.intersector = (flags_ & RTC_SCENE_FLAG_ROBUST) ? IntersectorMode::Watertight : device_->config().intersector;
  options.childOrder = device_->config().childOrder;
  options.keepBinaryTree = refitsLater();
  options.quality = quality_ == RTC_BUILD_QUALITY_HIGH  ? BuildQuality::High
                    : quality_ == RTC_BUILD_QUALITY_LOW ? BuildQuality::Low
                                                        : BuildQuality::Medium;
  options.spatialBudget = device_->config().spatialBudget;
  options.collapse = device_->config().collapse;
  options.binCount = device_->config().buildBins;
  options.traversalCost = device_->config().traversalCost;
  options.intersectionCost = device_->config().intersectionCost;
  options.builder = device_->config().builder;
  const int layoutWidth = options.layout == AccelLayout::Bvh8 ? 8 : options.layout == AccelLayout::Bvh4 ? 4 : 2;
  options.kmeansArity = device_->config().kmeansArity > 0 ? device_->config().kmeansArity : layoutWidth;
  options.distanceAlpha = device_->config().distanceAlpha;
  options.distanceSource = device_->config().distanceSource;
  options.maxLeafSize = device_->config().maxLeafSize;  // 0: the layout's and builder's default
  options.obbSplit = device_->config().obbSplit;
  options.obbBins = device_->config().obbBins;
  options.obbFit = device_->config().obbFit;
  options.obbClusters = device_->config().obbClusters;
  options.obbPalette = device_->config().obbPalette >= 0 ? device_->config().obbPalette
                       : options.obbClusters > 0       ? 0
                                                       : kDefaultObbPalette;
  options.obbWidth = device_->config().obbWidth;
  options.obbPackets = device_->config().obbPackets;
  options.obbTestCost = device_->config().obbTestCost;
  const auto started = std::chrono::steady_clock::now();
  bool refitted = false;
  device_->execute([&] {
    refitted = refit && accel_.refit(desc, options);
    if (!refitted) accel_.build(desc, options);
  });
  ++buildGeneration_;
  builtForDirectRays_ = !needsCallbacks_ && accel_.wideTrianglesOnly();
  if (builtForDirectRays_) builtEntry_ = accel_.queryEntry();
  if (device_->config().verbose >= 2) printBuildStatistics(refitted, std::chrono::steady_clock::now() - started);

  // Reported after the build (post = true): the application counts it even when it cancels, so it
  // is recorded as reported before the monitor may throw.
  const size_t memory = accel_.stats().memoryBytes;
  const ssize_t change = ssize_t(memory) - ssize_t(reportedMemory_);
  reportedMemory_ = memory;
  device_->reportMemory(change, true);
}

// verbose=2 prints each build as Embree does, with its SAH cost in Embree's convention
// ("total : sah = ..."), so the two libraries' trees compare by one number.
void Scene::printBuildStatistics(bool refitted, std::chrono::steady_clock::duration took) const {
  const SceneStats stats = accel_.stats();
  const AccelLayout layout = accel_.layout();
  const char* layoutName = layout == AccelLayout::Bvh8   ? "bvh8"
                           : layout == AccelLayout::Bvh4 ? "bvh4"
                           : layout == AccelLayout::Bvh2 ? "bvh2"
                           : layout == AccelLayout::Obb  ? "obb"
                                                         : "hybrid";
  std::printf("obvh: %s %s over %zu primitives in %.3f ms\n  total : sah = %.3f, %zu nodes, %zu leaves, %.2f MB\n",
              refitted ? "refitted" : "built", layoutName, stats.primitiveCount,
              std::chrono::duration<double, std::milli>(took).count(), accel_.statisticsSah(), stats.nodeCount,
              stats.leafCount, double(stats.memoryBytes) / (1024.0 * 1024.0));
  if (stats.leafBlockCount)
    std::printf("  leaves : %zu blocks of four triangles, %.2f%% filled, %.2f MB\n", stats.leafBlockCount,
                100.0 * double(stats.usedBlockLanes) / double(4 * stats.leafBlockCount),
                double(stats.leafBlockCount * sizeof(obvh::TriangleBlock4)) / (1024.0 * 1024.0));
  std::fflush(stdout);
}

void Scene::commit() {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const Ref<Geometry>& g : geometries_)
    if (g && !g->committed()) fail(RTC_ERROR_INVALID_OPERATION, "geometry not committed");
  if (progress_ && !progress_(progressUserPtr_, 0.0)) fail(RTC_ERROR_CANCELLED, "commit cancelled by the progress monitor");
  if (needsRebuild()) rebuild();
  modified_ = false;
  if (builtForDirectRays_ && !(flags_ & RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION)) directEntry_ = &builtEntry_;
  if (progress_ && !progress_(progressUserPtr_, 1.0)) {
    markModified();
    fail(RTC_ERROR_CANCELLED, "commit cancelled by the progress monitor");
  }
}

namespace {

RTCBounds embreeBounds(const Box3f& b) {
  RTCBounds out{};
  out.lower_x = b.lower.x;
  out.lower_y = b.lower.y;
  out.lower_z = b.lower.z;
  out.upper_x = b.upper.x;
  out.upper_y = b.upper.y;
  out.upper_z = b.upper.z;
  return out;
}

}  // namespace

RTCBounds Scene::bounds() const { return embreeBounds(accel_.bounds()); }

RTCLinearBounds Scene::linearBounds() const {
  const auto [start, end] = accel_.linearBounds();
  return {embreeBounds(start), embreeBounds(end)};
}

}  // namespace obvh::api
