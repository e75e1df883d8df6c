#include "traversal/wide_traversal.h"

#include "simd/cpu_features.h"

namespace obvh {

KernelIsa bestKernelIsa(int width) {
  const bool simd = width == 8 ? simd::cpuHasAvx2() : simd::cpuHasSse42();
  return simd ? KernelIsa::Simd : KernelIsa::Scalar;
}

}  // namespace obvh
