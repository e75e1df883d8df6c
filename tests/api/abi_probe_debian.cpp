// ABI probe compiled against Debian's <embree3/rtcore.h> (no obvh include path on this unit).
#define OBVH_PROBE_FUNCTION probeDebianEmbreeHeader
#include "abi_probe.inc"
