#include "procedural_meshes.h"

#include <algorithm>
#include <cmath>
#include <array>
#include <map>
#include <random>
#include <utility>

namespace obvh::tools {

MeshData randomTriangleSoup(size_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  MeshData mesh;
  for (size_t i = 0; i < count; ++i) {
    const float size = 0.005f * std::pow(100.f, unit(rng));
    const float c[3] = {unit(rng), unit(rng), unit(rng)};
    for (int v = 0; v < 3; ++v) {
      for (int k = 0; k < 3; ++k) mesh.vertices.push_back(c[k] + (unit(rng) - 0.5f) * size);
      mesh.indices.push_back(uint32_t(3 * i + v));
    }
  }
  return mesh;
}

MeshData icosphere(int subdivisions, float radius, const float center[3]) {
  const float t = (1.f + std::sqrt(5.f)) / 2.f;
  std::vector<std::array<float, 3>> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<uint32_t, 3>> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7},  {0, 7, 10}, {0, 10, 11},
                                            {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                            {3, 9, 4},  {3, 4, 2},  {3, 2, 6},  {3, 6, 8},  {3, 8, 9},
                                            {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},  {9, 8, 1}};
  auto normalizeVertex = [](std::array<float, 3> p) {
    const float l = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    return std::array<float, 3>{p[0] / l, p[1] / l, p[2] / l};
  };
  for (auto& p : v) p = normalizeVertex(p);
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoints;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = midpoints.find(key);
      if (it != midpoints.end()) return it->second;
      v.push_back(normalizeVertex({(v[a][0] + v[b][0]) / 2, (v[a][1] + v[b][1]) / 2, (v[a][2] + v[b][2]) / 2}));
      return midpoints[key] = uint32_t(v.size() - 1);
    };
    std::vector<std::array<uint32_t, 3>> next;
    for (const auto& tri : f) {
      const uint32_t a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]), c = midpoint(tri[2], tri[0]);
      next.push_back({tri[0], a, c});
      next.push_back({tri[1], b, a});
      next.push_back({tri[2], c, b});
      next.push_back({a, b, c});
    }
    f = std::move(next);
  }
  MeshData mesh;
  for (const auto& p : v)
    for (int k = 0; k < 3; ++k) mesh.vertices.push_back(center[k] + radius * p[k]);
  for (const auto& tri : f) mesh.indices.insert(mesh.indices.end(), tri.begin(), tri.end());
  return mesh;
}

MeshData box(const float lo[3], const float hi[3], bool asQuads) {
  MeshData mesh;
  for (int i = 0; i < 8; ++i) {
    mesh.vertices.push_back(i & 1 ? hi[0] : lo[0]);
    mesh.vertices.push_back(i & 2 ? hi[1] : lo[1]);
    mesh.vertices.push_back(i & 4 ? hi[2] : lo[2]);
  }
  // Faces listed counter-clockwise seen from outside.
  const uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  mesh.quads = asQuads;
  for (const auto& q : faces) {
    if (asQuads) {
      mesh.indices.insert(mesh.indices.end(), q, q + 4);
    } else {
      mesh.indices.insert(mesh.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
    }
  }
  return mesh;
}

MeshData quadGrid(int n, float jitter, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-1.f, 1.f);
  MeshData mesh;
  mesh.quads = true;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) {
      mesh.vertices.push_back(float(x) / n);
      mesh.vertices.push_back(float(y) / n);
      mesh.vertices.push_back(jitter * unit(rng) / n);
    }
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const uint32_t i = uint32_t(y * (n + 1) + x);
      mesh.indices.insert(mesh.indices.end(), {i, i + 1, i + uint32_t(n) + 2, i + uint32_t(n) + 1});
    }
  return mesh;
}

MeshData triangleFan(int count) {
  MeshData mesh;
  mesh.vertices = {0.f, 0.f, 0.f};
  for (int i = 0; i < count; ++i) {
    const float a = 2.f * 3.14159265358979f * float(i) / float(count);
    mesh.vertices.insert(mesh.vertices.end(), {std::cos(a), std::sin(a), 0.f});
  }
  for (int i = 0; i < count; ++i)
    mesh.indices.insert(mesh.indices.end(), {0u, uint32_t(1 + i), uint32_t(1 + (i + 1) % count)});
  return mesh;
}

