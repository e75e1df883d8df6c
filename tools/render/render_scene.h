// The renderer's scene: what a glTF file (or an OBJ/PLY mesh) describes, independent of the ray
// tracing library: meshes, materials, textures, punctual lights, cameras, the node hierarchy and
// node animations. poseAt() places everything in world space at one time.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "render_math.h"

namespace obvh::render {

enum class AlphaMode { Opaque, Mask, Blend };

// Decoded to linear RGBA floats (base colour textures are sRGB-encoded in glTF).
struct Texture {
  int width = 0, height = 0;
  std::vector<float> rgba;
  // Bilinear lookup with repeat wrapping.
  void sample(float u, float v, float out[4]) const;
};

struct Material {
  std::string name = "default";
  float baseColor[4] = {0.8f, 0.8f, 0.8f, 1.f};
  int baseColorTexture = -1;
  Vec3 emissive{0.f};
  int emissiveTexture = -1;
  AlphaMode alphaMode = AlphaMode::Opaque;
  float alphaCutoff = 0.5f;
  float transmission = 0.f;  // KHR_materials_transmission
  float ior = 1.5f;          // KHR_materials_ior
  float dispersion = 0.f;    // KHR_materials_dispersion: 20 / Abbe number
};

// One glTF mesh primitive: a triangle list with optional per-vertex normals and texture coordinates.
struct Primitive {
  std::vector<float> positions;  // x, y, z
  std::vector<float> normals;    // empty or one per vertex
  std::vector<float> uvs;        // empty or one pair per vertex
  std::vector<uint32_t> indices;
  int material = -1;             // -1: the default material
  size_t vertexCount() const { return positions.size() / 3; }
  size_t triangleCount() const { return indices.size() / 3; }
};

struct Mesh {
  std::string name;
  std::vector<Primitive> primitives;
};

enum class LightType { Point, Spot, Directional };
struct Light {
  LightType type = LightType::Point;
  Vec3 color{1.f};
  float intensity = 1.f;  // candela (point, spot) or lux (directional), as glTF defines them
  float range = 0.f;      // 0: infinite
  float innerConeAngle = 0.f, outerConeAngle = 0.785398f;
};

struct Camera {
  bool orthographic = false;
  float yfov = 0.8f;         // perspective, radians
  float aspectRatio = 0.f;   // as the file gives it; renders use the image's aspect
  float xmag = 1.f, ymag = 1.f;  // orthographic half extents
};

struct Node {
  std::string name;
  bool hasMatrix = false;
  Mat4 matrix;
  Vec3 translation{0.f};
  Quat rotation;
  Vec3 scale{1.f};
  std::vector<int> children;
  int mesh = -1, camera = -1, light = -1;
};

enum class AnimatedPath { Translation, Rotation, Scale };
struct AnimationChannel {
  int node = -1;
  AnimatedPath path = AnimatedPath::Translation;
  bool step = false;          // STEP interpolation, else LINEAR (CUBICSPLINE uses its value keys linearly)
  std::vector<float> times;   // ascending
  std::vector<float> values;  // 3 or 4 floats per key
};
struct Animation {
  std::string name;
  std::vector<AnimationChannel> channels;
};

struct RenderScene {
  std::string name;
  std::vector<Mesh> meshes;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<Light> lights;
  std::vector<Camera> cameras;
  std::vector<Node> nodes;
  std::vector<int> roots;  // nodes of the displayed scene
  std::vector<Animation> animations;
  std::vector<std::string> warnings;  // parts of the file that are not rendered, said once at load

  const Material& material(int index) const;
  size_t triangleCount() const;
  float animationDuration() const;  // seconds; 0 when nothing is animated
};

struct PlacedMesh {
  int mesh = -1;
  Mat4 toWorld;
};
struct PlacedLight {
  int light = -1;
  Vec3 position, direction;  // direction the light shines along (spot, directional)
};
struct PlacedCamera {
  int camera = -1;
  Mat4 toWorld;
};
struct ScenePose {
  std::vector<PlacedMesh> meshes;
  std::vector<PlacedLight> lights;
  std::vector<PlacedCamera> cameras;
};

// World placement of every mesh, light and camera at `time` seconds, every animation playing
// (clamped to its keys), following the node hierarchy from the roots.
ScenePose poseAt(const RenderScene& scene, float time);

struct Bounds {
  Vec3 lower{1e30f}, upper{-1e30f};
  bool empty() const { return lower.x > upper.x; }
  void extend(Vec3 p) { lower = min(lower, p), upper = max(upper, p); }
};
Bounds worldBounds(const RenderScene& scene, const ScenePose& pose);

}  // namespace obvh::render
