// The control mesh of a Catmull-Clark subdivision surface (Embree's RTC_GEOMETRY_TYPE_SUBDIVISION):
// faces of 3 to 15 vertices, their half-edges, and the sharpness of every edge and vertex after
// creases, boundaries and the subdivision mode are applied.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

namespace obvh {

constexpr float kInfiniteSharpness = std::numeric_limits<float>::infinity();

// Embree's RTCSubdivisionMode values.
enum class SubdivBoundary : uint8_t {
  None = 0,          // faces on the boundary are not drawn
  Smooth = 1,        // boundary edges are creases (the default)
  PinCorners = 2,    // ... and vertices of a single face are pinned
  PinBoundary = 3,   // every boundary vertex is pinned: the boundary is the control polygon
  PinAll = 4         // every edge and vertex sharp: the surface is the bilinear control mesh
};

struct SubdivMeshInput {
  std::vector<uint32_t> faceSizes;      // vertices per face
  std::vector<uint32_t> indices;        // each face's vertices in turn; a half-edge per entry
  uint32_t vertexCount = 0;
  std::vector<uint8_t> vertexValid;     // per vertex: finite and within Embree's range (empty: all)
  std::vector<uint32_t> edgeCreases;    // pairs of vertex indices
  std::vector<float> edgeCreaseWeights;
  std::vector<uint32_t> vertexCreases;
  std::vector<float> vertexCreaseWeights;
  std::vector<uint32_t> holes;          // faces that do not exist
  SubdivBoundary boundary = SubdivBoundary::Smooth;
};

class SubdivTopology {
 public:
  static constexpr uint32_t kNone = 0xFFFFFFFFu;

  explicit SubdivTopology(const SubdivMeshInput& input);

  uint32_t faceCount() const { return uint32_t(faceSize_.size()); }
  uint32_t faceSize(uint32_t f) const { return faceSize_[f]; }
  uint32_t firstHalfEdge(uint32_t f) const { return faceStart_[f]; }
  // A face is drawn unless it is a hole, invalid (size or indices) or, without boundaries, on one.
  bool drawn(uint32_t f) const { return drawn_[f] != 0; }
  bool present(uint32_t f) const { return present_[f] != 0; }

  uint32_t halfEdgeCount() const { return uint32_t(indices_.size()); }
  uint32_t vertexOf(uint32_t h) const { return indices_[h]; }  // the half-edge's start vertex
  uint32_t faceOf(uint32_t h) const { return halfEdgeFace_[h]; }  // kNone when the face is not present
  uint32_t faceOfEdge(uint32_t h) const;                           // the face whose entry h is
  uint32_t next(uint32_t h) const;
  uint32_t previous(uint32_t h) const;
  uint32_t opposite(uint32_t h) const { return opposite_[h]; }  // kNone on a boundary
  float edgeSharpness(uint32_t h) const { return edgeSharpness_[h]; }

  uint32_t vertexCount() const { return uint32_t(vertexSharpness_.size()); }
  float vertexSharpness(uint32_t v) const { return vertexSharpness_[v]; }
  // The present faces around vertex v.
  const uint32_t* facesAround(uint32_t v, uint32_t& count) const {
    count = vertexFaceStart_[v + 1] - vertexFaceStart_[v];
    return vertexFaces_.data() + vertexFaceStart_[v];
  }

 private:
  std::vector<uint32_t> faceSize_, faceStart_;
  std::vector<uint8_t> present_, drawn_;
  std::vector<uint32_t> indices_, halfEdgeFace_, opposite_;
  std::vector<float> edgeSharpness_, vertexSharpness_;
  std::vector<uint32_t> vertexFaceStart_, vertexFaces_;
};

}  // namespace obvh
