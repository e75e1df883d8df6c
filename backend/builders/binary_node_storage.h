// The nodes of a binary tree while a parallel builder makes them, by index: room for the most
// nodes n primitives can take (2n - 1), left unwritten until each node is made, then copied out
// into BinaryBvh::nodes. The SAH builders' leaves of up to 28 triangles use a small part of that
// room; value-initialized whole (the node vector's resize to 2n - 1), it had the kernel fault in
// and clear every page of it first (perf, a dragon build: 3.4% of the samples, and the build ran
// 1.08x as fast without).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <type_traits>
#include <vector>

#include "builders/prim_ref.h"
#include "bvh/binary_bvh.h"
#include "memory/huge_pages.h"

namespace obvh {

class BinaryNodeStorage {
  static_assert(std::is_trivially_copyable_v<Bvh2Node> && std::is_trivially_destructible_v<Bvh2Node>,
                "nodes are copied out of the storage and never destroyed in it");

 public:
  // Room for the nodes of a tree over `primitives` leaves at most; index 0, the root, is claimed.
  explicit BinaryNodeStorage(size_t primitives);

  // The first of two consecutive indices for an interior node's children (left, then right),
  // claimed by any thread.
  uint32_t claimPair() { return claimed_.fetch_add(2); }

  // Node `index` (claimed), made (with Bvh2Node's defaults) for the builder to fill in. Each index
  // is made once, by one thread.
  Bvh2Node& make(uint32_t index) { return *::new (bytes_.get() + size_t(index) * sizeof(Bvh2Node)) Bvh2Node; }

  // The claimed nodes, every one of them made, into nodes (replacing its contents).
  void copyOut(std::vector<Bvh2Node>& nodes) const;

 private:
  std::unique_ptr<unsigned char[]> bytes_;  // new[] of bytes: not written, so no page touched
  std::atomic<uint32_t> claimed_{1};
};

// The frame of a recursive builder's run: buildFromRoot(nodes) makes every node of the tree from the
// root (index 0) down in a fresh storage for refs.size() primitives; out then takes the nodes, and
// the references' order as the builder left it becomes out.primIndices (leaves index ranges of it).
template <typename BuildFromRoot>
void buildIntoBinaryBvh(const PrimRefs& refs, BinaryBvh& out, BuildFromRoot&& buildFromRoot) {
  const size_t n = refs.size();
  BinaryNodeStorage nodes(n);
  buildFromRoot(nodes);
  nodes.copyOut(out.nodes);
  reserveWithHugePages(out.primIndices, n);
  out.primIndices.resize(n);
  for (size_t i = 0; i < n; ++i) out.primIndices[i] = refs[i].index;
}

}  // namespace obvh
