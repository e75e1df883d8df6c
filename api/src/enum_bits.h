// Reads an enum argument's bits without loading it as the enum type. Programs pass arbitrary
// values (embree_verify passes 2000000 as a device property; misuse tests pass 77 as a geometry
// type) and Embree answers them with errors, but loading a value outside an enum's range is
// undefined behaviour in C++ (UBSan reports it). API entry points therefore work on the bits.
#pragma once

#include <cstring>

namespace obvh::api {

template <typename E>
int enumBits(const E& value) {
  static_assert(sizeof(E) == sizeof(int), "Embree's enums are int-sized");
  int bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

}  // namespace obvh::api
