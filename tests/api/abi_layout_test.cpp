// obvh's header must be ABI-identical to Debian's Embree 3.13.5 header: every struct size, member
// offset, alignment, enum value, constant, function signature and inline helper result.
#include <gtest/gtest.h>

#include <map>

#include "abi_fact.h"

namespace obvh::test {
namespace {

TEST(AbiLayout, ProbesSeeTheIntendedHeaders) {
  EXPECT_FALSE(probeDebianEmbreeHeader().isObvhHeader);
  EXPECT_TRUE(probeObvhHeader().isObvhHeader);
}

TEST(AbiLayout, EveryFactMatchesDebianEmbree) {
  const AbiProbe reference = probeDebianEmbreeHeader();
  const AbiProbe candidate = probeObvhHeader();
  ASSERT_EQ(reference.facts.size(), candidate.facts.size());
  ASSERT_GT(reference.facts.size(), 700u);
  size_t differences = 0;
  for (size_t i = 0; i < reference.facts.size(); ++i) {
    ASSERT_EQ(reference.facts[i].name, candidate.facts[i].name);
    if (reference.facts[i].value != candidate.facts[i].value) {
      ++differences;
      ADD_FAILURE() << reference.facts[i].name << ": Embree " << reference.facts[i].value << ", obvh "
                    << candidate.facts[i].value;
    }
  }
  EXPECT_EQ(differences, 0u);
}

}  // namespace
}  // namespace obvh::test
