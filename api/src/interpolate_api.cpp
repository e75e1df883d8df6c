// rtcInterpolate / rtcInterpolateN for triangle and quad meshes, with Embree's conventions:
// triangles interpolate linearly in (u, v); quads use the same two-triangle split as intersection,
// (v0, v1, v3) for u + v <= 1 and (v2, v3, v1) with (1-u, 1-v) otherwise. Second derivatives are 0.
#include <embree3/rtcore.h>

#include <cstring>
#include <vector>

#include "api_error.h"
#include "enum_bits.h"
#include "geometry.h"

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

void interpolateOne(const Geometry& g, unsigned primID, float u, float v, int type, unsigned slot, float* P,
                    float* dPdu, float* dPdv, float* ddPdudu, float* ddPdvdv, float* ddPdudv, unsigned valueCount) {
  if (!g.isMesh()) fail(RTC_ERROR_INVALID_OPERATION, "rtcInterpolate is supported for triangle and quad meshes");
  const BufferView* values = nullptr;
  if (type == RTC_BUFFER_TYPE_VERTEX) {
    if (slot != 0) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer slot");
    values = &g.vertexBuffer();
  } else if (type == RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE) {
    values = &g.attributeBuffer(slot);
  } else {
    fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer type for interpolation");
  }
  const BufferView& index = g.indexBuffer();
  if (!values->bound() || !index.bound()) fail(RTC_ERROR_INVALID_OPERATION, "buffer not set");
  if (primID >= index.itemCount) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid primitive ID");
  const int corners = g.isQuadMesh() ? 4 : 3;
  uint32_t idx[4];
  std::memcpy(idx, index.data() + size_t(primID) * index.byteStride, sizeof(uint32_t) * corners);

  Corners c;
  if (!g.isQuadMesh() || u + v <= 1.f) {
    const uint32_t third = g.isQuadMesh() ? idx[3] : idx[2];
    c = {{itemAt(*values, idx[0], valueCount), itemAt(*values, idx[1], valueCount), itemAt(*values, third, valueCount)},
         {1.f, 0.f}, {0.f, 1.f}, u, v};
  } else {
    // Second half: value = a2 + (1-u)(a3-a2) + (1-v)(a1-a2).
    c = {{itemAt(*values, idx[2], valueCount), itemAt(*values, idx[3], valueCount), itemAt(*values, idx[1], valueCount)},
         {-1.f, 0.f}, {0.f, -1.f}, 1.f - u, 1.f - v};
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
