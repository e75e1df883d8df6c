// rtcInterpolate / rtcInterpolateN for triangle, quad and grid meshes, with Embree's conventions:
// triangles interpolate linearly in (u, v); quads use the same two-triangle split as intersection,
// (v0, v1, v3) for u + v <= 1 and (v2, v3, v1) with (1-u, 1-v) otherwise. A grid's (u, v), clamped
// to [0, 1], picks a cell, interpolated as a quad with derivatives per unit of the grid's (u, v).
// Second derivatives are 0 on meshes. Curves evaluate their basis along the segment at u
// (interpolateCurve).
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "api_error.h"
#include "enum_bits.h"
#include "geometry.h"
#include "intersect/curve_basis.h"
#include "subdiv/patch_eval.h"

using namespace obvh::api;

namespace {

struct Corners {
  const float* value[3];
  float du[2];  // derivative weights of (value[1] - value[0]) and (value[2] - value[0]) along u
  float dv[2];
  float wu, wv;  // barycentric weights of value[1] and value[2]
};

const float* itemAt(const BufferView& view, uint32_t index, unsigned valueCount) {
  if (index >= view.itemCount) fail(RTC_ERROR_INVALID_ARGUMENT, "primitive references a vertex that does not exist");
  const size_t offset = view.byteOffset + size_t(index) * view.byteStride;
  if (offset + valueCount * sizeof(float) > view.buffer->size())
    fail(RTC_ERROR_INVALID_ARGUMENT, "valueCount reads past the end of the buffer");
  return reinterpret_cast<const float*>(view.buffer->data() + offset);
}

// A quad's corners (v0, v1, v2, v3) at (u, v), split as Embree splits quads.
Corners quadCorners(const BufferView& values, const uint32_t idx[4], float u, float v, unsigned valueCount) {
  if (u + v <= 1.f)
    return {{itemAt(values, idx[0], valueCount), itemAt(values, idx[1], valueCount), itemAt(values, idx[3], valueCount)},
            {1.f, 0.f}, {0.f, 1.f}, u, v};
  // Second half: value = a2 + (1-u)(a3-a2) + (1-v)(a1-a2).
  return {{itemAt(values, idx[2], valueCount), itemAt(values, idx[3], valueCount), itemAt(values, idx[1], valueCount)},
          {-1.f, 0.f}, {0.f, -1.f}, 1.f - u, 1.f - v};
}

// The cell of a grid that (u, v) falls in, as a quad, with derivatives scaled to the grid's (u, v).
Corners gridCorners(const BufferView& values, const unsigned char* record, float u, float v, unsigned valueCount) {
  RTCGrid grid;
  std::memcpy(&grid, record, sizeof grid);  // the buffer need only be 4-byte aligned
  if (grid.width < 2 || grid.height < 2) fail(RTC_ERROR_INVALID_ARGUMENT, "grid has no cells (width or height below 2)");
  const int columns = grid.width - 1, rows = grid.height - 1;
  u = std::clamp(u, 0.f, 1.f);
  v = std::clamp(v, 0.f, 1.f);
  // u = 1 lies on the last cell's far edge (Embree reads a column past the grid there).
  const int x = std::min(int(std::floor(u * float(columns))), columns - 1);
  const int y = std::min(int(std::floor(v * float(rows))), rows - 1);
  const auto index = [&](int dx, int dy) {
    const uint64_t i = uint64_t(grid.startVertexID) + uint64_t(y + dy) * grid.stride + uint64_t(x + dx);
    if (i > 0xFFFFFFFFu) fail(RTC_ERROR_INVALID_ARGUMENT, "primitive references a vertex that does not exist");
    return uint32_t(i);
  };
  const uint32_t idx[4] = {index(0, 0), index(1, 0), index(1, 1), index(0, 1)};
  Corners c = quadCorners(values, idx, u * float(columns) - float(x), v * float(rows) - float(y), valueCount);
  for (float& d : c.du) d /= float(columns);
  for (float& d : c.dv) d /= float(rows);
  return c;
}

// A curve segment's basis at u: the weights of its control vertices (2 for linear curves, else 4
// from the segment's first index) and their first and second derivatives in u.
struct CurveWeights {
  int count = 4;
  float w[4], dw[4], ddw[4];
};

CurveWeights curveWeights(const Geometry& g, float u) {
  if (g.type() == RTC_GEOMETRY_TYPE_FLAT_LINEAR_CURVE) return {2, {1.f - u, u, 0.f, 0.f}, {-1.f, 1.f, 0.f, 0.f}, {}};
  const obvh::CurveBasisWeights b = obvh::curveBasisWeights(obvh::curveBasisOf(g.shapeKind()), u);
  CurveWeights c;
  for (int k = 0; k < 4; ++k) c.w[k] = float(b.w[k]), c.dw[k] = float(b.dw[k]), c.ddw[k] = float(b.ddw[k]);
  return c;
}

// The first vertex of curve segment primID, which reads `count` vertices from it.
uint32_t segmentStart(const Geometry& g, unsigned primID, int count) {
  const BufferView& index = g.indexBuffer();
  if (primID >= index.itemCount) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid primitive ID");
  uint32_t first;
  std::memcpy(&first, index.data() + size_t(primID) * index.byteStride, sizeof first);
  if (uint64_t(first) + uint64_t(count - 1) > 0xFFFFFFFFu)
    fail(RTC_ERROR_INVALID_ARGUMENT, "primitive references a vertex that does not exist");
  return first;
}

// A curve's values along its segment primID at u. Measured on Debian's Embree and answered alike:
// a cubic curve writes P, dPdu and ddPdudu and leaves the derivatives in v as they were; a flat
// linear curve writes P and dPdu = 0 (not its slope) and leaves the rest.
void interpolateCurve(const Geometry& g, const BufferView& values, unsigned primID, float u, float* P, float* dPdu,
                      float* ddPdudu, unsigned valueCount) {
  const bool linear = g.type() == RTC_GEOMETRY_TYPE_FLAT_LINEAR_CURVE;
  const CurveWeights c = curveWeights(g, u);
  const uint32_t first = segmentStart(g, primID, c.count);
  const float* vertex[4];
  for (int k = 0; k < c.count; ++k) vertex[k] = itemAt(values, first + uint32_t(k), valueCount);
  for (unsigned i = 0; i < valueCount; ++i) {
    float p = 0.f, dp = 0.f, ddp = 0.f;
    for (int k = 0; k < c.count; ++k) p += c.w[k] * vertex[k][i], dp += c.dw[k] * vertex[k][i], ddp += c.ddw[k] * vertex[k][i];
    if (P) P[i] = p;
    if (dPdu) dPdu[i] = linear ? 0.f : dp;
    if (ddPdudu && !linear) ddPdudu[i] = ddp;
  }
}

// A Hermite curve's values, measured on Debian's Embree and answered alike: its vertex buffer
// (or, asked for its tangent buffer, the same) follows the Hermite basis over the vertices and
// tangents of the slot; a vertex attribute is interpolated linearly between the segment's two
// vertices (ddPdudu = 0). values: the vertex buffer of the slot, or the attribute's.
void interpolateHermite(const Geometry& g, const BufferView& values, int type, unsigned slot, unsigned primID, float u,
                        float* P, float* dPdu, float* ddPdudu, unsigned valueCount) {
  const uint32_t first = segmentStart(g, primID, 2);
  if (type == RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE) {
    const float *a = itemAt(values, first, valueCount), *b = itemAt(values, first + 1, valueCount);
    for (unsigned i = 0; i < valueCount; ++i) {
      if (P) P[i] = (1.f - u) * a[i] + u * b[i];
      if (dPdu) dPdu[i] = b[i] - a[i];
      if (ddPdudu) ddPdudu[i] = 0.f;
    }
    return;
  }
  const BufferView& tangent = g.tangentBuffer(slot);
  if (!tangent.bound()) fail(RTC_ERROR_INVALID_OPERATION, "buffer not set");
  const float* item[4] = {itemAt(values, first, valueCount), itemAt(tangent, first, valueCount),
                          itemAt(values, first + 1, valueCount), itemAt(tangent, first + 1, valueCount)};
  const float u2 = u * u, u3 = u2 * u;
  const float w[4] = {2.f * u3 - 3.f * u2 + 1.f, u3 - 2.f * u2 + u, -2.f * u3 + 3.f * u2, u3 - u2};
  const float dw[4] = {6.f * u2 - 6.f * u, 3.f * u2 - 4.f * u + 1.f, -6.f * u2 + 6.f * u, 3.f * u2 - 2.f * u};
  const float ddw[4] = {12.f * u - 6.f, 6.f * u - 4.f, -12.f * u + 6.f, 6.f * u - 2.f};
  for (unsigned i = 0; i < valueCount; ++i) {
    float p = 0.f, dp = 0.f, ddp = 0.f;
    for (int k = 0; k < 4; ++k) p += w[k] * item[k][i], dp += dw[k] * item[k][i], ddp += ddw[k] * item[k][i];
    if (P) P[i] = p;
    if (dPdu) dPdu[i] = dp;
    if (ddPdudu) ddPdudu[i] = ddp;
  }
}

// A buffer's items as the patch engine reads them (obvh::ControlValues), checked against the buffer.
struct ItemReader {
  const BufferView* values;
  unsigned valueCount;
  static void read(const void* context, uint32_t vertex, double* out) {
    const ItemReader& self = *static_cast<const ItemReader*>(context);
    const float* item = itemAt(*self.values, vertex, self.valueCount);
    for (unsigned k = 0; k < self.valueCount; ++k) out[k] = item[k];
  }
};

// A subdivision face's values on the limit surface of the topology the buffer uses, with exact
// derivatives. Faces of other than four vertices take Embree's subpatch encoding of (u, v).
void interpolateSubdivision(const Geometry& g, const BufferView& values, int type, unsigned slot, unsigned primID,
                            float u, float v, float* const outputs[6], unsigned valueCount) {
  const unsigned topologyID = type == RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE ? g.subdivision().attributeTopology(slot) : 0u;
  const obvh::SubdivTopology* topology = g.subdivision().topology(topologyID);
  if (!topology) fail(RTC_ERROR_INVALID_OPERATION, "geometry not committed, or an index buffer is not set");
  if (primID >= topology->faceCount()) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid primitive ID");
  if (!topology->present(primID)) fail(RTC_ERROR_INVALID_ARGUMENT, "the face is a hole or invalid");
  const uint32_t first = topology->firstHalfEdge(primID);
  for (uint32_t i = 0; i < topology->faceSize(primID); ++i) itemAt(values, topology->vertexOf(first + i), valueCount);
  int subpatch = 0;
  double pu = u, pv = v;
  if (topology->faceSize(primID) != 4) {
    const float l = std::floor(0.5f * u), h = std::floor(0.5f * v);
    subpatch = int(4.f * h + l);
    if (subpatch < 0 || subpatch >= int(topology->faceSize(primID)))
      fail(RTC_ERROR_INVALID_ARGUMENT, "(u, v) names no subpatch of the face");
    pu = 2.0 * (0.5 * double(u) - double(l)) - 0.5;
    pv = 2.0 * (0.5 * double(v) - double(h)) - 0.5;
  }
  const ItemReader reader{&values, valueCount};
  const obvh::PatchPoint point = obvh::evaluatePatch(
      obvh::facePatch(*topology, primID, subpatch, int(valueCount), &ItemReader::read, &reader), pu, pv);
  const std::vector<double>* results[6] = {&point.P, &point.dPdu, &point.dPdv, &point.ddPdudu, &point.ddPdvdv, &point.ddPdudv};
  for (int s = 0; s < 6; ++s)
    if (outputs[s])
      for (unsigned k = 0; k < valueCount; ++k) outputs[s][k] = float((*results[s])[k]);
}

void interpolateOne(const Geometry& g, unsigned primID, float u, float v, int type, unsigned slot, float* P,
                    float* dPdu, float* dPdv, float* ddPdudu, float* ddPdvdv, float* ddPdudv, unsigned valueCount) {
  if (!g.isMesh() && !g.isCurve() && !g.isSubdivision())
    fail(RTC_ERROR_INVALID_OPERATION,
         "rtcInterpolate is supported for triangle, quad, grid and subdivision meshes and curves");
  const BufferView* values = nullptr;
  if (type == RTC_BUFFER_TYPE_VERTEX || (type == RTC_BUFFER_TYPE_TANGENT && g.isHermite())) {
    if (slot >= g.timeStepCount()) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer slot");
    values = &g.vertexBuffer(slot);
  } else if (type == RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE) {
    values = &g.attributeBuffer(slot);
  } else {
    fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer type for interpolation");
  }
  if (g.isSubdivision()) {
    if (!values->bound()) fail(RTC_ERROR_INVALID_OPERATION, "buffer not set");
    float* const outputs[6] = {P, dPdu, dPdv, ddPdudu, ddPdvdv, ddPdudv};
    return interpolateSubdivision(g, *values, type, slot, primID, u, v, outputs, valueCount);
  }
  const BufferView& index = g.indexBuffer();
  if (!values->bound() || !index.bound()) fail(RTC_ERROR_INVALID_OPERATION, "buffer not set");
  if (g.isHermite()) return interpolateHermite(g, *values, type, slot, primID, u, P, dPdu, ddPdudu, valueCount);
  if (g.isCurve()) return interpolateCurve(g, *values, primID, u, P, dPdu, ddPdudu, valueCount);
  if (primID >= index.itemCount) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid primitive ID");
  const unsigned char* record = index.data() + size_t(primID) * index.byteStride;
  Corners c;
  if (g.isGridMesh()) {
    c = gridCorners(*values, record, u, v, valueCount);
  } else {
    uint32_t idx[4];
    std::memcpy(idx, record, sizeof(uint32_t) * (g.isQuadMesh() ? 4 : 3));
    if (g.isQuadMesh())
      c = quadCorners(*values, idx, u, v, valueCount);
    else
      c = {{itemAt(*values, idx[0], valueCount), itemAt(*values, idx[1], valueCount), itemAt(*values, idx[2], valueCount)},
           {1.f, 0.f}, {0.f, 1.f}, u, v};
  }
  for (unsigned k = 0; k < valueCount; ++k) {
    const float a = c.value[0][k], e1 = c.value[1][k] - a, e2 = c.value[2][k] - a;
    if (P) P[k] = a + c.wu * e1 + c.wv * e2;
    if (dPdu) dPdu[k] = c.du[0] * e1 + c.du[1] * e2;
    if (dPdv) dPdv[k] = c.dv[0] * e1 + c.dv[1] * e2;
    if (ddPdudu) ddPdudu[k] = 0.f;
    if (ddPdvdv) ddPdvdv[k] = 0.f;
    if (ddPdudv) ddPdudv[k] = 0.f;
  }
}

}  // namespace

