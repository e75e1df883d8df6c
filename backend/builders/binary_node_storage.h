// The nodes of a binary tree while a parallel builder makes them, by index: room for the most
// nodes n primitives can take (2n - 1), left unwritten until each node is made, then copied out
// into BinaryBvh::nodes. The SAH builders' leaves of up to 28 triangles use a small part of that
// room; value-initialized whole (the node vector's resize to 2n - 1), it had the kernel fault in
// and clear every page of it first (perf, a dragon build: 3.4% of the samples, and the build ran
// 1.08x as fast without).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <type_traits>
#include <vector>

#include "bvh/binary_bvh.h"

namespace obvh {

class BinaryNodeStorage {
  static_assert(std::is_trivially_copyable_v<Bvh2Node> && std::is_trivially_destructible_v<Bvh2Node>,
                "nodes are copied out of the storage and never destroyed in it");

 public:
  // Room for the nodes of a tree over `primitives` leaves at most.
  explicit BinaryNodeStorage(size_t primitives);

  // Node `index`, made (with Bvh2Node's defaults) for the builder to fill in. Each index is made
  // once, by one thread.
  Bvh2Node& make(uint32_t index) { return *::new (bytes_.get() + size_t(index) * sizeof(Bvh2Node)) Bvh2Node; }

  // Nodes [0, count), every one of them made, into nodes (replacing its contents).
  void copyOut(uint32_t count, std::vector<Bvh2Node>& nodes) const;

 private:
  std::unique_ptr<unsigned char[]> bytes_;  // new[] of bytes: not written, so no page touched
};

}  // namespace obvh
