// The calling thread's traversal counters while obvhEnableTraversalStatistics is on, else null.
#pragma once

#include "traversal/traversal_counters.h"

namespace obvh::api {

TraversalCounters* threadTraversalCounters();

}  // namespace obvh::api
