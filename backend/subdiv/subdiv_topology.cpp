#include "subdiv/subdiv_topology.h"

#include <algorithm>
#include <unordered_map>

namespace obvh {
namespace {

uint64_t edgeKey(uint32_t a, uint32_t b) {
  return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a;
}

}  // namespace

SubdivTopology::SubdivTopology(const SubdivMeshInput& input)
    : faceSize_(input.faceSizes), indices_(input.indices) {
  const uint32_t faces = uint32_t(faceSize_.size());
  // Each face takes its size's indices even when invalid; starts past the index buffer (or the
  // 32-bit range) leave the faces from there on invalid.
  const uint64_t pastEnd = uint64_t(indices_.size()) + 1;
  faceStart_.resize(faces + 1, 0);
  for (uint32_t f = 0; f < faces; ++f)
    faceStart_[f + 1] = uint32_t(std::min<uint64_t>(uint64_t(faceStart_[f]) + faceSize_[f], pastEnd));
  halfEdgeFace_.assign(indices_.size(), kNone);
  present_.assign(faces, 0);
  drawn_.assign(faces, 0);
  for (uint32_t f = 0; f < faces; ++f) {
    bool ok = faceSize_[f] >= 3 && faceSize_[f] <= 15 && faceStart_[f + 1] <= indices_.size();
    for (uint32_t h = faceStart_[f]; ok && h < faceStart_[f + 1]; ++h) {
      const uint32_t v = indices_[h];
      ok = v < input.vertexCount && (input.vertexValid.empty() || input.vertexValid[v]);
    }
    present_[f] = ok;
  }
  for (uint32_t hole : input.holes)
    if (hole < faces) present_[hole] = 0;
  for (uint32_t f = 0; f < faces; ++f)
    if (present_[f])
      for (uint32_t h = faceStart_[f]; h < faceStart_[f + 1]; ++h) halfEdgeFace_[h] = f;

  // Opposite half-edges: an edge of exactly two present faces, in opposite directions; any other
  // edge (boundary or non-manifold) is a boundary of each face that has it.
  std::unordered_map<uint64_t, std::vector<uint32_t>> edges;
  edges.reserve(indices_.size());
  for (uint32_t h = 0; h < indices_.size(); ++h)
    if (halfEdgeFace_[h] != kNone) edges[edgeKey(indices_[h], indices_[next(h)])].push_back(h);
  opposite_.assign(indices_.size(), kNone);
  for (const auto& [key, list] : edges) {
    if (list.size() != 2) continue;
    const uint32_t a = list[0], b = list[1];
    if (indices_[a] == indices_[b]) continue;  // same direction: inconsistent orientation
    opposite_[a] = b, opposite_[b] = a;
  }

  std::unordered_map<uint64_t, float> creases;
  for (size_t i = 0; 2 * i + 1 < input.edgeCreases.size() && i < input.edgeCreaseWeights.size(); ++i)
    creases[edgeKey(input.edgeCreases[2 * i], input.edgeCreases[2 * i + 1])] = input.edgeCreaseWeights[i];
  const bool pinAll = input.boundary == SubdivBoundary::PinAll;
  edgeSharpness_.assign(indices_.size(), 0.f);
  for (uint32_t h = 0; h < indices_.size(); ++h) {
    if (halfEdgeFace_[h] == kNone) continue;
    if (opposite_[h] == kNone || pinAll) {
      edgeSharpness_[h] = kInfiniteSharpness;
      continue;
    }
    const auto it = creases.find(edgeKey(indices_[h], indices_[next(h)]));
    if (it != creases.end() && it->second > 0.f) edgeSharpness_[h] = it->second;
  }

  vertexSharpness_.assign(input.vertexCount, 0.f);
  for (size_t i = 0; i < input.vertexCreases.size() && i < input.vertexCreaseWeights.size(); ++i)
    if (input.vertexCreases[i] < input.vertexCount)
      vertexSharpness_[input.vertexCreases[i]] = std::max(0.f, input.vertexCreaseWeights[i]);

  // Faces around each vertex, and how many boundary edges meet there.
  std::vector<uint32_t> boundaryEdges(input.vertexCount, 0);
  vertexFaceStart_.assign(input.vertexCount + 1, 0);
  for (uint32_t h = 0; h < indices_.size(); ++h) {
    if (halfEdgeFace_[h] == kNone) continue;
    ++vertexFaceStart_[indices_[h] + 1];
    if (opposite_[h] == kNone) ++boundaryEdges[indices_[h]], ++boundaryEdges[indices_[next(h)]];
  }
  for (uint32_t v = 0; v < input.vertexCount; ++v) vertexFaceStart_[v + 1] += vertexFaceStart_[v];
  vertexFaces_.resize(vertexFaceStart_.back());
  std::vector<uint32_t> fill(vertexFaceStart_.begin(), vertexFaceStart_.end() - 1);
  for (uint32_t h = 0; h < indices_.size(); ++h)
    if (halfEdgeFace_[h] != kNone) vertexFaces_[fill[indices_[h]]++] = halfEdgeFace_[h];

  for (uint32_t v = 0; v < input.vertexCount; ++v) {
    const uint32_t facesHere = vertexFaceStart_[v + 1] - vertexFaceStart_[v];
    const bool onBoundary = boundaryEdges[v] > 0;
    const bool pin = pinAll || (onBoundary && input.boundary == SubdivBoundary::PinBoundary) ||
                     (onBoundary && facesHere == 1 && input.boundary == SubdivBoundary::PinCorners);
    if (pin) vertexSharpness_[v] = kInfiniteSharpness;
  }

  for (uint32_t f = 0; f < faces; ++f) {
    bool draw = present_[f] != 0;
    if (draw && input.boundary == SubdivBoundary::None)
      for (uint32_t h = faceStart_[f]; h < faceStart_[f + 1]; ++h)
        if (opposite_[h] == kNone) draw = false;
    drawn_[f] = draw;
  }
}

uint32_t SubdivTopology::faceOfEdge(uint32_t h) const {
  return uint32_t(std::upper_bound(faceStart_.begin(), faceStart_.end(), h) - faceStart_.begin() - 1);
}

uint32_t SubdivTopology::next(uint32_t h) const {
  const uint32_t f = faceOfEdge(h);
  return h + 1 == faceStart_[f + 1] ? faceStart_[f] : h + 1;
}

uint32_t SubdivTopology::previous(uint32_t h) const {
  const uint32_t f = faceOfEdge(h);
  return h == faceStart_[f] ? faceStart_[f + 1] - 1 : h - 1;
}

}  // namespace obvh
