// `obvh_bench ladder`: what a build quality buys in trace speed, measured fairly. Each library
// builds the scene at two qualities; then, round after round, every (library, quality) traces the
// same rays once in rotating order, so that drifts of the machine (other load, clock) fall on all
// four alike. Prints per workload the median Mrays/s and the median, lowest and highest of the
// per-round ratios of the two qualities. Or, with --obvh-configs, the same for two obvh device
// configurations (e.g. two collapse methods), with Embree beside them for reference.
#pragma once

namespace obvh::tools {

// argv[0] is "ladder". Returns the process exit status.
int runLadderReport(int argc, char** argv);

}  // namespace obvh::tools
