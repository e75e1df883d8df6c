// The buffers and settings only subdivision geometries (RTC_GEOMETRY_TYPE_SUBDIVISION) have, and
// what a commit derives from them: the control mesh of each topology and the tessellation the
// scene traces.
#pragma once

#include <embree3/rtcore.h>

#include <memory>
#include <vector>

#include "buffer.h"
#include "subdiv/subdiv_tessellation.h"
#include "subdiv/subdiv_topology.h"

namespace obvh::api {

class SubdivisionGeometry {
 public:
  // True for the buffer types a subdivision geometry has beyond vertices and attributes.
  static bool ownsBufferType(int type);
  // Embree's checks of a buffer binding (slot, then format); throws its error codes.
  void checkBinding(int type, unsigned slot, int format) const;
  BufferView& view(int type, unsigned slot);

  void setTopologyCount(unsigned count);
  void setMode(unsigned topology, int mode);
  void setAttributeTopology(unsigned attribute, unsigned topology, unsigned attributeCount);
  unsigned attributeTopology(unsigned attribute) const;
  void setTessellationRate(float rate) { rate_ = rate; }

  // Builds every topology's control mesh and the tessellation of the vertices of each time step
  // (one cell structure; a face invalid at any step is left out at all).
  void commit(const std::vector<BufferView>& timeSteps);
  // Null until a commit with every buffer it needs.
  const SubdivTopology* topology(unsigned slot) const;
  const SubdivTessellation* tessellation() const { return tessellation_.get(); }
  // The tessellation's vertices at time steps 1, 2, ... (motion blur).
  const std::vector<std::vector<Vec3f>>& laterSteps() const { return laterSteps_; }

 private:
  SubdivMeshInput inputOf(unsigned topology, uint32_t vertexCount) const;

  BufferView faces_;
  std::vector<BufferView> indices_{1};  // per topology
  std::vector<int> modes_{RTC_SUBDIVISION_MODE_SMOOTH_BOUNDARY};
  std::vector<unsigned> attributeTopology_;
  BufferView edgeCreaseIndices_, edgeCreaseWeights_, vertexCreaseIndices_, vertexCreaseWeights_, holes_, levels_;
  float rate_ = 2.f;  // Embree's default: two segments an edge (measured)
  std::vector<std::shared_ptr<const SubdivTopology>> topologies_;
  std::shared_ptr<const SubdivTessellation> tessellation_;
  std::vector<std::vector<Vec3f>> laterSteps_;
};

}  // namespace obvh::api
