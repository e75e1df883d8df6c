#include "bvh/frame_clustering.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>
#include <random>

namespace obvh {
namespace {

double squaredDistance(const Features& a, const Features& b) {
  double d = 0.0;
  for (int j = 0; j < kFeatureDims; ++j) d += (a[size_t(j)] - b[size_t(j)]) * (a[size_t(j)] - b[size_t(j)]);
  return d;
}

}  // namespace

Features leafClusterFeatures(const Obb& b, float sceneSize) {
  Features features{};
  int order[3] = {0, 1, 2};
  std::sort(order, order + 3, [&](int a, int c) { return b.upper[a] - b.lower[a] > b.upper[c] - b.lower[c]; });
  int f = 0;
  for (int which = 0; which < 2; ++which) {
    const Vec3f a = b.axis[order[which]];
    for (int r = 0; r < 3; ++r)
      for (int c = r; c < 3; ++c) features[size_t(f++)] = double(a[r]) * a[c];
  }
  const Vec3f centre = (b.lower + b.upper) * 0.5f;  // in box coordinates; back to world:
  const Vec3f world = b.axis[0] * centre.x + b.axis[1] * centre.y + b.axis[2] * centre.z;
  for (int c = 0; c < 3; ++c) features[size_t(f++)] = 0.5 * world[c] / sceneSize;
  return features;
}

Features orientationFeatures(const Obb& b) {
  Features features{};
  int f = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j)
      for (int k = j; k < 3; ++k)
        for (int l = k; l < 3; ++l) {
          double sum = 0.0;
          for (const Vec3f& a : b.axis) sum += double(a[i]) * a[j] * a[k] * a[l];
          features[size_t(f++)] = sum;
        }
  return features;
}


std::vector<int> kMeans(const std::vector<Features>& features, int k, const Features* anchor) {
  const size_t n = features.size();
  k = int(std::min<size_t>(size_t(k), n));
  std::mt19937 rng(12345);
  std::vector<Features> centres;
  if (anchor) {
    centres.push_back(*anchor);
    std::vector<double> nearest(n);
    for (size_t i = 0; i < n; ++i) nearest[i] = squaredDistance(features[i], *anchor);
    for (int c = 0; c < k; ++c) {
      const size_t farthest = size_t(std::max_element(nearest.begin(), nearest.end()) - nearest.begin());
      centres.push_back(features[farthest]);
      for (size_t i = 0; i < n; ++i) nearest[i] = std::min(nearest[i], squaredDistance(features[i], centres.back()));
    }
  } else {
    for (int c = 0; c < k; ++c) centres.push_back(features[(size_t(c) * n) / size_t(k)]);
  }
  k = int(centres.size());
  const int firstMoving = anchor ? 1 : 0;
  std::vector<int> assignment(n, 0);
  for (int iteration = 0; iteration < 12; ++iteration) {
    tbb::parallel_for(size_t(0), n, [&](size_t i) {
      double best = std::numeric_limits<double>::infinity();
      for (int c = 0; c < k; ++c) {
        const double d = squaredDistance(features[i], centres[size_t(c)]);
        if (d < best) best = d, assignment[i] = c;
      }
    });
    std::vector<std::array<double, kFeatureDims>> sums(static_cast<size_t>(k));
    std::vector<size_t> counts(static_cast<size_t>(k), 0);
    for (auto& s : sums) s.fill(0.0);
    for (size_t i = 0; i < n; ++i) {
      ++counts[size_t(assignment[i])];
      for (int j = 0; j < kFeatureDims; ++j) sums[size_t(assignment[i])][size_t(j)] += features[i][size_t(j)];
    }
    for (int c = firstMoving; c < k; ++c) {
      if (counts[size_t(c)] == 0) {
        centres[size_t(c)] = features[rng() % n];  // re-seed an empty cluster
        continue;
      }
      for (int j = 0; j < kFeatureDims; ++j) centres[size_t(c)][size_t(j)] = sums[size_t(c)][size_t(j)] / double(counts[size_t(c)]);
    }
  }
  return assignment;
}

void representativeFrames(const std::vector<Obb>& boxes, const std::vector<Features>& features,
                          const std::vector<int>& assignment, int k, Representative rule, std::vector<Frame>& frames,
                          std::vector<int>& frameOfCluster) {
  std::vector<std::array<double, kFeatureDims>> means(static_cast<size_t>(k));
  std::vector<size_t> counts(size_t(k), 0);
  for (auto& m : means) m.fill(0.0);
  for (size_t j = 0; j < boxes.size(); ++j) {
    ++counts[size_t(assignment[j])];
    for (int d = 0; d < kFeatureDims; ++d) means[size_t(assignment[j])][size_t(d)] += features[j][size_t(d)];
  }
  auto distanceToMean = [&](size_t j) {
    const size_t c = size_t(assignment[j]);
    double sum = 0.0;
    for (int d = 0; d < kFeatureDims; ++d) {
      const double e = features[j][size_t(d)] - means[c][size_t(d)] / double(counts[c]);
      sum += e * e;
    }
    return sum;
  };
  std::vector<int> representative(size_t(k), -1);
  for (size_t j = 0; j < boxes.size(); ++j) {
    int& r = representative[size_t(assignment[j])];
    const bool better = rule == Representative::NearestMean ? r < 0 || distanceToMean(j) < distanceToMean(size_t(r))
                                    : r < 0 || boxes[j].halfArea() > boxes[size_t(r)].halfArea();
    if (better) r = int(j);
  }
  frameOfCluster.assign(size_t(k), -1);
  for (size_t c = 0; c < representative.size(); ++c)
    if (representative[c] >= 0) {
      frameOfCluster[c] = int(frames.size());
      const Obb& b = boxes[size_t(representative[c])];
      frames.push_back({{b.axis[0], b.axis[1], b.axis[2]}});
    }
}

}  // namespace obvh
