#include "subdiv/subdiv_tessellation.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "subdiv/patch_eval.h"

namespace obvh {
namespace {

// Where a grid point lies when it is shared with other grids: a control vertex's limit point, a
// point along a mesh edge (t from the start of the edge's canonical half-edge), along an edge
// between two subpatches of one face, or a face's centre.
struct SharedPoint {
  enum Kind : uint32_t { Vertex, MeshEdge, SubpatchEdge, FaceCentre } kind;
  uint32_t id = 0;
  uint32_t numerator = 0, denominator = 1;
  bool operator==(const SharedPoint& o) const {
    return kind == o.kind && id == o.id && numerator == o.numerator && denominator == o.denominator;
  }
};
struct SharedPointHash {
  size_t operator()(const SharedPoint& p) const {
    uint64_t h = (uint64_t(p.kind) << 60) ^ (uint64_t(p.id) << 24) ^ (uint64_t(p.numerator) << 12) ^ p.denominator;
    return std::hash<uint64_t>()(h * 0x9E3779B97F4A7C15ull);
  }
};

// A point t = numerator / denominator along half-edge h, named by the edge's canonical half-edge
// (the smaller of the pair); the ends are the edge's vertices.
SharedPoint onMeshEdge(const SubdivTopology& topology, uint32_t h, uint32_t numerator, uint32_t denominator) {
  const uint32_t g = std::gcd(numerator, denominator);
  numerator /= g, denominator /= g;
  if (numerator == 0) return {SharedPoint::Vertex, topology.vertexOf(h), 0, 1};
  if (numerator == denominator) return {SharedPoint::Vertex, topology.vertexOf(topology.next(h)), 0, 1};
  const uint32_t o = topology.opposite(h);
  if (o != SubdivTopology::kNone && o < h) return {SharedPoint::MeshEdge, o, denominator - numerator, denominator};
  return {SharedPoint::MeshEdge, h, numerator, denominator};
}

// The grid of one patch: its resolution, its points' (u, v) and, for boundary points, where they
// are shared.
struct PatchGrid {
  uint32_t face = 0;
  int subpatch = -1;          // -1: the quad face itself
  int columns = 1, rows = 1;  // cells along u and v
  std::vector<double> u, v;
  std::vector<SharedPoint> shared;  // per point: where it is shared, when isShared says it is
  std::vector<uint8_t> isShared;
  std::vector<double> positions;    // 3 per point
};

// The parameter of grid point i of `cells` on an edge of `segments` segments: the nearest of the
// edge's own points (Embree's stitching of coarser edges).
uint32_t stitched(int i, int cells, int segments) {
  if (segments >= cells) return uint32_t(i);
  return uint32_t(std::floor(double(i) * segments / cells + 0.5));
}

void setShared(PatchGrid& grid, int i, int j, const SharedPoint& p) {
  const size_t k = size_t(j) * (grid.columns + 1) + i;
  grid.shared[k] = p;
  grid.isShared[k] = 1;
}

// Fills a grid's (u, v) and shared points. edges[e]: segments of the grid's edge e (0: v = 0,
// 1: u = 1, 2: v = 1, 3: u = 0), and how each edge's points are named.
template <typename NameEdgePoint>
void layOutGrid(PatchGrid& grid, const int edges[4], NameEdgePoint name) {
  grid.columns = std::max(edges[0], edges[2]);
  grid.rows = std::max(edges[1], edges[3]);
  const size_t points = size_t(grid.columns + 1) * (grid.rows + 1);
  grid.u.resize(points), grid.v.resize(points), grid.shared.resize(points), grid.isShared.assign(points, 0);
  for (int j = 0; j <= grid.rows; ++j)
    for (int i = 0; i <= grid.columns; ++i) {
      double u = double(i) / grid.columns, v = double(j) / grid.rows;
      if (j == 0) u = double(stitched(i, grid.columns, edges[0])) / std::min(edges[0], grid.columns);
      if (j == grid.rows) u = double(stitched(i, grid.columns, edges[2])) / std::min(edges[2], grid.columns);
      if (i == 0) v = double(stitched(j, grid.rows, edges[3])) / std::min(edges[3], grid.rows);
      if (i == grid.columns) v = double(stitched(j, grid.rows, edges[1])) / std::min(edges[1], grid.rows);
      const size_t k = size_t(j) * (grid.columns + 1) + i;
      grid.u[k] = u, grid.v[k] = v;
    }
  // Edge e's point at stitched index s of its segments, walking the grid's boundary.
  for (int i = 0; i <= grid.columns; ++i) {
    const int s0 = edges[0] >= grid.columns ? i : int(stitched(i, grid.columns, edges[0]));
    const int s2 = edges[2] >= grid.columns ? i : int(stitched(i, grid.columns, edges[2]));
    setShared(grid, i, 0, name(0, s0, std::min(edges[0], grid.columns)));
    setShared(grid, i, grid.rows, name(2, std::min(edges[2], grid.columns) - s2, std::min(edges[2], grid.columns)));
  }
  for (int j = 0; j <= grid.rows; ++j) {
    const int s1 = edges[1] >= grid.rows ? j : int(stitched(j, grid.rows, edges[1]));
    const int s3 = edges[3] >= grid.rows ? j : int(stitched(j, grid.rows, edges[3]));
    setShared(grid, grid.columns, j, name(1, s1, std::min(edges[1], grid.rows)));
    setShared(grid, 0, j, name(3, std::min(edges[3], grid.rows) - s3, std::min(edges[3], grid.rows)));
  }
}

std::vector<PatchGrid> gridsOfFace(const SubdivTopology& topology, uint32_t face, const float* levels, float rate) {
  const uint32_t first = topology.firstHalfEdge(face), n = topology.faceSize(face);
  const auto level = [&](uint32_t h) { return levels ? levels[h] : rate; };
  std::vector<PatchGrid> grids;
  if (n == 4) {
    PatchGrid grid;
    grid.face = face;
    int edges[4];
    for (int e = 0; e < 4; ++e) {
      // An edge shared with a face of other than four vertices has that face's segments: two
      // halves of half the level each (else the two grids would crack apart).
      const uint32_t o = topology.opposite(first + e);
      const bool besideSubpatches = o != SubdivTopology::kNone && topology.faceSize(topology.faceOf(o)) != 4;
      edges[e] = besideSubpatches ? 2 * edgeSegments(0.5f * level(first + e)) : edgeSegments(level(first + e));
    }
    // Grid edge e runs along half-edge first + e; edges 2 and 3 run against the grid's u and v,
    // which layOutGrid has already turned into the half-edge's direction.
    layOutGrid(grid, edges, [&](int e, int s, int segments) {
      return onMeshEdge(topology, first + uint32_t(e), uint32_t(s), uint32_t(segments));
    });
    grids.push_back(std::move(grid));
    return grids;
  }
  // Subpatch k: corners (vertex k, middle of edge k, face centre, middle of edge k - 1); its outer
  // edges take half their mesh edge's level and so does the inner edge from the middle of edge k
  // (the closest of the rules tried against Embree for faces with differing levels).
  for (uint32_t k = 0; k < n; ++k) {
    PatchGrid grid;
    grid.face = face;
    grid.subpatch = int(k);
    const uint32_t hk = first + k, hPrev = first + (k + n - 1) % n;
    const int half = edgeSegments(0.5f * level(hk)), halfPrev = edgeSegments(0.5f * level(hPrev));
    const int edges[4] = {half, half, halfPrev, halfPrev};
    layOutGrid(grid, edges, [&](int e, int s, int segments) -> SharedPoint {
      switch (e) {
        case 0: return onMeshEdge(topology, hk, uint32_t(s), 2u * uint32_t(segments));
        case 3: return onMeshEdge(topology, hPrev, uint32_t(segments + s), 2u * uint32_t(segments));
        default: {
          // Inner edge k runs from the middle of edge k to the centre; edge 2 of this subpatch is
          // inner edge k - 1 walked from the centre.
          const uint32_t edge = e == 1 ? k : (k + n - 1) % n;
          const uint32_t t = e == 1 ? uint32_t(s) : uint32_t(segments - s);
          if (t == 0) return onMeshEdge(topology, first + edge, 1, 2);
          if (t == uint32_t(segments)) return {SharedPoint::FaceCentre, face, 0, 1};
          const uint32_t g = std::gcd(t, uint32_t(segments));
          return {SharedPoint::SubpatchEdge, first + edge, t / g, uint32_t(segments) / g};
        }
      }
    });
    grids.push_back(std::move(grid));
  }
  return grids;
}

}  // namespace

int edgeSegments(float level) {
  if (!(level >= 1.f)) return 1;
  return int(std::ceil(std::min(level, 4096.f)));
}

SubdivTessellation tessellateSubdivision(const SubdivTopology& topology, ControlValues readPosition,
                                         const void* context, const float* levels, float rate) {
  const uint32_t faces = topology.faceCount();
  std::vector<std::vector<PatchGrid>> perFace(faces);
  tbb::parallel_for(uint32_t(0), faces, [&](uint32_t f) {
    if (!topology.drawn(f)) return;
    perFace[f] = gridsOfFace(topology, f, levels, rate);
    for (PatchGrid& grid : perFace[f]) {
      const LocalPatch patch = facePatch(topology, f, std::max(grid.subpatch, 0), 3, readPosition, context);
      evaluatePatchPoints(patch, grid.u, grid.v, grid.positions);
    }
  });

  SubdivTessellation out;
  std::unordered_map<SharedPoint, Vec3f, SharedPointHash> sharedPositions;
  for (uint32_t f = 0; f < faces; ++f) {
    for (const PatchGrid& grid : perFace[f]) {
      const uint32_t base = uint32_t(out.vertices.size());
      for (size_t k = 0; k < grid.u.size(); ++k) {
        const Vec3f p{float(grid.positions[3 * k]), float(grid.positions[3 * k + 1]), float(grid.positions[3 * k + 2])};
        if (!grid.isShared[k]) {
          out.vertices.push_back(p);
          continue;
        }
        out.vertices.push_back(sharedPositions.emplace(grid.shared[k], p).first->second);
      }
      // Subpatch (u, v) are encoded as Embree encodes them: U = 2 (k mod 4) + 0.5 + u, V alike with k / 4.
      const float uOffset = grid.subpatch < 0 ? 0.f : 2.f * float(grid.subpatch % 4) + 0.5f;
      const float vOffset = grid.subpatch < 0 ? 0.f : 2.f * float(grid.subpatch / 4) + 0.5f;
      const int width = grid.columns + 1;
      for (int j = 0; j < grid.rows; ++j)
        for (int i = 0; i < grid.columns; ++i) {
          const uint32_t corner[4] = {uint32_t(j * width + i), uint32_t(j * width + i + 1),
                                      uint32_t((j + 1) * width + i + 1), uint32_t((j + 1) * width + i)};
          SubdivCell cell;
          cell.facePrimID = f;
          for (int c = 0; c < 4; ++c) {
            out.cellCorners.push_back(base + corner[c]);
            cell.u[c] = uOffset + float(grid.u[corner[c]]);
            cell.v[c] = vOffset + float(grid.v[corner[c]]);
          }
          out.cells.push_back(cell);
        }
    }
  }
  return out;
}

}  // namespace obvh
