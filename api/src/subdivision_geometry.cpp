#include "subdivision_geometry.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "api_error.h"
#include "scene/primitive_collection.h"

namespace obvh::api {
namespace {

template <typename T>
std::vector<T> readItems(const BufferView& view, size_t components) {
  std::vector<T> out;
  if (!view.bound() || !view.data()) return out;
  out.resize(view.itemCount * components);
  for (size_t i = 0; i < view.itemCount; ++i)
    std::memcpy(&out[i * components], view.data() + i * view.byteStride, sizeof(T) * components);
  return out;
}

struct VertexSource {
  const BufferView* view;
};

void readPosition(const void* context, uint32_t vertex, double* out) {
  const BufferView& view = *static_cast<const VertexSource*>(context)->view;
  float xyz[3];
  std::memcpy(xyz, view.data() + size_t(vertex) * view.byteStride, sizeof xyz);
  out[0] = xyz[0], out[1] = xyz[1], out[2] = xyz[2];
}

}  // namespace

bool SubdivisionGeometry::ownsBufferType(int type) {
  switch (type) {
    case RTC_BUFFER_TYPE_FACE: case RTC_BUFFER_TYPE_INDEX: case RTC_BUFFER_TYPE_EDGE_CREASE_INDEX:
    case RTC_BUFFER_TYPE_EDGE_CREASE_WEIGHT: case RTC_BUFFER_TYPE_VERTEX_CREASE_INDEX:
    case RTC_BUFFER_TYPE_VERTEX_CREASE_WEIGHT: case RTC_BUFFER_TYPE_HOLE: case RTC_BUFFER_TYPE_LEVEL:
      return true;
  }
  return false;
}

void SubdivisionGeometry::checkBinding(int type, unsigned slot, int format) const {
  const unsigned slots = type == RTC_BUFFER_TYPE_INDEX ? unsigned(indices_.size()) : 1u;
  if (slot >= slots) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer slot");
  int expected = RTC_FORMAT_UINT;
  if (type == RTC_BUFFER_TYPE_EDGE_CREASE_INDEX) expected = RTC_FORMAT_UINT2;
  if (type == RTC_BUFFER_TYPE_EDGE_CREASE_WEIGHT || type == RTC_BUFFER_TYPE_VERTEX_CREASE_WEIGHT ||
      type == RTC_BUFFER_TYPE_LEVEL)
    expected = RTC_FORMAT_FLOAT;
  if (format != expected) fail(RTC_ERROR_INVALID_OPERATION, "invalid buffer format for a subdivision geometry");
}

BufferView& SubdivisionGeometry::view(int type, unsigned slot) {
  switch (type) {
    case RTC_BUFFER_TYPE_INDEX:
      if (slot >= indices_.size()) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer slot");
      return indices_[slot];
    case RTC_BUFFER_TYPE_FACE: case RTC_BUFFER_TYPE_EDGE_CREASE_INDEX: case RTC_BUFFER_TYPE_EDGE_CREASE_WEIGHT:
    case RTC_BUFFER_TYPE_VERTEX_CREASE_INDEX: case RTC_BUFFER_TYPE_VERTEX_CREASE_WEIGHT: case RTC_BUFFER_TYPE_HOLE:
    case RTC_BUFFER_TYPE_LEVEL:
      if (slot != 0) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer slot");
      break;
    default:
      fail(RTC_ERROR_INVALID_ARGUMENT, "unknown buffer type");
  }
  switch (type) {
    case RTC_BUFFER_TYPE_FACE: return faces_;
    case RTC_BUFFER_TYPE_EDGE_CREASE_INDEX: return edgeCreaseIndices_;
    case RTC_BUFFER_TYPE_EDGE_CREASE_WEIGHT: return edgeCreaseWeights_;
    case RTC_BUFFER_TYPE_VERTEX_CREASE_INDEX: return vertexCreaseIndices_;
    case RTC_BUFFER_TYPE_VERTEX_CREASE_WEIGHT: return vertexCreaseWeights_;
    case RTC_BUFFER_TYPE_HOLE: return holes_;
    default: return levels_;
  }
}

void SubdivisionGeometry::setTopologyCount(unsigned count) {
  if (count == 0) fail(RTC_ERROR_INVALID_ARGUMENT, "at least one topology is required");
  indices_.resize(count);
  modes_.resize(count, RTC_SUBDIVISION_MODE_SMOOTH_BOUNDARY);
}

void SubdivisionGeometry::setMode(unsigned topology, int mode) {
  if (topology >= modes_.size()) fail(RTC_ERROR_INVALID_OPERATION, "invalid topology ID");
  modes_[topology] = mode;
}

void SubdivisionGeometry::setAttributeTopology(unsigned attribute, unsigned topology, unsigned attributeCount) {
  if (attribute >= attributeCount) fail(RTC_ERROR_INVALID_OPERATION, "invalid vertex attribute slot");
  if (topology >= indices_.size()) fail(RTC_ERROR_INVALID_OPERATION, "invalid topology ID");
  if (attributeTopology_.size() < attributeCount) attributeTopology_.resize(attributeCount, 0);
  attributeTopology_[attribute] = topology;
}

unsigned SubdivisionGeometry::attributeTopology(unsigned attribute) const {
  return attribute < attributeTopology_.size() ? attributeTopology_[attribute] : 0u;
}

SubdivMeshInput SubdivisionGeometry::inputOf(unsigned topology, uint32_t vertexCount) const {
  SubdivMeshInput in;
  in.faceSizes = readItems<uint32_t>(faces_, 1);
  in.indices = readItems<uint32_t>(indices_[topology], 1);
  in.vertexCount = vertexCount;
  in.edgeCreases = readItems<uint32_t>(edgeCreaseIndices_, 2);
  in.edgeCreaseWeights = readItems<float>(edgeCreaseWeights_, 1);
  in.vertexCreases = readItems<uint32_t>(vertexCreaseIndices_, 1);
  in.vertexCreaseWeights = readItems<float>(vertexCreaseWeights_, 1);
  in.holes = readItems<uint32_t>(holes_, 1);
  const int mode = modes_[topology];
  in.boundary = mode >= RTC_SUBDIVISION_MODE_NO_BOUNDARY && mode <= RTC_SUBDIVISION_MODE_PIN_ALL ? SubdivBoundary(mode)
                                                                                               : SubdivBoundary::Smooth;
  return in;
}

void SubdivisionGeometry::commit(const std::vector<BufferView>& timeSteps) {
  topologies_.clear();
  tessellation_.reset();
  laterSteps_.clear();
  if (!faces_.bound() || !faces_.data()) return;
  for (unsigned t = 0; t < indices_.size(); ++t) {
    if (!indices_[t].bound() || !indices_[t].data()) {
      topologies_.push_back(nullptr);
      continue;
    }
    // Interpolation reads buffers of any size through a topology: its vertices are the indices
    // used (rtcInterpolate checks them against the buffer).
    SubdivMeshInput in = inputOf(t, 0);
    for (uint32_t index : in.indices) in.vertexCount = std::max(in.vertexCount, index + 1);
    topologies_.push_back(std::make_shared<SubdivTopology>(in));
  }
  if (!indices_[0].bound() || !indices_[0].data()) return;
  const size_t vertexCount = timeSteps[0].itemCount;
  for (const BufferView& step : timeSteps)
    if (!step.bound() || !step.data() || step.itemCount != vertexCount) return;
  SubdivMeshInput in = inputOf(0, uint32_t(vertexCount));
  in.vertexValid.assign(vertexCount, 1);
  for (const BufferView& step : timeSteps)
    for (size_t v = 0; v < vertexCount; ++v) {
      float xyz[3];
      std::memcpy(xyz, step.data() + v * step.byteStride, sizeof xyz);
      in.vertexValid[v] &= isValidVertex(xyz);
    }
  const SubdivTopology traced(in);
  const std::vector<float> levels = readItems<float>(levels_, 1);
  const float* perEdge = !levels.empty() && levels.size() >= in.indices.size() ? levels.data() : nullptr;
  for (size_t s = 0; s < timeSteps.size(); ++s) {
    VertexSource source{&timeSteps[s]};
    SubdivTessellation t = tessellateSubdivision(traced, readPosition, &source, perEdge, rate_);
    if (s == 0)
      tessellation_ = std::make_shared<SubdivTessellation>(std::move(t));
    else
      laterSteps_.push_back(std::move(t.vertices));
  }
}

const SubdivTopology* SubdivisionGeometry::topology(unsigned slot) const {
  return slot < topologies_.size() ? topologies_[slot].get() : nullptr;
}

}  // namespace obvh::api
