// Oriented bounding boxes: three orthonormal axes and the interval the box covers along each.
#pragma once

#include <cstddef>

#include "math/vec3.h"

namespace obvh {

struct Obb {
  Vec3f axis[3] = {{1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, {0.f, 0.f, 1.f}};
  Vec3f lower{0.f, 0.f, 0.f};  // lower[k] = min over the contents of dot(axis[k], p)
  Vec3f upper{-1.f, -1.f, -1.f};

  bool empty() const { return lower.x > upper.x || lower.y > upper.y || lower.z > upper.z; }
  // Half the surface area, like Box3f::halfArea, so SAH costs of both kinds compare directly.
  float halfArea() const {
    if (empty()) return 0.f;
    const Vec3f d = upper - lower;
    return d.x * d.y + d.y * d.z + d.z * d.x;
  }
  float volume() const { return empty() ? 0.f : (upper.x - lower.x) * (upper.y - lower.y) * (upper.z - lower.z); }
  // The box's coordinates of a world point: its projections on the three axes.
  Vec3f toBoxFrame(Vec3f p) const { return {dot(axis[0], p), dot(axis[1], p), dot(axis[2], p)}; }
  // True when p lies in the box, allowing `slack` along each axis.
  bool contains(Vec3f p, float slack = 0.f) const;
};

// The axis-aligned box of the points, as an Obb with the world axes.
Obb fitAxisAligned(const Vec3f* points, size_t count);

// DiTO-14 (Larsson and Kallberg 2011): extremal points along 7 fixed directions, a large base
// triangle and the two tetrahedra it spans with the points farthest above and below it; every
// triangle edge with the triangle's normal proposes a frame, the one with the smallest surface
// area over the extremal points wins, and the box is refitted over all points. Falls back to the
// axis-aligned box when that is smaller.
Obb fitDito14(const Vec3f* points, size_t count);

// Principal axes of the points' covariance (for comparison with DiTO-14).
Obb fitPca(const Vec3f* points, size_t count);

// How the oriented layouts fit a box to a node's triangles (device config obb_fit).
enum class ObbFit { Dito14, Pca };
Obb fitObb(ObbFit method, const Vec3f* points, size_t count);

// Box with the given axes enclosing the points, rounded outwards so that every point is inside.
Obb fitWithAxes(const Vec3f axes[3], const Vec3f* points, size_t count);

}  // namespace obvh
