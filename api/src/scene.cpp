#include "scene.h"

#include "api_error.h"

namespace obvh::api {

unsigned Scene::attach(Geometry* geometry) {
  std::lock_guard<std::mutex> lock(mutex_);
  unsigned id = 0;
  while (id < geometries_.size() && geometries_[id]) ++id;  // lowest free ID, as Embree hands them out
  if (id == geometries_.size()) geometries_.emplace_back();
  geometries_[id] = Ref<Geometry>(geometry);
  modified_ = true;
  return id;
}

void Scene::attachById(Geometry* geometry, unsigned geomID) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (geomID == RTC_INVALID_GEOMETRY_ID) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid argument");
  if (geomID < geometries_.size() && geometries_[geomID])
    fail(RTC_ERROR_INVALID_OPERATION, "invalid geometry ID provided");
  if (geomID >= geometries_.size()) geometries_.resize(size_t(geomID) + 1);
  geometries_[geomID] = Ref<Geometry>(geometry);
  modified_ = true;
}

void Scene::detach(unsigned geomID) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (geomID >= geometries_.size()) fail(RTC_ERROR_INVALID_OPERATION, "invalid geometry ID");
  if (!geometries_[geomID]) fail(RTC_ERROR_INVALID_OPERATION, "invalid geometry");
  geometries_[geomID] = Ref<Geometry>();
  modified_ = true;
}

Geometry* Scene::geometry(unsigned geomID) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (geomID >= geometries_.size()) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid geometry ID");
  return geometries_[geomID].get();
}

void Scene::setFlags(RTCSceneFlags flags) {
  flags_ = flags;
  modified_ = true;
}

void Scene::setBuildQuality(RTCBuildQuality quality) {
  // REFIT is a per-geometry quality; scenes accept only the three build levels.
  if (quality != RTC_BUILD_QUALITY_LOW && quality != RTC_BUILD_QUALITY_MEDIUM && quality != RTC_BUILD_QUALITY_HIGH)
    fail(RTC_ERROR_UNKNOWN, "invalid build quality");
  quality_ = quality;
  modified_ = true;
}

void Scene::setProgressMonitor(RTCProgressMonitorFunction fn, void* userPtr) {
  std::lock_guard<std::mutex> lock(mutex_);
  progress_ = fn;
  progressUserPtr_ = userPtr;
}

bool Scene::needsRebuild() const {
  if (modified_ || builtModificationCounters_.size() != geometries_.size()) return true;
  for (size_t id = 0; id < geometries_.size(); ++id)
    if (geometries_[id] && geometries_[id]->modificationCounter() != builtModificationCounters_[id]) return true;
  return false;
}

void Scene::rebuild() {
  std::vector<MeshDesc> meshes;
  builtModificationCounters_.assign(geometries_.size(), 0);
  for (size_t id = 0; id < geometries_.size(); ++id) {
    Geometry* g = geometries_[id].get();
    if (!g) continue;
    builtModificationCounters_[id] = g->modificationCounter();
    const BufferView& index = g->indexBuffer();
    const BufferView& vertex = g->vertexBuffer();
    if (!g->enabled() || !index.bound() || !vertex.bound() || !index.data() || !vertex.data()) continue;
    MeshDesc mesh;
    mesh.vertices = vertex.data();
    mesh.vertexStride = vertex.byteStride;
    mesh.vertexCount = vertex.itemCount;
    mesh.indices = index.data();
    mesh.indexStride = index.byteStride;
    mesh.primCount = index.itemCount;
    mesh.quads = g->isQuadMesh();
    mesh.geomID = uint32_t(id);
    mesh.mask = g->mask();
    meshes.push_back(mesh);
  }
  BuildOptions options;
  options.binCount = device_->config().buildBins;
  options.maxLeafSize = device_->config().maxLeafSize;
  device_->execute([&] { accel_.build(meshes, uint32_t(geometries_.size()), options); });

  const size_t memory = accel_.stats().memoryBytes;
  device_->reportMemory(ssize_t(memory) - ssize_t(reportedMemory_), true);
  reportedMemory_ = memory;
}

void Scene::commit() {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const Ref<Geometry>& g : geometries_)
    if (g && !g->committed()) fail(RTC_ERROR_INVALID_OPERATION, "geometry not committed");
  if (progress_ && !progress_(progressUserPtr_, 0.0)) fail(RTC_ERROR_CANCELLED, "commit cancelled by the progress monitor");
  if (needsRebuild()) rebuild();
  modified_ = false;
  if (progress_ && !progress_(progressUserPtr_, 1.0)) {
    modified_ = true;
    fail(RTC_ERROR_CANCELLED, "commit cancelled by the progress monitor");
  }
}

RTCBounds Scene::bounds() const {
  const Box3f& b = accel_.bounds();
  RTCBounds out{};
  out.lower_x = b.lower.x;
  out.lower_y = b.lower.y;
  out.lower_z = b.lower.z;
  out.upper_x = b.upper.x;
  out.upper_y = b.upper.y;
  out.upper_z = b.upper.z;
  return out;
}

}  // namespace obvh::api