MeshData cubeGrid(int n, const float lo[3], const float hi[3]) {
  MeshData mesh;
  // Each face is a grid in two axes at one end of the third; vertices on shared borders are
  // computed by the same expression on both faces, so neighbouring faces meet exactly.
  auto at = [&](int axis, int step) { return lo[axis] + (hi[axis] - lo[axis]) * float(step) / float(n); };
  for (int normalAxis = 0; normalAxis < 3; ++normalAxis)
    for (int side = 0; side < 2; ++side) {
      const int a = (normalAxis + 1) % 3, b = (normalAxis + 2) % 3;
      const uint32_t base = uint32_t(mesh.vertexCount());
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
          float p[3];
          p[normalAxis] = side ? hi[normalAxis] : lo[normalAxis];
          p[a] = at(a, i);
          p[b] = at(b, j);
          mesh.vertices.insert(mesh.vertices.end(), p, p + 3);
        }
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const uint32_t v00 = base + uint32_t(j * (n + 1) + i), v10 = v00 + 1, v01 = v00 + uint32_t(n + 1), v11 = v01 + 1;
          if (side) mesh.indices.insert(mesh.indices.end(), {v00, v10, v11, v00, v11, v01});
          else mesh.indices.insert(mesh.indices.end(), {v00, v11, v10, v00, v01, v11});
        }
    }
  return mesh;
}

MeshData closedFan(int count, float radius, float height, const float center[3]) {
  MeshData mesh;
  mesh.vertices = {center[0], center[1], center[2] + height, center[0], center[1], center[2] - height};
  for (int i = 0; i < count; ++i) {
    const float angle = 2.f * 3.14159265358979f * float(i) / float(count);
    mesh.vertices.insert(mesh.vertices.end(),
                         {center[0] + radius * std::cos(angle), center[1] + radius * std::sin(angle), center[2]});
  }
  for (int i = 0; i < count; ++i) {
    const uint32_t a = uint32_t(2 + i), b = uint32_t(2 + (i + 1) % count);
    mesh.indices.insert(mesh.indices.end(), {0u, a, b, 1u, b, a});
  }
  return mesh;
}

void transformMesh(MeshData& mesh, float scale, const float offset[3]) {
  for (size_t i = 0; i < mesh.vertices.size(); ++i) mesh.vertices[i] = mesh.vertices[i] * scale + offset[i % 3];
}

MeshData gridPatches(int n, float jitter, uint32_t seed) {
  MeshData mesh = quadGrid(n, jitter, seed);
  mesh.indices.clear();
  mesh.quads = false;
  mesh.grid = true;
  const uint32_t stride = uint32_t(n) + 1;
  const auto at = [&](int x, int y) { return uint32_t(y) * stride + uint32_t(x); };
  // Tiles of varying size covering the field; a tile's last row and column are its neighbours' first.
  const int widths[] = {2, 3, 5, 4, 9, 17};
  int y = 0, row = 0;
  while (y < n) {
    const int height = std::min(widths[(row + 2) % 6], n - y + 1);
    int x = 0, column = row;
    while (x < n) {
      const int width = std::min(widths[column % 6], n - x + 1);
      mesh.grids.push_back({at(x, y), stride, uint16_t(width), uint16_t(height)});
      x += width - 1;
      ++column;
    }
    y += height - 1;
    ++row;
  }
  return mesh;
}

MeshData gridCellsAsQuads(const MeshData& gridMesh) {
  MeshData mesh;
  mesh.vertices = gridMesh.vertices;
  mesh.quads = true;
  for (const RTCGrid& g : gridMesh.grids)
    for (uint32_t y = 0; y + 1 < g.height; ++y)
      for (uint32_t x = 0; x + 1 < g.width; ++x) {
        const uint32_t i = g.startVertexID + y * g.stride + x;
        mesh.indices.insert(mesh.indices.end(), {i, i + 1, i + g.stride + 1, i + g.stride});
      }
  return mesh;
}

MeshData moving(MeshData mesh, int steps, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> wander(-0.04f, 0.04f);
  std::vector<float> previous = mesh.vertices;
  for (int step = 1; step < steps; ++step) {
    for (size_t i = 0; i < previous.size(); ++i) previous[i] += wander(rng) + (i % 3 == 0 ? 0.15f : 0.f);
    mesh.laterSteps.push_back(previous);
  }
  return mesh;
}

}  // namespace obvh::tools
