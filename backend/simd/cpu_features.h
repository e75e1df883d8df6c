// Run-time detection of the instruction sets the kernels can use.
#pragma once

namespace obvh::simd {

bool cpuHasSse42();
bool cpuHasAvx2();

}  // namespace obvh::simd
