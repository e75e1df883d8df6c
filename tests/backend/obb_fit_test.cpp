// OBB fitting: DiTO-14 finds the minimal box of rotated boxes, and for any point set every point
// is inside, the box never exceeds the axis-aligned one and nothing is NaN. PCA is checked too, and
// shown where it loses to DiTO-14.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "obb/obb.h"

namespace obvh {
namespace {

// A random rotation from a random unit quaternion.
void randomRotation(std::mt19937& rng, Vec3f axes[3]) {
  std::normal_distribution<double> normal;
  double q[4], n = 0;
  for (double& c : q) c = normal(rng), n += c * c;
  n = std::sqrt(n);
  const double w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
  axes[0] = {float(1 - 2 * (y * y + z * z)), float(2 * (x * y + w * z)), float(2 * (x * z - w * y))};
  axes[1] = {float(2 * (x * y - w * z)), float(1 - 2 * (x * x + z * z)), float(2 * (y * z + w * x))};
  axes[2] = {float(2 * (x * z + w * y)), float(2 * (y * z - w * x)), float(1 - 2 * (x * x + y * y))};
}

// The eight corners of the box with these axes, centre and half extents.
std::vector<Vec3f> boxCorners(const Vec3f axes[3], const Vec3f& centre, const Vec3f& extent) {
  std::vector<Vec3f> corners;
  for (int corner = 0; corner < 8; ++corner) {
    Vec3f p = centre;
    for (int k = 0; k < 3; ++k) p = p + axes[k] * (((corner >> k) & 1) ? extent[k] : -extent[k]);
    corners.push_back(p);
  }
  return corners;
}

// Every point inside the box, judged in double precision (the box is rounded outwards).
void expectContainsAll(const Obb& box, const std::vector<Vec3f>& points) {
  for (const Vec3f& p : points)
    for (int k = 0; k < 3; ++k) {
      const double d = double(box.axis[k].x) * p.x + double(box.axis[k].y) * p.y + double(box.axis[k].z) * p.z;
      ASSERT_GE(d, double(box.lower[k])) << "point outside along axis " << k;
      ASSERT_LE(d, double(box.upper[k])) << "point outside along axis " << k;
    }
  for (int k = 0; k < 3; ++k) {
    EXPECT_TRUE(std::isfinite(box.axis[k].x) && std::isfinite(box.axis[k].y) && std::isfinite(box.axis[k].z));
    EXPECT_NEAR(dot(box.axis[k], box.axis[k]), 1.f, 1e-5f);
    EXPECT_NEAR(dot(box.axis[k], box.axis[(k + 1) % 3]), 0.f, 1e-5f);
  }
}

TEST(ObbFit, Dito14FindsTheMinimalBoxOfRotatedBoxes) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  int found = 0;
  const int trials = 500;
  for (int trial = 0; trial < trials; ++trial) {
    Vec3f axes[3];
    randomRotation(rng, axes);
    const Vec3f extent{0.1f + 10.f * unit(rng), 0.1f + 10.f * unit(rng), 0.1f + 10.f * unit(rng)};
    const Vec3f centre{100.f * unit(rng), -50.f * unit(rng), 20.f * unit(rng)};
    std::vector<Vec3f> points = boxCorners(axes, centre, extent);  // then points on and inside the box
    for (int i = 0; i < 200; ++i) {
      Vec3f p = centre;
      for (int k = 0; k < 3; ++k) p = p + axes[k] * (extent[k] * (2.f * unit(rng) - 1.f));
      points.push_back(p);
    }
    const Obb box = fitDito14(points.data(), points.size());
    expectContainsAll(box, points);
    const float exact = 4.f * (extent.x * extent.y + extent.y * extent.z + extent.z * extent.x);
    EXPECT_GE(box.halfArea(), exact * (1.f - 1e-4f));
    if (box.halfArea() <= exact * (1.f + 1e-3f)) ++found;
  }
  EXPECT_EQ(found, trials) << "DiTO-14 missed the minimal box in " << trials - found << " of " << trials << " rotations";
}

// Why DiTO-14 and not PCA: the principal axes follow where the points are dense, not the hull. A
// slanted line's box whose vertices crowd along its diagonal (a fan of long thin triangles) gets a
// PCA frame along that diagonal and a box far larger than the line's, while DiTO-14, which looks
// only at extremal points, still finds the line's own box.
TEST(ObbFit, Dito14FindsTheBoxWherePcaFollowsCrowdedPoints) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  int pcaWorse = 0;
  const int trials = 100;
  for (int trial = 0; trial < trials; ++trial) {
    Vec3f axes[3];
    randomRotation(rng, axes);
    const Vec3f extent{5.f + 5.f * unit(rng), 0.5f + unit(rng), 0.05f + 0.1f * unit(rng)};
    std::vector<Vec3f> points = boxCorners(axes, Vec3f{0.f, 0.f, 0.f}, extent);
    for (int i = 0; i < 400; ++i) {  // along the diagonal from corner 0 to corner 3 (the line's top face)
      const float s = 2.f * unit(rng) - 1.f;
      points.push_back(axes[0] * (s * extent.x) + axes[1] * (s * extent.y) + axes[2] * (-extent.z));
    }
    const float exact = 4.f * (extent.x * extent.y + extent.y * extent.z + extent.z * extent.x);
    const Obb dito = fitDito14(points.data(), points.size());
    const Obb pca = fitPca(points.data(), points.size());
    expectContainsAll(dito, points);
    expectContainsAll(pca, points);
    EXPECT_LE(dito.halfArea(), exact * (1.f + 1e-3f)) << "trial " << trial;
    if (pca.halfArea() > 1.1f * exact) ++pcaWorse;
  }
  EXPECT_GE(pcaWorse, trials * 9 / 10) << "PCA found the line's box in " << trials - pcaWorse << " of " << trials;
}

