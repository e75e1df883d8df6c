// `obvh_bench probe`: one of the ladder's workloads (ladder_workloads.h) traced by one library, one
// thread, a given number of times, for profilers. The traces run inside traceProbeRepeats, so that
// callgrind can count only them (--toggle-collect); perf record needs nothing.
#pragma once

namespace obvh::tools {

// argv[0] is "probe". Returns the process exit status.
int runProbeReport(int argc, char** argv);

}  // namespace obvh::tools
