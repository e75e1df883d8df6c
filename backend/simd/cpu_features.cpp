#include "simd/cpu_features.h"

namespace obvh::simd {

bool cpuHasSse42() {
#if defined(__x86_64__) || defined(__i386__)
  static const bool has = __builtin_cpu_supports("sse4.2");
  return has;
#else
  return false;
#endif
}

bool cpuHasAvx2() {
#if defined(__x86_64__) || defined(__i386__)
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
#else
  return false;
#endif
}

}  // namespace obvh::simd
