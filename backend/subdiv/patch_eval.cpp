#include "subdiv/patch_eval.h"

#include <algorithm>
#include <numeric>

namespace obvh {
namespace {

// Uniform cubic B-spline basis at t and its first and second derivatives.
void bsplineBasis(double t, double b[4], double d[4], double dd[4]) {
  const double s = 1.0 - t, t2 = t * t, t3 = t2 * t;
  b[0] = s * s * s / 6.0;
  b[1] = (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0;
  b[2] = (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0;
  b[3] = t3 / 6.0;
  d[0] = -0.5 * s * s;
  d[1] = 1.5 * t2 - 2.0 * t;
  d[2] = -1.5 * t2 + t + 0.5;
  d[3] = 0.5 * t2;
  dd[0] = s;
  dd[1] = 3.0 * t - 2.0;
  dd[2] = 1.0 - 3.0 * t;
  dd[3] = t;
}

void evaluateGrid(const std::vector<double>& grid, int dim, double u, double v, double scale, PatchPoint& out) {
  double bu[4], du[4], ddu[4], bv[4], dv[4], ddv[4];
  bsplineBasis(u, bu, du, ddu);
  bsplineBasis(v, bv, dv, ddv);
  for (std::vector<double>* o : {&out.P, &out.dPdu, &out.dPdv, &out.ddPdudu, &out.ddPdvdv, &out.ddPdudv})
    o->assign(dim, 0.0);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      const double* g = grid.data() + size_t(r * 4 + c) * dim;
      for (int k = 0; k < dim; ++k) {
        out.P[k] += bv[r] * bu[c] * g[k];
        out.dPdu[k] += bv[r] * du[c] * g[k] * scale;
        out.dPdv[k] += dv[r] * bu[c] * g[k] * scale;
        out.ddPdudu[k] += bv[r] * ddu[c] * g[k] * scale * scale;
        out.ddPdvdv[k] += ddv[r] * bu[c] * g[k] * scale * scale;
        out.ddPdudv[k] += dv[r] * du[c] * g[k] * scale * scale;
      }
    }
}

void evaluateBilinear(const std::vector<double>& corners, int dim, double u, double v, double scale, PatchPoint& out) {
  for (std::vector<double>* o : {&out.P, &out.dPdu, &out.dPdv, &out.ddPdudu, &out.ddPdvdv, &out.ddPdudv})
    o->assign(dim, 0.0);
  const double* c0 = corners.data();
  const double* c1 = c0 + dim;
  const double* c2 = c1 + dim;
  const double* c3 = c2 + dim;
  for (int k = 0; k < dim; ++k) {
    out.P[k] = (1 - u) * (1 - v) * c0[k] + u * (1 - v) * c1[k] + u * v * c2[k] + (1 - u) * v * c3[k];
    out.dPdu[k] = ((1 - v) * (c1[k] - c0[k]) + v * (c2[k] - c3[k])) * scale;
    out.dPdv[k] = ((1 - u) * (c3[k] - c0[k]) + u * (c2[k] - c1[k])) * scale;
    out.ddPdudv[k] = (c0[k] - c1[k] + c2[k] - c3[k]) * scale * scale;
  }
}

double clamp01(double x) { return std::min(1.0, std::max(0.0, x)); }

void evaluatePointsAt(const LocalPatch& patch, const std::vector<double>& us, const std::vector<double>& vs,
                      const std::vector<int>& which, int depth, std::vector<double>& out) {
  std::vector<double> grid;
  PatchPoint point;
  if (regularControlGrid(patch, grid)) {
    for (int i : which) {
      evaluateGrid(grid, 3, us[i], vs[i], 1.0, point);
      std::copy(point.P.begin(), point.P.end(), out.begin() + 3 * size_t(i));
    }
    return;
  }
  // Points at a corner take its limit position (exact; the limit masks need quads around it, so
  // not before the first step); the rest go on to the children.
  std::vector<int> rest;
  if (depth > 0) {
    cornerLimits(patch, grid);
    for (int i : which) {
      const bool corner = (us[i] == 0.0 || us[i] == 1.0) && (vs[i] == 0.0 || vs[i] == 1.0);
      if (!corner && depth < kMaxPatchDepth) {
        rest.push_back(i);
        continue;
      }
      evaluateBilinear(grid, 3, us[i], vs[i], 1.0, point);
      std::copy(point.P.begin(), point.P.end(), out.begin() + 3 * size_t(i));
    }
  } else {
    rest = which;
  }
  if (rest.empty()) return;
  // Each point goes to one quadrant, so one copy holds every child's coordinates.
  const LocalPatch subdivided = subdivide(patch);
  std::vector<int> inside[2][2];
  std::vector<double> childU = us, childV = vs;
  for (int i : rest) {
    const int qu = us[i] >= 0.5, qv = vs[i] >= 0.5;
    inside[qu][qv].push_back(i);
    childU[i] = 2.0 * us[i] - qu, childV[i] = 2.0 * vs[i] - qv;
  }
  for (int qu = 0; qu < 2; ++qu)
    for (int qv = 0; qv < 2; ++qv)
      if (!inside[qu][qv].empty())
        evaluatePointsAt(quadrantChild(subdivided, qu, qv), childU, childV, inside[qu][qv], depth + 1, out);
}

}  // namespace

PatchPoint evaluatePatch(LocalPatch patch, double u, double v) {
  std::vector<double> grid;
  PatchPoint out;
  double scale = 1.0;
  for (int depth = 0;; ++depth) {
    if (regularControlGrid(patch, grid)) {
      evaluateGrid(grid, patch.dim, u, v, scale, out);
      return out;
    }
    u = clamp01(u), v = clamp01(v);
    if (depth == kMaxPatchDepth) {
      cornerLimits(patch, grid);
      evaluateBilinear(grid, patch.dim, u, v, scale, out);
      return out;
    }
    const int qu = u >= 0.5, qv = v >= 0.5;
    patch = quadrantChild(subdivide(patch), qu, qv);
    u = 2.0 * u - qu, v = 2.0 * v - qv, scale *= 2.0;
  }
}

void evaluatePatchPoints(const LocalPatch& patch, const std::vector<double>& us, const std::vector<double>& vs,
                         std::vector<double>& out) {
  out.assign(3 * us.size(), 0.0);
  std::vector<double> cu(us.size()), cv(vs.size());
  for (size_t i = 0; i < us.size(); ++i) cu[i] = clamp01(us[i]), cv[i] = clamp01(vs[i]);
  std::vector<int> all(us.size());
  std::iota(all.begin(), all.end(), 0);
  evaluatePointsAt(patch, cu, cv, all, 0, out);
}

LocalPatch facePatch(const SubdivTopology& topology, uint32_t face, int subpatch, int dim, ControlValues read,
                     const void* context) {
  LocalPatch ring = ringOfFace(topology, face, dim, read, context);
  if (topology.faceSize(face) == 4) return ring;
  return cornerChild(subdivide(ring), subpatch);
}

}  // namespace obvh
