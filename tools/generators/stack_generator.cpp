#include "stack_generator.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace obvh::tools {
namespace {

constexpr float kPi = 3.14159265358979f;

struct Point {
  float x, y;
};

// Closed box from a quadrilateral footprint (counter-clockwise) extruded from z0 to z1.
void addPrism(MeshData& mesh, const std::vector<Point>& footprint, float z0, float z1) {
  const uint32_t base = uint32_t(mesh.vertexCount());
  const uint32_t n = uint32_t(footprint.size());
  for (float z : {z0, z1})
    for (const Point& p : footprint) mesh.vertices.insert(mesh.vertices.end(), {p.x, p.y, z});
  for (uint32_t i = 0; i < n; ++i) {  // sides
    const uint32_t a = base + i, b = base + (i + 1) % n;
    mesh.indices.insert(mesh.indices.end(), {a, b, b + n, a, b + n, a + n});
  }
  for (uint32_t i = 1; i + 1 < n; ++i) {  // bottom (facing down) and top fans
    mesh.indices.insert(mesh.indices.end(), {base, base + i + 1, base + i});
    mesh.indices.insert(mesh.indices.end(), {base + n, base + n + i, base + n + i + 1});
  }
}

void addBox(MeshData& mesh, float x0, float y0, float z0, float x1, float y1, float z1) {
  addPrism(mesh, {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, z0, z1);
}

// Lines at `degrees` across the die: each a box whose centre line is clipped to the die square.
void addLines(MeshData& mesh, const StackParams& p, float degrees, float z0, float z1) {
  const float a = degrees * kPi / 180.f;
  const Point d{std::cos(a), std::sin(a)}, n{-std::sin(a), std::cos(a)};
  const float size = p.dieSize, half = 0.5f * p.lineWidthRatio * p.linePitch;
  const Point centre{0.5f * size, 0.5f * size};
  const float reach = size * 0.7072f;  // half the diagonal: every line that can touch the die
  for (float s = -reach + 0.5f * p.linePitch; s < reach; s += p.linePitch) {
    // Clip centre + s*n + t*d to the die square.
    const Point o{centre.x + s * n.x, centre.y + s * n.y};
    float t0 = -1e30f, t1 = 1e30f;
    bool inside = true;
    for (int axis = 0; axis < 2 && inside; ++axis) {
      const float oa = axis ? o.y : o.x, da = axis ? d.y : d.x;
      if (std::fabs(da) < 1e-7f) {
        inside = oa >= 0.f && oa <= size;
        continue;
      }
      const float ta = (0.f - oa) / da, tb = (size - oa) / da;
      t0 = std::max(t0, std::min(ta, tb));
      t1 = std::min(t1, std::max(ta, tb));
    }
    if (!inside || t1 - t0 < 2.f * half) continue;
    const Point p0{o.x + t0 * d.x, o.y + t0 * d.y}, p1{o.x + t1 * d.x, o.y + t1 * d.y};
    addPrism(mesh,
             {{p0.x - half * n.x, p0.y - half * n.y}, {p1.x - half * n.x, p1.y - half * n.y},
              {p1.x + half * n.x, p1.y + half * n.y}, {p0.x + half * n.x, p0.y + half * n.y}},
             z0, z1);
  }
}

StackScene build(const StackParams& p, const std::string& name) {
  std::mt19937 rng(p.seed);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  MeshData slabs, lines, vias, steps, blocks;
  const float t = p.layerThickness, size = p.dieSize;
  for (int layer = 0; layer < p.layers; ++layer) {
    const float z = float(layer) * t;
    addBox(slabs, 0.f, 0.f, z, size, size, z + 0.25f * t);
    addLines(lines, p, p.angles[size_t(layer) % p.angles.size()], z + 0.25f * t, z + 0.75f * t);
    if (layer + 1 < p.layers)
      for (int v = 0; v < p.viasPerLayer; ++v) {
        const float cx = size * (0.05f + 0.9f * unit(rng)), cy = size * (0.05f + 0.9f * unit(rng));
        const float r = 0.3f * p.linePitch;
        std::vector<Point> octagon;
        for (int k = 0; k < 8; ++k)
          octagon.push_back({cx + r * std::cos(kPi * float(k) / 4.f), cy + r * std::sin(kPi * float(k) / 4.f)});
        addPrism(vias, octagon, z + 0.5f * t, z + 1.5f * t);
      }
  }
  const float top = float(p.layers) * t;
  for (int profile = 0; profile < p.steppedProfiles; ++profile) {
    const float x0 = size * 0.9f * unit(rng), y0 = size * 0.9f * unit(rng);
    const float stepWidth = 0.1f * size / float(p.stepsPerProfile), depth = 0.05f * size;
    for (int s = 0; s < p.stepsPerProfile; ++s)
      addBox(steps, x0 + float(s) * stepWidth, y0, top, x0 + float(s + 1) * stepWidth, y0 + depth,
             top + t * float(s + 1) / float(p.stepsPerProfile));
  }
  for (int b = 0; b < p.blocks; ++b) {
    const float x0 = size * unit(rng), y0 = size * unit(rng), z0 = top * unit(rng);
    const float w = size * (0.02f + 0.1f * unit(rng)), h = size * (0.02f + 0.1f * unit(rng));
    addBox(blocks, x0, y0, z0, std::min(size, x0 + w), std::min(size, y0 + h), z0 + t * (0.2f + unit(rng)));
  }
  StackScene scene;
  scene.name = name;
  const std::pair<const char*, MeshData*> groups[] = {
      {"slabs", &slabs}, {"lines", &lines}, {"vias", &vias}, {"steps", &steps}, {"blocks", &blocks}};
  for (const auto& [groupName, mesh] : groups)
    if (!mesh->indices.empty()) {
      scene.groupNames.push_back(groupName);
      scene.groups.push_back(std::move(*mesh));
    }
  return scene;
}

}  // namespace

size_t StackScene::triangleCount() const {
  size_t n = 0;
  for (const MeshData& g : groups) n += g.primitiveCount();
  return n;
}

SceneData StackScene::asScene() const {
  SceneData scene;
  scene.name = name;
  scene.meshes = groups;
  return scene;
}

StackScene generateStack(const StackParams& params, const std::string& name) {
  if (params.layers < 1 || params.angles.empty() || !(params.linePitch > 0.f) || !(params.dieSize > 0.f))
    throw std::invalid_argument("stack parameters need layers >= 1, at least one angle, pitch > 0 and die size > 0");
  if (params.targetTriangles == 0) return build(params, name);
  // The line count falls monotonically with the pitch: bisect on a log scale for the closest count.
  StackParams p = params;
  float lo = p.dieSize * 1e-4f, hi = p.dieSize;
  StackScene best = build(p, name);
  auto distance = [&](const StackScene& s) {
    return std::fabs(double(s.triangleCount()) - double(params.targetTriangles));
  };
  for (int i = 0; i < 40; ++i) {
    p.linePitch = std::sqrt(lo * hi);
    StackScene s = build(p, name);
    (s.triangleCount() > params.targetTriangles ? lo : hi) = p.linePitch;
    if (distance(s) < distance(best)) best = std::move(s);
  }
  return best;
}

const std::vector<StackPreset>& stackPresets() {
  static const std::vector<StackPreset> presets = [] {
    auto preset = [](const char* name, const char* description, StackParams p, size_t target) {
      p.targetTriangles = target;
      return StackPreset{name, description, p};
    };
    StackParams diagonal;
    diagonal.layers = 6, diagonal.angles = {45.f};
    StackParams small;
    small.layers = 2, small.angles = {30.f, 60.f};
    StackParams vias;
    vias.layers = 3, vias.angles = {45.f, -45.f}, vias.viasPerLayer = 60;
    StackParams axis;
    axis.layers = 8, axis.angles = {0.f, 90.f}, axis.blocks = 400;
    StackParams stepped;
    stepped.layers = 3, stepped.angles = {45.f}, stepped.steppedProfiles = 24;
    StackParams mixed;
    mixed.layers = 4, mixed.angles = {0.f, 30.f, 45.f, 60.f};
    StackParams large;
    large.layers = 10, large.angles = {0.f, 30.f, 45.f, 60.f, 90.f}, large.viasPerLayer = 400,
    large.steppedProfiles = 40, large.blocks = 200;
    return std::vector<StackPreset>{
        preset("diagonal-42k", "6 layers of 45-degree lines", diagonal, 42252),
        preset("small-1.5k", "2 layers of 30- and 60-degree lines", small, 1548),
        preset("vias-5.6k", "3 layers of +-45-degree lines joined by vias", vias, 5616),
        preset("axis-516k", "8 layers of 0/90-degree lines and 400 axis-aligned blocks", axis, 515824),
        preset("stepped-6.6k", "3 layers of 45-degree lines under 24 stepped profiles", stepped, 6604),
        preset("mixed-6.9k", "4 layers at 0, 30, 45 and 60 degrees", mixed, 6912),
        preset("mixed-654k", "10 layers at 0..90 degrees with vias, steps and blocks", large, 653544)};
  }();
  return presets;
}

const StackPreset* findStackPreset(const std::string& name) {
  for (const StackPreset& p : stackPresets())
    if (p.name == name) return &p;
  return nullptr;
}

}  // namespace obvh::tools
