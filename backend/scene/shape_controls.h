// What a shape primitive is traced as, per kind: its control points (a round cubic curve's in
// Bezier form, whatever basis it was given in; a flat cubic curve's in its own basis, as its quads
// are cut from the exact curve), their bounds, and the test for its kind.
#pragma once

#include <algorithm>

#include "intersect/ribbon_curve.h"
#include "intersect/round_curve.h"
#include "intersect/shapes.h"
#include "scene/scene_desc.h"

namespace obvh {

struct ShapeControls {
  ShapeVertex v[4];
  Box3f bounds;
};

// vertices: the controlPointCount(kind) vertices the primitive reads, in buffer order.
inline ShapeControls shapeControls(ShapeKind kind, const ShapeVertex* vertices) {
  ShapeControls c;
  if (kind == ShapeKind::Sphere) {
    c.v[0] = vertices[0];
    c.bounds = sphereBounds(c.v[0]);
  } else if (kind == ShapeKind::FlatLinearCurve) {
    c.v[0] = vertices[0], c.v[1] = vertices[1];
    c.bounds = segmentBounds(c.v[0], c.v[1]);
  } else if (isRibbonCurve(kind)) {
    std::copy(vertices, vertices + 4, c.v);
    c.bounds = ribbonCurveBounds(curveBasisOf(kind), c.v);
  } else {
    const CubicBezier bezier = bezierOf(curveBasisOf(kind), vertices);
    std::copy(bezier.p, bezier.p + 4, c.v);
    c.bounds = roundCurveBounds(bezier);
  }
  return c;
}

// v: the primitive's control points as shapeControls made them; ribbonQuads: flat cubic curves' quads.
inline bool intersectShapeControls(ShapeKind kind, const Ray& ray, const ShapeVertex* v, int ribbonQuads, ShapeHit& hit) {
  if (kind == ShapeKind::Sphere) return intersectSphere(ray, v[0], hit);
  if (kind == ShapeKind::FlatLinearCurve) return intersectFlatSegment(ray, v[0], v[1], hit);
  if (isRibbonCurve(kind)) return intersectRibbonCurve(ray, curveBasisOf(kind), v, ribbonQuads, hit);
  CubicBezier bezier;
  std::copy(v, v + 4, bezier.p);
  return intersectRoundCurve(ray, bezier, hit);
}

}  // namespace obvh
