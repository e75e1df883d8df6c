// `obvh_bench accuracy`: what each level of accuracy costs in time. Per mode (obvh watertight,
// obvh with the ROBUST flag, obvh fast, Embree default and ROBUST): Mrays/s on real meshes and the
// accuracy study's error rates; printed, and written as CSV and a gnuplot PNG.
#pragma once

namespace obvh::tools {

// argv[0] is "accuracy". Returns the process exit status.
int runAccuracyReport(int argc, char** argv);

}  // namespace obvh::tools
