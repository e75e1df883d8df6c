// The tests use the procedural meshes of tools/common under their own namespace.
#pragma once

#include "procedural_meshes.h"

namespace obvh::test {
using namespace obvh::tools;
}  // namespace obvh::test
