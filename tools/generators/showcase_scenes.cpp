#include "showcase_scenes.h"

#include <cmath>
#include <stdexcept>

#include "gltf_builder.h"

namespace obvh::tools {
namespace {

constexpr float kPi = 3.14159265f;

std::array<float, 4> aboutY(float angle) { return {0.f, std::sin(angle / 2), 0.f, std::cos(angle / 2)}; }
std::array<float, 4> aboutX(float angle) { return {std::sin(angle / 2), 0.f, 0.f, std::cos(angle / 2)}; }

int floorMesh(GltfBuilder& b, float half) {
  TriangleList floor;
  floor.box({-half, -0.1f, -half}, {half, 0.f, half});
  GltfMaterialDesc grey;
  grey.name = "floor";
  grey.baseColor = {0.7, 0.7, 0.7, 1.0};
  return b.addMesh("floor", floor, b.addMaterial(grey));
}

int boxMesh(GltfBuilder& b, const std::string& name, std::array<float, 3> half, std::array<double, 4> colour) {
  TriangleList box;
  box.box({-half[0], -half[1], -half[2]}, {half[0], half[1], half[2]});
  GltfMaterialDesc m;
  m.name = name;
  m.baseColor = colour;
  return b.addMesh(name, box, b.addMaterial(m));
}

void shadows(GltfBuilder& b) {
  b.addNode("floor", floorMesh(b, 6.f));
  b.addNode("red box", boxMesh(b, "red", {0.5f, 0.5f, 0.5f}, {0.8, 0.2, 0.15, 1}), {-1.2f, 0.5f, 0.f}, aboutY(0.4f));
  b.addNode("tall box", boxMesh(b, "blue", {0.35f, 1.1f, 0.35f}, {0.2, 0.35, 0.8, 1}), {0.9f, 1.1f, -0.6f}, aboutY(-0.3f));
  b.addNode("slab", boxMesh(b, "green", {0.8f, 0.08f, 0.5f}, {0.25, 0.7, 0.3, 1}), {0.4f, 0.9f, 1.2f}, aboutY(0.2f));
  b.addLight("point", {1.f, 0.95f, 0.85f}, 40.0, {2.f, 4.f, 3.f});
  b.addLight("spot", {0.6f, 0.7f, 1.f}, 60.0, {-3.f, 4.f, 1.f}, aboutX(-1.2f));
  b.addLight("directional", {1.f, 1.f, 1.f}, 0.8, {0.f, 5.f, 0.f}, aboutX(-1.1f));
  b.addCamera({3.5f, 3.2f, 5.5f}, {0.f, 0.6f, 0.f}, 0.8);
}

void alpha(GltfBuilder& b) {
  b.addNode("floor", floorMesh(b, 6.f));
  b.addNode("box", boxMesh(b, "box", {0.4f, 0.4f, 0.4f}, {0.9, 0.8, 0.2, 1}), {0.f, 0.4f, -1.6f});
  const std::array<std::array<double, 4>, 3> colours{{{0.9, 0.1, 0.1, 0.5}, {0.1, 0.9, 0.1, 0.5}, {0.1, 0.2, 0.9, 0.5}}};
  for (int i = 0; i < 3; ++i) {
    TriangleList pane;
    pane.quad({-0.7f, 0.f, 0.f}, {0.7f, 0.f, 0.f}, {0.7f, 1.4f, 0.f}, {-0.7f, 1.4f, 0.f});
    GltfMaterialDesc m;
    m.name = "pane " + std::to_string(i);
    m.baseColor = colours[size_t(i)];
    m.alphaMode = "BLEND";
    b.addNode(m.name, b.addMesh(m.name, pane, b.addMaterial(m)), {-0.6f + 0.6f * float(i), 0.05f, -0.4f + 0.5f * float(i)});
  }
  // A cut-out checker: alpha 0 or 1 per cell, masked at 0.5.
  std::vector<uint8_t> checker;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const bool solid = (x + y) % 2 == 0;
      checker.insert(checker.end(), {230, 230, 240, uint8_t(solid ? 255 : 0)});
    }
  GltfMaterialDesc mask;
  mask.name = "checker";
  mask.baseColor = {1, 1, 1, 1};
  mask.alphaMode = "MASK";
  mask.baseColorTexture = b.addTexture(8, 8, checker);
  TriangleList fence;
  fence.quad({-1.f, 0.f, 0.f}, {1.f, 0.f, 0.f}, {1.f, 2.f, 0.f}, {-1.f, 2.f, 0.f});
  b.addNode("checker", b.addMesh("checker", fence, b.addMaterial(mask)), {1.6f, 0.f, -0.8f}, aboutY(-0.6f));
  b.addLight("point", {1.f, 1.f, 1.f}, 50.0, {1.f, 4.f, 3.f});
  b.addCamera({0.5f, 2.2f, 4.8f}, {0.2f, 0.7f, -0.6f}, 0.8);
}

// Vertical emissive strips behind a glass prism standing on a floor: seen through the prism, every
// strip is spread into a spectrum (violet bent most), seen directly it stays white.
void prism(GltfBuilder& b) {
  GltfMaterialDesc strip;
  strip.name = "white strip";
  strip.baseColor = {0, 0, 0, 1};
  strip.emissive = {1, 1, 1};
  TriangleList strips;
  for (int i = -14; i <= 14; ++i) {
    const float x = 0.7f * float(i);
    strips.quad({x - 0.1f, -3.f, 0.f}, {x + 0.1f, -3.f, 0.f}, {x + 0.1f, 3.f, 0.f}, {x - 0.1f, 3.f, 0.f});
  }
  b.addNode("strips", b.addMesh("strips", strips, b.addMaterial(strip)), {0.f, 0.f, -6.f});

  GltfMaterialDesc glass;
  glass.name = "dispersive glass";
  glass.baseColor = {1, 1, 1, 1};
  glass.transmission = 1.0;
  glass.ior = 1.6;
  glass.dispersion = 4.0;  // Abbe number 5: far stronger than real glass, so the spread is plain to see
  TriangleList body;
  const float r = 0.9f, h = 1.3f;
  std::array<std::array<float, 3>, 3> bottom, top;
  for (int k = 0; k < 3; ++k) {
    const float a = kPi + 2.f * kPi * float(k) / 3.f;
    bottom[size_t(k)] = {r * std::cos(a), -h, r * std::sin(a)};
    top[size_t(k)] = {r * std::cos(a), h, r * std::sin(a)};
  }
  // Corners run clockwise seen from +y, so each side quad faces outwards in this order.
  for (int k = 0; k < 3; ++k) {
    const size_t n = size_t((k + 1) % 3);
    body.quad(bottom[n], bottom[size_t(k)], top[size_t(k)], top[n]);
  }
  body.triangle(top[0], top[2], top[1]);
  body.triangle(bottom[0], bottom[1], bottom[2]);
  b.addNode("prism", b.addMesh("prism", body, b.addMaterial(glass)), {0.f, 0.f, -2.5f});
  b.addNode("floor", floorMesh(b, 8.f), {0.f, -h - 0.02f, -2.f});  // not coplanar with the prism's base
  b.addLight("directional", {1.f, 1.f, 1.f}, 0.6, {0.f, 3.f, 0.f}, {-0.5f, 0.2f, 0.1f, 0.835f});
  b.addCamera({0.f, 0.f, 1.5f}, {0.f, 0.f, -6.f}, 0.9);
}

// One crate mesh instanced five times on a turning carousel (instances move), and one box moved
// by itself (its vertices are refitted), lit by a point light.
void animated(GltfBuilder& b) {
  b.addNode("floor", floorMesh(b, 6.f));
  const int crate = boxMesh(b, "crate", {0.3f, 0.3f, 0.3f}, {0.75, 0.5, 0.25, 1});
  const int carousel = b.addNode("carousel", -1, {0.f, 0.3f, 0.f});
  for (int i = 0; i < 5; ++i) {
    const float a = 2.f * kPi * float(i) / 5.f;
    b.addChild(carousel, b.addNode("crate " + std::to_string(i), crate, {1.6f * std::cos(a), 0.f, 1.6f * std::sin(a)}, aboutY(a)));
  }
  std::vector<float> times, turns;
  for (int k = 0; k <= 4; ++k) {
    times.push_back(0.5f * float(k));
    const auto q = aboutY(kPi / 2.f * float(k));
    turns.insert(turns.end(), q.begin(), q.end());
  }
  b.animate(carousel, "rotation", times, turns);
  const int slider = b.addNode("slider", boxMesh(b, "slider", {0.25f, 0.5f, 0.25f}, {0.3, 0.6, 0.9, 1}), {-0.8f, 0.5f, 0.f});
  b.animate(slider, "translation", {0.f, 1.f, 2.f}, {-0.8f, 0.5f, 0.f, 0.8f, 0.5f, 0.f, -0.8f, 0.5f, 0.f});
  b.addLight("point", {1.f, 1.f, 1.f}, 45.0, {1.5f, 4.f, 2.5f});
  b.addCamera({0.f, 3.f, 5.f}, {0.f, 0.3f, 0.f}, 0.8);
}

struct Entry {
  ShowcaseScene scene;
  void (*build)(GltfBuilder&);
};

const std::vector<Entry>& entries() {
  static const std::vector<Entry> list = {
      {{"shadows", "boxes on a floor under a point, a spot and a directional light (lambert + shadows)"}, shadows},
      {{"alpha", "blended panes and a masked checker fence over a floor, one light (shadows + transparency)"}, alpha},
      {{"prism", "a dispersive glass prism before white strips (path tracing + spectral dispersion)"}, prism},
      {{"animated", "a turning carousel of instanced crates and a sliding box, 2 s (animation + shadows)"}, animated},
  };
  return list;
}

}  // namespace

const std::vector<ShowcaseScene>& showcaseScenes() {
  static const std::vector<ShowcaseScene> scenes = [] {
    std::vector<ShowcaseScene> out;
    for (const Entry& e : entries()) out.push_back(e.scene);
    return out;
  }();
  return scenes;
}

void writeShowcaseScene(const std::string& name, const std::string& path) {
  for (const Entry& e : entries())
    if (e.scene.name == name) {
      GltfBuilder builder;
      e.build(builder);
      builder.write(path);
      return;
    }
  throw std::runtime_error("unknown scene '" + name + "' (obvh_scenegen --list shows them)");
}

}  // namespace obvh::tools
