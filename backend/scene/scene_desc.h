// Everything the API layer hands the backend to build one scene.
#pragma once

#include <cstdint>
#include <vector>

#include "intersect/curve_basis.h"
#include "intersect/shapes.h"
#include "math/affine.h"
#include "scene/instance_motion.h"
#include "scene/mesh_desc.h"

namespace obvh {

class SceneAccel;

struct InstanceDesc {
  const SceneAccel* child = nullptr;  // a committed scene; it must outlive this one's use of it
  Affine3f localToWorld;              // the first time step's, when it moves
  uint32_t geomID = 0;
  uint32_t mask = 0xFFFFFFFFu;
  InstanceMotion motion;              // motion blur: empty unless it moves
};

// Embree user geometry: the API computed each primitive's bounds with the user's callback.
struct UserGeometryDesc {
  uint32_t geomID = 0;
  uint32_t mask = 0xFFFFFFFFu;
  std::vector<Box3f> primitiveBounds;  // an empty or non-finite box skips the primitive
};

// Embree's sphere points, flat linear curves, round and flat cubic curves, which obvh intersects
// itself (intersect/shapes.h, intersect/round_curve.h, intersect/ribbon_curve.h).
enum class ShapeKind {
  Sphere,
  FlatLinearCurve,
  RoundBezierCurve,
  RoundBSplineCurve,
  RoundCatmullRomCurve,
  FlatBezierCurve,
  FlatBSplineCurve,
  FlatCatmullRomCurve
};
inline bool isRibbonCurve(ShapeKind kind) {
  return kind == ShapeKind::FlatBezierCurve || kind == ShapeKind::FlatBSplineCurve || kind == ShapeKind::FlatCatmullRomCurve;
}
// A cubic curve kind's basis (Bezier for the others).
inline CurveBasis curveBasisOf(ShapeKind kind) {
  switch (kind) {
    case ShapeKind::RoundBSplineCurve: case ShapeKind::FlatBSplineCurve: return CurveBasis::BSpline;
    case ShapeKind::RoundCatmullRomCurve: case ShapeKind::FlatCatmullRomCurve: return CurveBasis::CatmullRom;
    default: return CurveBasis::Bezier;
  }
}
// The vertices one primitive of the kind reads: a sphere's centre, a segment's ends, a cubic's controls.
inline int controlPointCount(ShapeKind kind) {
  return kind == ShapeKind::Sphere ? 1 : kind == ShapeKind::FlatLinearCurve ? 2 : 4;
}
struct ShapeGeometryDesc {
  ShapeKind kind = ShapeKind::Sphere;
  uint32_t geomID = 0;
  uint32_t mask = 0xFFFFFFFFu;
  std::vector<ShapeVertex> vertices;
  std::vector<uint32_t> segments;  // curves: each segment's first vertex (the others follow it)
  // Motion blur: the vertices of time steps 1, 2, ... (vertices is step 0), over [timeStart, timeEnd].
  std::vector<std::vector<ShapeVertex>> laterSteps;
  float timeStart = 0.f, timeEnd = 1.f;
  int ribbonQuads = 4;  // flat cubic curves: quads a segment (intersect/ribbon_curve.h)
};

struct SceneDesc {
  std::vector<MeshDesc> meshes;
  std::vector<InstanceDesc> instances;
  std::vector<UserGeometryDesc> userGeometries;
  std::vector<ShapeGeometryDesc> shapes;
  uint32_t geometryIdLimit = 0;               // one more than the largest geomID
  std::vector<uint8_t> intersectFiltered;     // per geomID: has an intersection filter
  std::vector<uint8_t> occlusionFiltered;     // per geomID: has an occlusion filter
  const void* owner = nullptr;                // handed back to QueryCallbacks
};

}  // namespace obvh
