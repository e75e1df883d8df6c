// Per-thread traversal counts (obvh extension): QueryDispatch hands the thread's counters to the
// backend when counting is enabled, so the normal query path stays uncounted.
#include <obvh/traversal_statistics.h>

#include "traversal_statistics_state.h"

#include <atomic>

namespace obvh::api {

namespace {
thread_local bool counting = false;
thread_local TraversalCounters counters;
// Threads counting now. Every query asks for its thread's counters; reading this first spares the
// thread-local lookup (a call into the dynamic loader from a shared library) while nobody counts.
std::atomic<int> countingThreads{0};
}  // namespace

TraversalCounters* threadTraversalCounters() {
  if (countingThreads.load(std::memory_order_relaxed) == 0) return nullptr;
  return counting ? &counters : nullptr;
}

}  // namespace obvh::api

extern "C" __attribute__((visibility("default"))) void obvhEnableTraversalStatistics(int enable) {
  const bool counting = enable != 0;
  if (counting != obvh::api::counting) obvh::api::countingThreads.fetch_add(counting ? 1 : -1);
  obvh::api::counting = counting;
  obvh::api::counters = {};
}

extern "C" __attribute__((visibility("default"))) void obvhTakeTraversalStatistics(ObvhTraversalStatistics* statistics) {
  if (!statistics) return;
  statistics->boundingVolumeTests = obvh::api::counters.volumeTests();
  statistics->leafVisits = obvh::api::counters.leafVisits;
  obvh::api::counters = {};
}
