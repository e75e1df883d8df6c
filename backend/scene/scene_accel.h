// A committed scene: a BVH over its still triangles (of triangle, quad and grid meshes), and a
// second BVH over its "objects" (instances of other scenes, user-geometry primitives, points and
// curve segments, triangles of moving meshes: scene_objects.cpp), queried one after the other.
#pragma once

#include <utility>
#include <vector>

#include "builders/build_options.h"
#include "bvh/binary_bvh.h"
#include "intersect/ray.h"
#include "intersect/triangle.h"
#include "scene/primitive_collection.h"
#include "scene/scene_desc.h"
#include "bvh/wide_bvh.h"
#include "bvh/oriented_bvh.h"
#include "bvh/oriented_wide_bvh.h"
#include "traversal/bvh2_traversal.h"
#include "traversal/wide_traversal.h"
#include "traversal/oriented_traversal.h"
#include "traversal/oriented_wide_traversal.h"
#include "traversal/traversal_counters.h"
#include "traversal/point_query_callbacks.h"
#include "traversal/query_callbacks.h"
#include "traversal/query_entry.h"

namespace obvh {

struct SceneStats {
  size_t primitiveCount = 0;
  size_t nodeCount = 0;
  size_t leafCount = 0;
  size_t memoryBytes = 0;
  size_t leafBlockCount = 0;  // wide layouts: four-triangle leaf blocks, and how many lanes hold a triangle
  size_t usedBlockLanes = 0;
};

class SceneAccel {
 public:
  void build(const SceneDesc& desc, const BuildOptions& options);
  // RTC_BUILD_QUALITY_REFIT: keeps the tree and recomputes its bounds from desc's new vertices.
  // Returns false (and changes nothing) unless the scene was built before with the same options,
  // from triangles and quads only, with the same primitives: then the caller builds instead.
  // Oriented layouts are never refitted (their frames would have to be fitted again).
  bool refit(const SceneDesc& desc, const BuildOptions& options);

  const Box3f& bounds() const { return bounds_; }
  // Boxes at the start and the end of the shutter [0, 1] whose linear blend at any time in between
  // holds everything the scene's rays can meet at that time (Embree's rtcGetSceneLinearBounds).
  std::pair<Box3f, Box3f> linearBounds() const;
  // The triangle layout traced (accel=hybrid may have settled on a wide AABB layout).
  AccelLayout layout() const { return layout_; }
  SceneStats stats() const;

  // counters (metrics only) count the volume tests of the triangle BVH; they are kept for the
  // binary and oriented layouts (accel=bvh2|obb|hybrid), not for the wide ones.
  bool intersect(Ray& ray, Hit& hit, const QueryState& state, TraversalCounters* counters = nullptr) const;
  bool occluded(const Ray& ray, const QueryState& state, TraversalCounters* counters = nullptr) const;
  // Whether the scene is one wide triangle tree (axis-aligned or oriented) and nothing else (no
  // instances, user geometry or shapes). Its single rays and packets may then skip intersect()'s
  // dispatch and take queryEntry()'s kernels, which test the wide triangle tree alone, as the two
  // functions below do (intersect() and occluded() use them for the axis-aligned layouts). They
  // count nothing.
  bool wideTrianglesOnly() const {
    return (layout_ == AccelLayout::Bvh8 || layout_ == AccelLayout::Bvh4 || orientedWide()) && objectBvh_.empty();
  }
  bool intersectWideTriangles(Ray& ray, Hit& hit, const QueryState& state) const {
    if (layout_ == AccelLayout::Bvh8) return !triangleView8_.empty() && intersectClosestWide(triangleView8_, ray, hit, state);
    if (layout_ == AccelLayout::Bvh4) return !triangleView4_.empty() && intersectClosestWide(triangleView4_, ray, hit, state);
    return intersectOrientedWideTriangles(ray, hit, state, nullptr);
  }
  bool occludedWideTriangles(const Ray& ray, const QueryState& state) const {
    if (layout_ == AccelLayout::Bvh8) return !triangleView8_.empty() && intersectAnyWide(triangleView8_, ray, state);
    if (layout_ == AccelLayout::Bvh4) return !triangleView4_.empty() && intersectAnyWide(triangleView4_, ray, state);
    return occludedOrientedWideTriangles(ray, state, nullptr);
  }
  // The queries of a wideTrianglesOnly() scene as a QueryEntry, chosen once (the layout and its
  // kernels): valid until the next build or refit.
  QueryEntry queryEntry() const;
  // Packets of up to kMaxPacketSize rays (lane i active when bit i of active is set): the same
  // answers as intersect/occluded per lane; the wide layouts trace the triangles as one packet.
  // Return the mask of lanes that hit / are occluded.
  uint32_t intersectPacket(Ray* rays, Hit* hits, uint32_t active, const QueryState& state) const;
  uint32_t occludedPacket(const Ray* rays, uint32_t active, const QueryState& state) const;
  // The triangle tree's SAH cost as Embree's verbose statistics compute it (bvh/tree_statistics.h);
  // the oriented layouts report their binary tree's.
  double statisticsSah() const;
  // Shape and SAH cost of the triangle BVH in the layout it is traced in (bvh4/bvh8: their binary
  // tree, which a build keeps only with BuildOptions::keepBinaryTree; std::logic_error otherwise).
  LayoutMetrics triangleLayoutMetrics() const;
  // Visits every primitive whose bounds overlap the sphere around point (world space when
  // instance is null); returns true when any callback reported a change.
  bool pointQuery(const Vec3f& point, PointQueryCallbacks& callbacks, const PointQueryInstance* instance = nullptr,
                  float radiusScale = 1.f) const;

