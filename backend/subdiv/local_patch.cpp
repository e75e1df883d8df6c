#include "subdiv/local_patch.h"

#include <algorithm>
#include <cmath>

namespace obvh {
namespace {

uint64_t edgeKey(int a, int b) {
  const uint32_t lo = uint32_t(std::min(a, b)), hi = uint32_t(std::max(a, b));
  return (uint64_t(lo) << 32) | hi;
}

float decremented(float sharpness) { return sharpness > 1.f ? sharpness - 1.f : 0.f; }

// A run of indices in one of Adjacency's flat lists.
struct IndexSpan {
  const int* first;
  const int* last;
  const int* begin() const { return first; }
  const int* end() const { return last; }
  size_t size() const { return size_t(last - first); }
};

// Edges and incidences of a patch, for one subdivision step or a regularity check. Flat lists
// (patches are small and built many times a face: allocations, not arithmetic, were the cost).
struct Adjacency {
  struct Edge {
    int a = 0, b = 0;
    int faces[2] = {-1, -1};
    int faceCount = 0;
    float sharpness = 0.f;
  };
  std::vector<Edge> edges;
  std::vector<int> cornerEdge;                    // per face corner i: the edge (i, i + 1)
  std::vector<std::pair<uint64_t, int>> byKey;    // (edge key, edge), sorted by key
  std::vector<int> edgeStart, edgeList;           // per vertex: its edges
  std::vector<int> faceStart, faceList;           // per vertex: its faces (once per corner)