RTC_API void rtcInterpolate(const RTCInterpolateArguments* args) {
  Geometry* g = args ? Geometry::from(args->geometry) : nullptr;
  guarded(g ? g->device() : nullptr, [&] {
    requireHandle(args);
    requireHandle(g);
    interpolateOne(*g, args->primID, args->u, args->v, enumBits(args->bufferType), args->bufferSlot, args->P, args->dPdu,
                   args->dPdv, args->ddPdudu, args->ddPdvdv, args->ddPdudv, args->valueCount);
  });
}

// Results are stored per component: value k of item i at [k * N + i], as Embree lays them out.
RTC_API void rtcInterpolateN(const RTCInterpolateNArguments* args) {
  Geometry* g = args ? Geometry::from(args->geometry) : nullptr;
  guarded(g ? g->device() : nullptr, [&] {
    requireHandle(args);
    requireHandle(g);
    const unsigned N = args->N, count = args->valueCount;
    std::vector<float> out[6];
    for (auto& o : out) o.resize(count);
    const int* valid = static_cast<const int*>(args->valid);
    for (unsigned i = 0; i < N; ++i) {
      if (valid && valid[i] != -1) continue;
      float* slots[6];
      for (int s = 0; s < 6; ++s) slots[s] = out[s].data();
      interpolateOne(*g, args->primIDs[i], args->u[i], args->v[i], enumBits(args->bufferType), args->bufferSlot,
                     args->P ? slots[0] : nullptr, args->dPdu ? slots[1] : nullptr, args->dPdv ? slots[2] : nullptr,
                     args->ddPdudu ? slots[3] : nullptr, args->ddPdvdv ? slots[4] : nullptr,
                     args->ddPdudv ? slots[5] : nullptr, count);
      float* targets[6] = {args->P, args->dPdu, args->dPdv, args->ddPdudu, args->ddPdvdv, args->ddPdudv};
      for (int s = 0; s < 6; ++s)
        if (targets[s])
          for (unsigned k = 0; k < count; ++k) targets[s][size_t(k) * N + i] = out[s][k];
    }
  });
}
