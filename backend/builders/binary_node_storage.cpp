#include "builders/binary_node_storage.h"

#include "memory/huge_pages.h"

namespace obvh {

BinaryNodeStorage::BinaryNodeStorage(size_t primitives) {
  const size_t bytes = (primitives == 0 ? 1 : 2 * primitives - 1) * sizeof(Bvh2Node);
  bytes_.reset(new unsigned char[bytes]);
  adviseHugePages(bytes_.get(), bytes);
}

void BinaryNodeStorage::copyOut(std::vector<Bvh2Node>& nodes) const {
  const uint32_t count = claimed_.load();
  const Bvh2Node* made = std::launder(reinterpret_cast<const Bvh2Node*>(bytes_.get()));
  nodes.clear();
  reserveWithHugePages(nodes, count);
  nodes.assign(made, made + count);
}

}  // namespace obvh
