// Floats compared by their bits: the kernels promise the very floats of their references, and
// operator== would let +0 pass for -0.
#pragma once

#include <cstring>

namespace obvh::test {

inline bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace obvh::test