 private:
  // The oriented layouts traced four- or eight-wide (obb_width=4|8), whose views may be empty.
  bool orientedWide() const {
    return (layout_ == AccelLayout::Obb || layout_ == AccelLayout::Hybrid) && options_.obbWidth > 2;
  }
  bool intersectOrientedWideTriangles(Ray& ray, Hit& hit, const QueryState& state, TraversalCounters* counters) const;
  bool occludedOrientedWideTriangles(const Ray& ray, const QueryState& state, TraversalCounters* counters) const;
  enum class ObjectKind : uint32_t { Instance, UserPrimitive, Shape, MotionTriangle };
  struct ObjectRef {
    ObjectKind kind;
    uint32_t index;   // into instances_ (Instance), the geomID (UserPrimitive), into shapes_ (Shape)
                      // or into motion_.triangles (MotionTriangle)
    uint32_t primID;  // UserPrimitive only
    Box3f bounds;     // world bounds, for point queries
  };
  struct Instance {
    const SceneAccel* child;
    Affine3d worldToLocal;
    uint32_t geomID;
    Affine3f localToWorld;
    float similarityScale;  // see PointQueryInstance
    float radiusToLocal;    // bound on how much worldToLocal stretches lengths
    InstanceMotion motion;  // when moving, the fields above hold at its time (placedAt)
  };
  // The instance placed at `time`: itself when it does not move, else built in `storage`; null when
  // it is not there then.
  static const Instance* placedAt(const Instance& instance, float time, Instance& storage);
  static Instance makeInstance(const SceneAccel* child, const Affine3f& localToWorld, uint32_t geomID);

  // A sphere, a flat curve segment (its two vertices), a round cubic curve (its Bezier control
  // points, whatever its basis) or a flat cubic curve (its control vertices in its own basis, cut
  // into ribbonQuads quads); v holds controlPointCount(kind) of them. A moving one keeps them
  // at every time step in shapeSteps_ (step s from firstStep + s * count) and they are blended per ray.
  struct ShapePrimitive {
    ShapeKind kind;
    uint32_t geomID, primID;
    int ribbonQuads;
    ShapeVertex v[4];
    uint32_t firstStep = 0, stepCount = 1;
    float timeStart = 0.f, timeEnd = 1.f;
  };
  // The primitive's control points where it is at `time`; false when it is not there then.
  bool shapeAt(const ShapePrimitive& shape, float time, ShapeVertex out[4]) const;

  // watertight: the ray's frame for moving triangles, made once per ray (it depends on org and dir).
  bool intersectObject(const ObjectRef& object, Ray& ray, Hit& hit, const QueryState& state,
                       WatertightRayOnDemand& watertight) const;
  bool intersectShape(const ShapePrimitive& shape, Ray& ray, Hit& hit, const QueryState& state, bool occlusion) const;
  bool occludedObject(const ObjectRef& object, const Ray& ray, const QueryState& state,
                      WatertightRayOnDemand& watertight) const;
  // A moving triangle at the ray's time (nothing outside its mesh's time range).
  bool intersectMotionTriangle(const MotionTriangle& motion, Ray& ray, Hit& hit, const QueryState& state,
                               bool occlusion, WatertightRayOnDemand& watertight) const;
  void buildTriangleTree(CollectedPrimitives& collected, const BuildOptions& options);
  bool orientedBoxesPayOff() const;
  void makeTriangleViews(TrianglesInLeafOrder trianglesInLeafOrder);
  void releaseBinaryTree();
  bool intersectObjects(Ray& ray, Hit& hit, const QueryState& state) const;
  bool occludedObjects(const Ray& ray, const QueryState& state) const;
  static Ray toLocal(const Instance& instance, const Ray& ray);

  // Triangles and quads: the binary tree, and its wide or oriented form when that layout is selected.
  AccelLayout layout_ = AccelLayout::Bvh4;
  BinaryBvh triangleBvh_;
  WideBvh<4> triangleBvh4_;
  TriangleWideView<4> triangleView4_;
  WideBvh<8> triangleBvh8_;
  TriangleWideView<8> triangleView8_;
  OrientedBvh triangleOriented_;
  TriangleOrientedView triangleOrientedView_;
  OrientedWideBvh<4> triangleOrientedWide4_;  // when options_.obbWidth == 4
  TriangleOrientedWideView<4> triangleOrientedWideView4_;
  OrientedWideBvh<8> triangleOrientedWide8_;  // when options_.obbWidth == 8
  TriangleOrientedWideView<8> triangleOrientedWideView8_;
  BuildOptions options_;
  BuildOptions requested_;  // as passed to build(), for refit's same-options check
  StoredTriangles triangles_;
  // Of the triangle tree, still known once the binary tree is released (releaseBinaryTree).
  size_t triangleCount_ = 0, triangleLeafCount_ = 0;
  Box3f triangleBounds_;
  // Instances and user primitives.
  BinaryBvh objectBvh_;
  std::vector<ObjectRef> objects_;
  std::vector<Instance> instances_;
  std::vector<ShapePrimitive> shapes_;
  std::vector<ShapeVertex> shapeSteps_;
  // Triangles of motion-blurred meshes, and the set (filters, masks, their grid cells) they test with.
  CollectedMotion motion_;
  TriangleSet motionSet_;

  std::vector<GridCell> gridCells_;  // grid cells, indexed by the primID of their triangles
  std::vector<SubdivCell> subdivCells_;  // subdivision tessellation cells, alike
  std::vector<uint32_t> geometryMasks_;
  std::vector<uint8_t> intersectFiltered_, occlusionFiltered_;
  const void* owner_ = nullptr;
  Box3f bounds_;
  TriangleBvhView triangleView_;
};

}  // namespace obvh
