// ABI probe compiled against obvh's api/include/embree3/rtcore.h.
#define OBVH_PROBE_FUNCTION probeObvhHeader
#include "abi_probe.inc"
