// The calling thread's traversal counters while obvhEnableTraversalStatistics is on, else null.
#pragma once

#include <atomic>

#include "traversal/traversal_counters.h"

namespace obvh::api {

TraversalCounters* threadTraversalCounters();

// Threads counting now. Every query asks whether anyone counts; reading this first spares the
// thread-local lookup (a call into the dynamic loader from a shared library) while nobody does.
extern std::atomic<int> countingThreads;
inline bool anyThreadCounting() { return countingThreads.load(std::memory_order_relaxed) != 0; }

}  // namespace obvh::api
