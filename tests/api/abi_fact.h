// One named ABI fact (a size, offset, alignment, enum value or signature) as text.
#pragma once

#include <string>
#include <vector>

namespace obvh::test {

struct AbiFact {
  std::string name;
  std::string value;
};

struct AbiProbe {
  bool isObvhHeader = false;
  std::vector<AbiFact> facts;
};

AbiProbe probeDebianEmbreeHeader();
AbiProbe probeObvhHeader();

}  // namespace obvh::test
