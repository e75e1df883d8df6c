#include "render_scene.h"

#include <algorithm>
#include <cmath>

namespace obvh::render {

void Texture::sample(float u, float v, float out[4]) const {
  const float x = (u - std::floor(u)) * width - 0.5f, y = (v - std::floor(v)) * height - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float wx = x - fx, wy = y - fy;
  const auto wrap = [](int i, int n) { return ((i % n) + n) % n; };
  const int x0 = wrap(int(fx), width), x1 = wrap(int(fx) + 1, width);
  const int y0 = wrap(int(fy), height), y1 = wrap(int(fy) + 1, height);
  const auto texel = [&](int tx, int ty, int c) { return rgba[(size_t(ty) * width + tx) * 4 + c]; };
  for (int c = 0; c < 4; ++c)
    out[c] = (1 - wy) * ((1 - wx) * texel(x0, y0, c) + wx * texel(x1, y0, c)) +
             wy * ((1 - wx) * texel(x0, y1, c) + wx * texel(x1, y1, c));
}

const Material& RenderScene::material(int index) const {
  static const Material fallback;
  return index >= 0 && size_t(index) < materials.size() ? materials[index] : fallback;
}

size_t RenderScene::triangleCount() const {
  size_t n = 0;
  for (const Mesh& mesh : meshes)
    for (const Primitive& p : mesh.primitives) n += p.triangleCount();
  return n;
}

float RenderScene::animationDuration() const {
  float duration = 0.f;
  for (const Animation& a : animations)
    for (const AnimationChannel& c : a.channels)
      if (!c.times.empty()) duration = std::max(duration, c.times.back());
  return duration;
}

namespace {

// The channel's value at `time`: clamped outside the keys, linear (slerp for rotations) or step inside.
void sampleChannel(const AnimationChannel& c, float time, float out[4]) {
  const int width = c.path == AnimatedPath::Rotation ? 4 : 3;
  const size_t keys = c.times.size();
  size_t hi = size_t(std::upper_bound(c.times.begin(), c.times.end(), time) - c.times.begin());
  if (hi == 0 || hi == keys || c.step) {
    const size_t k = hi == 0 ? 0 : hi - 1;
    std::copy_n(&c.values[k * width], width, out);
    return;
  }
  const size_t lo = hi - 1;
  const float span = c.times[hi] - c.times[lo];
  const float s = span > 0.f ? (time - c.times[lo]) / span : 0.f;
  const float* a = &c.values[lo * width];
  const float* b = &c.values[hi * width];
  if (c.path == AnimatedPath::Rotation) {
    const Quat q = slerp(Quat{a[0], a[1], a[2], a[3]}, Quat{b[0], b[1], b[2], b[3]}, s);
    out[0] = q.x, out[1] = q.y, out[2] = q.z, out[3] = q.w;
  } else {
    for (int i = 0; i < width; ++i) out[i] = a[i] + s * (b[i] - a[i]);
  }
}

}  // namespace

ScenePose poseAt(const RenderScene& scene, float time) {
  std::vector<Node> nodes = scene.nodes;
  for (const Animation& animation : scene.animations)
    for (const AnimationChannel& c : animation.channels) {
      if (c.times.empty()) continue;
      Node& node = nodes[c.node];
      float v[4];
      sampleChannel(c, time, v);
      if (c.path == AnimatedPath::Translation) node.translation = {v[0], v[1], v[2]};
      else if (c.path == AnimatedPath::Scale) node.scale = {v[0], v[1], v[2]};
      else node.rotation = {v[0], v[1], v[2], v[3]};
    }

  ScenePose pose;
  // The loader rejects cycles, so a plain depth-first walk terminates.
  struct Pending {
    int node;
    Mat4 parent;
  };
  std::vector<Pending> stack;
  for (auto it = scene.roots.rbegin(); it != scene.roots.rend(); ++it) stack.push_back({*it, Mat4{}});
  while (!stack.empty()) {
    const Pending p = stack.back();
    stack.pop_back();
    const Node& node = nodes[p.node];
    const Mat4 world = p.parent * (node.hasMatrix ? node.matrix : composeTrs(node.translation, node.rotation, node.scale));
    if (node.mesh >= 0) pose.meshes.push_back({node.mesh, world});
    if (node.camera >= 0) pose.cameras.push_back({node.camera, world});
    if (node.light >= 0)
      pose.lights.push_back({node.light, transformPoint(world, Vec3{0.f}),
                             normalize(transformVector(world, Vec3{0.f, 0.f, -1.f}))});
    for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) stack.push_back({*it, world});
  }
  return pose;
}

Bounds worldBounds(const RenderScene& scene, const ScenePose& pose) {
  Bounds b;
  for (const PlacedMesh& placed : pose.meshes)
    for (const Primitive& p : scene.meshes[placed.mesh].primitives)
      for (size_t v = 0; v < p.vertexCount(); ++v)
        b.extend(transformPoint(placed.toWorld, {p.positions[3 * v], p.positions[3 * v + 1], p.positions[3 * v + 2]}));
  return b;
}

}  // namespace obvh::render
