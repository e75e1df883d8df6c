// Points of a Catmull-Clark limit surface: a face's patch is subdivided towards the point until
// the point's child is a regular bicubic B-spline patch (evaluated exactly), or the child has
// shrunk below 2^-kMaxPatchDepth of the face near an extraordinary point (then the bilinear blend
// of its corners' limit positions is used).
#pragma once

#include <vector>

#include "subdiv/local_patch.h"

namespace obvh {

constexpr int kMaxPatchDepth = 12;

// Values and derivatives at one (u, v) of a patch, `dim` each.
struct PatchPoint {
  std::vector<double> P, dPdu, dPdv, ddPdudu, ddPdvdv, ddPdudv;
};

// Face 0 of `patch` must be a quad; (u, v) in [0, 1] (values outside are clamped when subdividing).
PatchPoint evaluatePatch(LocalPatch patch, double u, double v);

// Positions only, for many points of one patch: out[3 * i] receives point i (patch.dim == 3).
void evaluatePatchPoints(const LocalPatch& patch, const std::vector<double>& us, const std::vector<double>& vs,
                         std::vector<double>& out);

// The patch a face's (u, v) lies on: the face's ring for a quad, else the ring of its child at
// vertex `subpatch` after one subdivision step (Embree's parametrization of other faces).
LocalPatch facePatch(const SubdivTopology& topology, uint32_t face, int subpatch, int dim, ControlValues read,
                     const void* context);

}  // namespace obvh