TEST(ObbFit, RandomPointSetsAreEnclosedAndNeverWorseThanTheAxisAlignedBox) {
  std::mt19937 rng(2);
  std::normal_distribution<float> normal;
  for (int trial = 0; trial < 300; ++trial) {
    Vec3f axes[3];
    randomRotation(rng, axes);
    const Vec3f scale{std::exp(2.f * normal(rng)), std::exp(2.f * normal(rng)), std::exp(2.f * normal(rng))};
    std::vector<Vec3f> points;
    const int count = 3 + trial % 200;
    for (int i = 0; i < count; ++i)
      points.push_back(axes[0] * (scale.x * normal(rng)) + axes[1] * (scale.y * normal(rng)) + axes[2] * (scale.z * normal(rng)) +
                       Vec3f{1e3f, -2e3f, 5e2f});
    const Obb dito = fitDito14(points.data(), points.size());
    const Obb pca = fitPca(points.data(), points.size());
    const Obb aligned = fitAxisAligned(points.data(), points.size());
    expectContainsAll(dito, points);
    expectContainsAll(pca, points);
    expectContainsAll(aligned, points);
    EXPECT_LE(dito.halfArea(), aligned.halfArea());
  }
}

TEST(ObbFit, DegenerateInputs) {
  const std::vector<Vec3f> one = {{1.f, 2.f, 3.f}};
  const std::vector<Vec3f> collinear = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}};
  const std::vector<Vec3f> coplanar = {{0, 0, 5}, {1, 0, 5}, {0, 1, 5}, {1, 1, 5}, {0.5f, 0.2f, 5}};
  const std::vector<Vec3f> repeated(20, Vec3f{-4.f, 4.f, 1e6f});
  for (const auto* points : {&one, &collinear, &coplanar, &repeated}) {
    expectContainsAll(fitDito14(points->data(), points->size()), *points);
    expectContainsAll(fitPca(points->data(), points->size()), *points);
  }
  // A slanted flat set gets a box of zero thickness, not an axis-aligned slab.
  std::vector<Vec3f> diagonal;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 3; ++j) diagonal.push_back({float(i) + 0.1f * float(j), float(i) - 0.1f * float(j), float(j)});
  const Obb slanted = fitDito14(diagonal.data(), diagonal.size());
  EXPECT_LT(slanted.volume(), 1e-3f * fitAxisAligned(diagonal.data(), diagonal.size()).volume());
}

}  // namespace
}  // namespace obvh
