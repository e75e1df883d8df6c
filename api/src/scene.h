// RTCScene: attached geometries, commit (which builds the backend's acceleration structure), queries.
#pragma once

#include <embree3/rtcore.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <vector>

#include "api_error.h"
#include "device.h"
#include "geometry.h"
#include "ref_counted.h"
#include "scene/scene_accel.h"

namespace obvh::api {

class Scene : public RefCounted {
 public:
  explicit Scene(Device* device) : device_(device), rayMasks_(device->config().rayMasks) {}
  // Gives the memory it reported back to the device's memory monitor.
  ~Scene() override;

  Device* device() const { return device_.get(); }

  unsigned attach(Geometry* geometry);
  void attachById(Geometry* geometry, unsigned geomID);
  void detach(unsigned geomID);
  Geometry* geometry(unsigned geomID);

  // Raw bits (enum_bits.h): any value may be passed; flags() is handed back as given.
  void setFlags(int flags);
  int flags() const { return flags_; }
  void setBuildQuality(int quality);
  void setProgressMonitor(RTCProgressMonitorFunction fn, void* userPtr);

  void commit();
  RTCBounds bounds() const;
  RTCLinearBounds linearBounds() const;  // see SceneAccel::linearBounds

  // Throws INVALID_OPERATION when the scene changed since its last commit.
  void requireCommitted() const {
    if (modified_.load(std::memory_order_relaxed)) fail(RTC_ERROR_INVALID_OPERATION, "scene not committed");
  }
  const SceneAccel& accel() const { return accel_; }
  // The geometry a committed scene was built with (valid until the scene changes).
  Geometry* builtGeometry(unsigned geomID) const { return builtGeometries_[geomID].get(); }
  // Whether queries must call back into the API (filters or user geometry somewhere below).
  bool needsCallbacks() const { return needsCallbacks_; }
  // The kernels single rays and packets take past the general query path (query_dispatch.h), or
  // null when they may not: committed, one wide triangle tree, no callbacks. A scene that accepts
  // context filters (RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION) never does, whether or not a context
  // brings one. Set by commit and cleared by every change, where three conditions (and the
  // context's filter) were tested at every ray.
  const QueryEntry* directEntry() const { return directEntry_.load(std::memory_order_relaxed); }
  // The device's ray_mask setting, read at every direct ray (a copy here spares the load of the device).
  bool rayMasks() const { return rayMasks_; }
  uint64_t buildGeneration() const { return buildGeneration_; }

  static Scene* from(RTCScene handle) { return reinterpret_cast<Scene*>(handle); }
  RTCScene handle() { return reinterpret_cast<RTCScene>(this); }

 private:
  void printBuildStatistics(bool refitted, std::chrono::steady_clock::duration took) const;
  bool needsRebuild() const;
  void rebuild();
  bool wantsRefit() const;
  bool refitsLater() const;
  void markModified() {
    modified_ = true;
    directEntry_ = nullptr;
  }

  Ref<Device> device_;
  std::mutex mutex_;
  std::vector<Ref<Geometry>> geometries_;        // index is the geomID; empty slots are null
  std::vector<uint64_t> builtModificationCounters_;
  int flags_ = RTC_SCENE_FLAG_NONE;
  int quality_ = RTC_BUILD_QUALITY_MEDIUM;
  RTCProgressMonitorFunction progress_ = nullptr;
  void* progressUserPtr_ = nullptr;
  std::atomic<bool> modified_{true};
  SceneAccel accel_;
  std::vector<Ref<Geometry>> builtGeometries_;
  std::vector<uint64_t> builtChildGenerations_;  // instanced scenes' generations at the last build
  bool needsCallbacks_ = false;
  std::atomic<const QueryEntry*> directEntry_{nullptr};
  QueryEntry builtEntry_;  // what directEntry_ points to when set
  bool builtForDirectRays_ = false;  // the last build: one wide triangle tree, no callbacks
  const bool rayMasks_;
  uint64_t buildGeneration_ = 0;
  size_t reportedMemory_ = 0;
};

}  // namespace obvh::api