  explicit Adjacency(const LocalPatch& p) : cornerEdge(p.faceVertices.size()) {
    const int nv = p.vertexCount();
    std::vector<std::pair<uint64_t, int>> corners;  // (edge key, corner)
    std::vector<int> faceOfCorner(p.faceVertices.size());
    corners.reserve(p.faceVertices.size());
    for (int f = 0; f < p.faceCount(); ++f) {
      const uint32_t start = p.faceStart[f], n = p.faceStart[f + 1] - start;
      for (uint32_t i = 0; i < n; ++i) {
        const int a = p.faceVertices[start + i], b = p.faceVertices[start + (i + 1) % n];
        corners.emplace_back(edgeKey(a, b), int(start + i));
        faceOfCorner[start + i] = f;
      }
    }
    std::sort(corners.begin(), corners.end());
    for (size_t k = 0; k < corners.size(); ++k) {
      const int corner = corners[k].second;
      if (k == 0 || corners[k].first != corners[k - 1].first) {
        const int f = faceOfCorner[corner];
        const uint32_t start = p.faceStart[f], n = p.faceStart[f + 1] - start;
        Edge e;
        e.a = p.faceVertices[corner];
        e.b = p.faceVertices[start + (uint32_t(corner) - start + 1) % n];
        e.sharpness = p.sharpness(e.a, e.b);
        byKey.emplace_back(corners[k].first, int(edges.size()));
        edges.push_back(e);
      }
      Edge& e = edges.back();
      if (e.faceCount < 2) e.faces[e.faceCount] = faceOfCorner[corner];
      ++e.faceCount;
      cornerEdge[corner] = int(edges.size()) - 1;
    }
    edgeStart.assign(nv + 1, 0);
    faceStart.assign(nv + 1, 0);
    for (const Edge& e : edges) ++edgeStart[e.a + 1], ++edgeStart[e.b + 1];
    for (int v : p.faceVertices) ++faceStart[v + 1];
    for (int v = 0; v < nv; ++v) edgeStart[v + 1] += edgeStart[v], faceStart[v + 1] += faceStart[v];
    edgeList.resize(edgeStart.back());
    faceList.resize(faceStart.back());
    std::vector<int> edgeFill(edgeStart.begin(), edgeStart.end() - 1), faceFill(faceStart.begin(), faceStart.end() - 1);
    for (int e = 0; e < int(edges.size()); ++e) edgeList[edgeFill[edges[e].a]++] = e, edgeList[edgeFill[edges[e].b]++] = e;
    for (size_t c = 0; c < p.faceVertices.size(); ++c) faceList[faceFill[p.faceVertices[c]]++] = faceOfCorner[c];
  }
  IndexSpan vertexEdges(int v) const { return {edgeList.data() + edgeStart[v], edgeList.data() + edgeStart[v + 1]}; }
  IndexSpan vertexFaces(int v) const { return {faceList.data() + faceStart[v], faceList.data() + faceStart[v + 1]}; }
  int edge(int a, int b) const {
    const uint64_t key = edgeKey(a, b);
    const auto it = std::lower_bound(byKey.begin(), byKey.end(), std::make_pair(key, 0));
    return it != byKey.end() && it->first == key ? it->second : -1;
  }
  int otherFace(int a, int b, int face) const {
    const int e = edge(a, b);
    if (e < 0 || edges[e].faceCount != 2) return -1;
    return edges[e].faces[0] == face ? edges[e].faces[1] : edges[e].faces[0];
  }
  int otherEnd(int e, int v) const { return edges[e].a == v ? edges[e].b : edges[e].a; }
};

enum class VertexRule { Smooth, Crease, Corner };

VertexRule ruleFor(int sharpEdges, float vertexSharpness) {
  if (vertexSharpness > 0.f || sharpEdges > 2) return VertexRule::Corner;
  return sharpEdges == 2 ? VertexRule::Crease : VertexRule::Smooth;
}

void addScaled(double* out, const double* in, double scale, int dim) {
  for (int k = 0; k < dim; ++k) out[k] += scale * in[k];
}

}  // namespace

LocalPatch subdivide(const LocalPatch& p) {
  const Adjacency adj(p);
  const int nv = p.vertexCount(), ne = int(adj.edges.size()), nf = p.faceCount(), dim = p.dim;
  LocalPatch c;
  c.dim = dim;
  const int total = nv + ne + nf;
  c.values.assign(size_t(total) * dim, 0.0);
  c.vertexSharpness.assign(total, 0.f);
  auto out = [&](int v) { return c.values.data() + size_t(v) * dim; };
  const int edgeBase = nv, faceBase = nv + ne;

  for (int f = 0; f < nf; ++f) {
    const uint32_t start = p.faceStart[f], n = p.faceStart[f + 1] - start;
    for (uint32_t i = 0; i < n; ++i) addScaled(out(faceBase + f), p.value(p.faceVertices[start + i]), 1.0 / n, dim);
  }
  for (int e = 0; e < ne; ++e) {
    const Adjacency::Edge& edge = adj.edges[e];
    double* o = out(edgeBase + e);
    const bool smoothPossible = edge.faceCount == 2 && edge.sharpness < 1.f;
    const double sharpWeight = smoothPossible ? edge.sharpness : 1.0;
    addScaled(o, p.value(edge.a), 0.5 * sharpWeight, dim);
    addScaled(o, p.value(edge.b), 0.5 * sharpWeight, dim);
    if (smoothPossible) {
      const double w = 0.25 * (1.0 - sharpWeight);
      addScaled(o, p.value(edge.a), w, dim);
      addScaled(o, p.value(edge.b), w, dim);
      addScaled(o, out(faceBase + edge.faces[0]), w, dim);
      addScaled(o, out(faceBase + edge.faces[1]), w, dim);
    }
  }
  std::vector<double> parentPos(dim), childPos(dim);
  for (int v = 0; v < nv; ++v) {
    const IndexSpan vEdges = adj.vertexEdges(v);
    const IndexSpan vFaces = adj.vertexFaces(v);
    const float sv = p.vertexSharpness[v];
    c.vertexSharpness[v] = decremented(sv);
    int sharpNow = 0, sharpNext = 0;
    double sharpSum = 0.0;
    for (int e : vEdges) {
      const float s = adj.edges[e].sharpness;
      if (s > 0.f) ++sharpNow, sharpSum += std::min(1.f, s);
      if (s > 1.f) ++sharpNext;
    }
    auto positionBy = [&](VertexRule rule, float minimumSharpness, double* pos) {
      std::fill(pos, pos + dim, 0.0);
      const size_t n = vEdges.size();
      if (rule == VertexRule::Corner || n < 2 || (rule == VertexRule::Smooth && vFaces.size() != n)) {
        addScaled(pos, p.value(v), 1.0, dim);
        return;
      }
      if (rule == VertexRule::Crease) {
        addScaled(pos, p.value(v), 0.75, dim);
        for (int e : vEdges)
          if (adj.edges[e].sharpness > minimumSharpness) addScaled(pos, p.value(adj.otherEnd(e, v)), 0.125, dim);
        return;
      }
      const double inv = 1.0 / double(n);
      addScaled(pos, p.value(v), double(n - 2) * inv, dim);
      for (int e : vEdges) addScaled(pos, p.value(adj.otherEnd(e, v)), inv * inv, dim);
      for (int f : vFaces) addScaled(pos, out(faceBase + f), inv * inv, dim);
    };
    const VertexRule now = ruleFor(sharpNow, sv), next = ruleFor(sharpNext, decremented(sv));
    positionBy(now, 0.f, parentPos.data());
    double* o = out(v);
    if (now == next) {
      addScaled(o, parentPos.data(), 1.0, dim);
      continue;
    }
    // A semi-sharp feature fading out: blend the two rules by its sharpness.
    positionBy(next, 1.f, childPos.data());
    const double fraction = sv > 0.f ? std::min(1.0, double(sv)) : (sharpNow > 0 ? sharpSum / sharpNow : 0.0);
    addScaled(o, parentPos.data(), fraction, dim);
    addScaled(o, childPos.data(), 1.0 - fraction, dim);
  }
  for (int e = 0; e < ne; ++e) {
    const Adjacency::Edge& edge = adj.edges[e];
    const float s = decremented(edge.sharpness);
    if (s <= 0.f) continue;
    c.edgeSharpness[edgeKey(edge.a, edgeBase + e)] = s;
    c.edgeSharpness[edgeKey(edgeBase + e, edge.b)] = s;
  }
  for (int f = 0; f < nf; ++f) {
    const uint32_t start = p.faceStart[f], n = p.faceStart[f + 1] - start;
    for (uint32_t i = 0; i < n; ++i) {
      c.faceVertices.push_back(p.faceVertices[start + i]);
      c.faceVertices.push_back(edgeBase + adj.cornerEdge[start + i]);
      c.faceVertices.push_back(faceBase + f);
      c.faceVertices.push_back(edgeBase + adj.cornerEdge[start + (i + n - 1) % n]);
      c.faceStart.push_back(uint32_t(c.faceVertices.size()));
    }
  }
  return c;
}

namespace {

// The 1-ring of face `target` of c, with that face first and its vertices in the order given.
LocalPatch extractRing(const LocalPatch& c, int target, const int quad[4]) {
  LocalPatch r;
  r.dim = c.dim;
  std::vector<int> local(c.vertexCount(), -1);
  auto localVertex = [&](int v) {
    if (local[v] < 0) {
      local[v] = r.vertexCount();
      r.vertexSharpness.push_back(c.vertexSharpness[v]);
      r.values.insert(r.values.end(), c.value(v), c.value(v) + c.dim);
    }
    return local[v];
  };
  auto addFace = [&](const int* vertices, uint32_t n) {
    for (uint32_t i = 0; i < n; ++i) r.faceVertices.push_back(localVertex(vertices[i]));
    for (uint32_t i = 0; i < n; ++i) {
      const float s = c.sharpness(vertices[i], vertices[(i + 1) % n]);
      if (s > 0.f) r.edgeSharpness[edgeKey(local[vertices[i]], local[vertices[(i + 1) % n]])] = s;
    }
    r.faceStart.push_back(uint32_t(r.faceVertices.size()));
  };
  addFace(quad, 4);
  for (int f = 0; f < c.faceCount(); ++f) {
    if (f == target) continue;
    const uint32_t start = c.faceStart[f], n = c.faceStart[f + 1] - start;
    const int* vertices = c.faceVertices.data() + start;
    const bool touches = std::any_of(vertices, vertices + n, [&](int v) {
      return v == quad[0] || v == quad[1] || v == quad[2] || v == quad[3];
    });
    if (touches) addFace(vertices, n);
  }
  return r;
}

}  // namespace

float LocalPatch::sharpness(int a, int b) const {
  const auto it = edgeSharpness.find(edgeKey(a, b));
  return it == edgeSharpness.end() ? 0.f : it->second;
}

LocalPatch ringOfFace(const SubdivTopology& topology, uint32_t face, int dim, ControlValues read, const void* context) {
  LocalPatch p;
  p.dim = dim;
  std::unordered_map<uint32_t, int> local;
  auto localVertex = [&](uint32_t g) {
    const auto [it, inserted] = local.emplace(g, p.vertexCount());
    if (inserted) {
      p.vertexSharpness.push_back(topology.vertexSharpness(g));
      p.values.resize(p.values.size() + dim);
      read(context, g, p.values.data() + size_t(it->second) * dim);
    }
    return it->second;
  };
  auto addFace = [&](uint32_t f) {
    const uint32_t first = topology.firstHalfEdge(f), n = topology.faceSize(f);
    for (uint32_t i = 0; i < n; ++i) p.faceVertices.push_back(localVertex(topology.vertexOf(first + i)));
    for (uint32_t i = 0; i < n; ++i) {
      const float s = topology.edgeSharpness(first + i);
      if (s > 0.f)
        p.edgeSharpness[edgeKey(localVertex(topology.vertexOf(first + i)),
                                localVertex(topology.vertexOf(first + (i + 1) % n)))] = s;
    }
    p.faceStart.push_back(uint32_t(p.faceVertices.size()));
  };
  addFace(face);
  std::vector<uint32_t> added{face};
  for (uint32_t i = 0; i < topology.faceSize(face); ++i) {
    uint32_t count = 0;
    const uint32_t* faces = topology.facesAround(topology.vertexOf(topology.firstHalfEdge(face) + i), count);
    for (uint32_t k = 0; k < count; ++k) {
      if (std::find(added.begin(), added.end(), faces[k]) != added.end()) continue;
      added.push_back(faces[k]);
      addFace(faces[k]);
    }
  }
  return p;
}

LocalPatch quadrantChild(const LocalPatch& c, int qu, int qv) {
  // Child i of face 0 is (corner i, edge point i, face point, edge point i - 1); rotate it so that
  // its first vertex sits at the quadrant's lowest (u, v).
  static const int kChild[2][2] = {{0, 3}, {1, 2}};  // [qu][qv]
  static const int kStart[4] = {0, 3, 2, 1};
  const int child = kChild[qu][qv];
  const int* v = c.faceVertices.data() + c.faceStart[child];
  int quad[4];
  for (int i = 0; i < 4; ++i) quad[i] = v[(kStart[child] + i) % 4];
  return extractRing(c, child, quad);
}

LocalPatch cornerChild(const LocalPatch& c, int corner) {
  const int* v = c.faceVertices.data() + c.faceStart[corner];
  const int quad[4] = {v[0], v[1], v[2], v[3]};
  return extractRing(c, corner, quad);
}

namespace {

// Position in a face's vertex list, or -1.
int indexIn(const LocalPatch& p, int face, int vertex) {
  const uint32_t start = p.faceStart[face], n = p.faceStart[face + 1] - start;
  for (uint32_t i = 0; i < n; ++i)
    if (p.faceVertices[start + i] == vertex) return int(i);
  return -1;
}
int vertexAt(const LocalPatch& p, int face, int index) {
  const uint32_t start = p.faceStart[face], n = p.faceStart[face + 1] - start;
  return p.faceVertices[start + uint32_t((index % int(n) + int(n)) % int(n))];
}
bool isQuad(const LocalPatch& p, int face) { return face >= 0 && p.faceStart[face + 1] - p.faceStart[face] == 4; }

// Grid cells of each corner's vertex V and outer points N', P', z, x, w (see regularControlGrid).
constexpr int kCornerCells[4][6] = {
    {5, 4, 1, 0, 8, 2}, {6, 2, 7, 3, 1, 11}, {10, 11, 14, 15, 7, 13}, {9, 13, 8, 12, 14, 4}};

}  // namespace

bool regularControlGrid(const LocalPatch& p, std::vector<double>& grid) {
  if (!isQuad(p, 0)) return false;
  const Adjacency adj(p);
  const int dim = p.dim;
  grid.assign(16 * size_t(dim), 0.0);
  const int* q = p.faceVertices.data();
  auto set = [&](int cell, std::initializer_list<std::pair<int, double>> terms) {
    double* o = grid.data() + size_t(cell) * dim;
    std::fill(o, o + dim, 0.0);
    for (const auto& [vertex, weight] : terms) addScaled(o, p.value(vertex), weight, dim);
  };
  for (int k = 0; k < 4; ++k) {
    const int V = q[k], N = q[(k + 1) % 4], D = q[(k + 2) % 4], P = q[(k + 3) % 4];
    const float sv = p.vertexSharpness[V];
    int sharp = 0;
    bool fractional = false;
    for (int e : adj.vertexEdges(V)) {
      const float s = adj.edges[e].sharpness;
      if (s > 0.f) ++sharp;
      if (s > 0.f && std::isfinite(s)) fractional = true;
    }
    if (fractional || (sv > 0.f && std::isfinite(sv))) return false;
    const bool sharpVN = p.sharpness(V, N) > 0.f, sharpVP = p.sharpness(V, P) > 0.f;
    const int* cells = kCornerCells[k];
    set(cells[0], {{V, 1.0}});
    if (!sharpVN && !sharpVP) {
      if (sv > 0.f || sharp != 0 || adj.vertexEdges(V).size() != 4 || adj.vertexFaces(V).size() != 4) return false;
      const int f1 = adj.otherFace(V, P, 0), f3 = adj.otherFace(V, N, 0);
      if (!isQuad(p, f1) || !isQuad(p, f3)) return false;
      const int i1 = indexIn(p, f1, V), i3 = indexIn(p, f3, V);
      if (vertexAt(p, f1, i1 + 1) != P || vertexAt(p, f3, i3 - 1) != N) return false;
      const int x = vertexAt(p, f1, i1 + 2), nOut = vertexAt(p, f1, i1 + 3);
      const int pOut = vertexAt(p, f3, i3 + 1), w = vertexAt(p, f3, i3 + 2);
      const int f2 = adj.otherFace(V, nOut, f1);
      if (!isQuad(p, f2)) return false;
      const int i2 = indexIn(p, f2, V);
      if (vertexAt(p, f2, i2 + 1) != nOut || vertexAt(p, f2, i2 + 3) != pOut) return false;
      set(cells[1], {{nOut, 1.0}});
      set(cells[2], {{pOut, 1.0}});
      set(cells[3], {{vertexAt(p, f2, i2 + 2), 1.0}});
      set(cells[4], {{x, 1.0}});
      set(cells[5], {{w, 1.0}});
    } else if (sharpVN && !sharpVP) {
      if (sv > 0.f || sharp != 2) return false;
      const int f1 = adj.otherFace(V, P, 0);
      if (!isQuad(p, f1)) return false;
      const int i1 = indexIn(p, f1, V);
      if (vertexAt(p, f1, i1 + 1) != P) return false;
      const int x = vertexAt(p, f1, i1 + 2), nOut = vertexAt(p, f1, i1 + 3);
      if (p.sharpness(V, nOut) <= 0.f) return false;
      set(cells[1], {{nOut, 1.0}});
      set(cells[2], {{V, 2.0}, {P, -1.0}});
      set(cells[3], {{nOut, 2.0}, {x, -1.0}});
      set(cells[4], {{x, 1.0}});
      set(cells[5], {{N, 2.0}, {D, -1.0}});
    } else if (!sharpVN && sharpVP) {
      if (sv > 0.f || sharp != 2) return false;
      const int f3 = adj.otherFace(V, N, 0);
      if (!isQuad(p, f3)) return false;
      const int i3 = indexIn(p, f3, V);
      if (vertexAt(p, f3, i3 - 1) != N) return false;
      const int pOut = vertexAt(p, f3, i3 + 1), w = vertexAt(p, f3, i3 + 2);
      if (p.sharpness(V, pOut) <= 0.f) return false;
      set(cells[1], {{V, 2.0}, {N, -1.0}});
      set(cells[2], {{pOut, 1.0}});
      set(cells[3], {{pOut, 2.0}, {w, -1.0}});
      set(cells[4], {{P, 2.0}, {D, -1.0}});
      set(cells[5], {{w, 1.0}});
    } else {
      if (!(sv > 0.f) && sharp < 3) return false;  // a crease rule would round this corner
      set(cells[1], {{V, 2.0}, {N, -1.0}});
      set(cells[2], {{V, 2.0}, {P, -1.0}});
      set(cells[3], {{V, 4.0}, {N, -2.0}, {P, -2.0}, {D, 1.0}});
      set(cells[4], {{P, 2.0}, {D, -1.0}});
      set(cells[5], {{N, 2.0}, {D, -1.0}});
    }
  }
  return true;
}

void cornerLimits(const LocalPatch& p, std::vector<double>& corners) {
  const Adjacency adj(p);
  const int dim = p.dim;
  corners.assign(4 * size_t(dim), 0.0);
  for (int k = 0; k < 4; ++k) {
    const int V = p.faceVertices[k];
    double* o = corners.data() + size_t(k) * dim;
    const IndexSpan vEdges = adj.vertexEdges(V);
    const IndexSpan vFaces = adj.vertexFaces(V);
    int sharp = 0;
    for (int e : vEdges) sharp += adj.edges[e].sharpness > 0.f;
    const VertexRule rule = ruleFor(sharp, p.vertexSharpness[V]);
    const size_t n = vEdges.size();
    if (rule == VertexRule::Corner || (rule == VertexRule::Smooth && vFaces.size() != n) || n < 2) {
      addScaled(o, p.value(V), 1.0, dim);
    } else if (rule == VertexRule::Crease) {
      addScaled(o, p.value(V), 4.0 / 6.0, dim);
      for (int e : vEdges)
        if (adj.edges[e].sharpness > 0.f) addScaled(o, p.value(adj.otherEnd(e, V)), 1.0 / 6.0, dim);
    } else {
      const double denominator = double(n) * double(n + 5);
      addScaled(o, p.value(V), double(n * n) / denominator, dim);
      for (int e : vEdges) addScaled(o, p.value(adj.otherEnd(e, V)), 4.0 / denominator, dim);
      for (int f : vFaces) addScaled(o, p.value(vertexAt(p, f, indexIn(p, f, V) + 2)), 1.0 / denominator, dim);
    }
  }
}

}  // namespace obvh
