// How the wide collapses choose a wide node's children among a binary node's descendants, shared by
// the AABB layouts (wide_collapse.cpp) and the oriented ones (oriented_wide_collapse.cpp): greedily
// (open the widest child until the node is full), or by the dynamic programme of the SAH-optimal
// collapse (Ylitie, Karras and Laine, "Efficient Incoherent Ray Traversal on GPUs Through
// Compressed Wide BVHs", HPG 2017): bottom-up, per binary node and i = 1..N, the cheapest forest of
// at most i wide roots standing for the node's subtree, and the choices that give it; then,
// top-down, the roots a wide node gets.
//
// Tree access: isLeaf(node), leftChild(node) (the right child is the next index), area(node) ->
// float, and for the dynamic programme choice(node) -> const ForestChoice<N>&.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>

namespace obvh {

template <int N>
struct ForestChoice {
  int8_t split[N];  // [j - 1]: roots from the left child in the cheapest forest of exactly j
  int8_t roots[N];  // [i - 1]: how many roots the cheapest forest of at most i has
  bool leafChosen;  // the subtree is one leaf when it stands alone
};

// A binary leaf stays a leaf; every forest of it is that leaf, at `cost`.
template <int N>
void chooseLeaf(ForestChoice<N>& choice, float cost, float atMost[N]) {
  std::fill_n(choice.split, N, int8_t(0));
  std::fill_n(choice.roots, N, int8_t(1));
  choice.leafChosen = true;
  std::fill_n(atMost, N, cost);
}

// An interior node, from its children's forests: standing alone it is a wide node (nodeCost plus
// the cheapest forest of N roots from its children) or one leaf (asLeaf; infinity when it may not
// be one); forests of two or more roots come from the children.
template <int N>
void chooseInterior(const float left[N], const float right[N], float nodeCost, float asLeaf, ForestChoice<N>& choice,
                    float atMost[N]) {
  std::fill_n(choice.split, N, int8_t(0));
  std::fill_n(choice.roots, N, int8_t(1));
  float forest[N + 1];
  for (int j = 2; j <= N; ++j) {
    forest[j] = std::numeric_limits<float>::infinity();
    for (int k = 1; k < j; ++k) {
      const float c = left[k - 1] + right[j - k - 1];
      if (c < forest[j]) forest[j] = c, choice.split[j - 1] = int8_t(k);
    }
  }
  const float asNode = nodeCost + forest[N];
  choice.leafChosen = asLeaf <= asNode;
  atMost[0] = std::min(asLeaf, asNode);
  for (int i = 2; i <= N; ++i) {
    if (forest[i] < atMost[i - 2]) {
      atMost[i - 1] = forest[i], choice.roots[i - 1] = int8_t(i);
    } else {
      atMost[i - 1] = atMost[i - 2], choice.roots[i - 1] = choice.roots[i - 2];
    }
  }
}

template <int N, typename Tree>
void gatherForest(const Tree& tree, uint32_t node, int most, uint32_t* roots, int& count) {
  const ForestChoice<N>& c = tree.choice(node);
  const int j = c.roots[most - 1];
  if (j == 1 || tree.isLeaf(node)) {
    roots[count++] = node;
    return;
  }
  const int k = c.split[j - 1];
  gatherForest<N>(tree, tree.leftChild(node), k, roots, count);
  gatherForest<N>(tree, tree.leftChild(node) + 1, j - k, roots, count);
}

// The children of the wide node that `node` becomes, larger boxes first: the lane order decides
// between children entered at the same distance (rays starting inside several boxes) and is the
// any-hit visiting order. Insertion sort, stable: at most N entries and no allocation per node.
template <int N, typename Tree>
int wideChildrenOf(const Tree& tree, uint32_t node, uint32_t children[N]) {
  int count = 0;
  const uint32_t left = tree.leftChild(node);
  const int k = tree.choice(node).split[N - 1];
  gatherForest<N>(tree, left, k, children, count);
  gatherForest<N>(tree, left + 1, N - k, children, count);
  float area[N];
  for (int c = 0; c < count; ++c) {
    const uint32_t child = children[c];
    const float a = tree.area(child);
    int slot = c;
    for (; slot > 0 && area[slot - 1] < a; --slot) children[slot] = children[slot - 1], area[slot] = area[slot - 1];
    children[slot] = child, area[slot] = a;
  }
  return count;
}

// The children of interior binary node `node` as a wide node of the greedy collapse: starting from
// its two children, the interior child of largest area is opened (replaced by its two children)
// until the node is full or only leaves are left.
template <int N, typename Tree>
int greedyChildrenOf(const Tree& tree, uint32_t node, uint32_t children[N]) {
  children[0] = tree.leftChild(node), children[1] = tree.leftChild(node) + 1;
  int count = 2;
  while (count < N) {
    int widest = -1;
    float widestArea = -1.f;
    for (int c = 0; c < count; ++c) {
      if (!tree.isLeaf(children[c]) && tree.area(children[c]) > widestArea) {
        widestArea = tree.area(children[c]);
        widest = c;
      }
    }
    if (widest < 0) break;
    const uint32_t opened = children[widest];
    children[widest] = tree.leftChild(opened);
    children[count++] = tree.leftChild(opened) + 1;
  }
  return count;
}

}  // namespace obvh
