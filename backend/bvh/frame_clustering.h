// K-means over box frames, for the oriented layouts' shared frames (oriented_layout.cpp): leaf
// clusters (obb_clusters), grouped by orientation and position, and the frame palette
// (obb_palette), grouped by orientation alone.
#pragma once

#include <array>
#include <vector>

#include "bvh/oriented_bvh.h"
#include "obb/obb.h"

namespace obvh {

constexpr int kFeatureDims = 15;

// In double: products of tiny axis components are denormal in float, and the threads' flush-to-zero
// modes may differ (the main thread's is the application's), which made the clustering depend on
// which thread assigned which node.
using Features = std::array<double, kFeatureDims>;

// Leaf clusters' features: the sign-free outer products of the longest two axes (orientation) and
// the box centre scaled by the scene size, so nearby leaves of one direction group together.
Features leafClusterFeatures(const Obb& b, float sceneSize);

// A frame's orientation alone, blind to the order and signs of its axes (a box is the same box
// with its axes permuted or flipped): the fifteen distinct entries of the sum over the axes of
// a (x) a (x) a (x) a, which is equal for two frames exactly when they span the same box directions.
Features orientationFeatures(const Obb& b);

// Lloyd's k-means, seeded deterministically: the cluster of each feature vector. Without `anchor`,
// the seeds are spread evenly over the given order. With one, cluster 0 is held at the anchor and
// the k others are seeded farthest first from it and from each other (few clusters must each find
// a direction of their own).
std::vector<int> kMeans(const std::vector<Features>& features, int k, const Features* anchor = nullptr);

// How a cluster's frame is chosen among its members'.
enum class Representative { LargestBox, NearestMean };

// Each cluster's frame: that of its member with the largest box (it covers the most area), or with
// the features nearest the cluster's mean. Empty clusters get none; frameOfCluster maps a cluster
// to its frame's index in `frames`.
void representativeFrames(const std::vector<Obb>& boxes, const std::vector<Features>& features,
                          const std::vector<int>& assignment, int k, Representative rule, std::vector<Frame>& frames,
                          std::vector<int>& frameOfCluster);

}  // namespace obvh
