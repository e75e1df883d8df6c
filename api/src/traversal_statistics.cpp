// Per-thread traversal counts (obvh extension): QueryDispatch hands the thread's counters to the
// backend when counting is enabled, so the normal query path stays uncounted.
#include <obvh/traversal_statistics.h>

#include "traversal_statistics_state.h"

#include <atomic>

namespace obvh::api {

std::atomic<int> countingThreads{0};

namespace {
thread_local bool counting = false;
thread_local TraversalCounters counters;
}  // namespace

TraversalCounters* threadTraversalCounters() {
  if (!anyThreadCounting()) return nullptr;
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
