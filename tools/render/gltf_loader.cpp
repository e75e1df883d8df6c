// glTF 2.0 through tinygltf. tinygltf checks the JSON; everything it leaves to the caller (indices
// into other arrays, accessor extents, component types, index ranges, node cycles) is checked
// here, so a broken file is reported, never rendered from garbage.
#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <set>
#include <stdexcept>

#include "gltf_schema_check.h"
#include "scene_loader.h"

namespace obvh::render {
namespace {

class GltfReader {
 public:
  GltfReader(const tinygltf::Model& model, const std::string& path) : model_(model), path_(path) {}

  RenderScene read();

 private:
  [[noreturn]] void fail(const std::string& what) const { throw std::runtime_error("glTF '" + path_ + "': " + what); }

  template <class T>
  const T& element(const std::vector<T>& list, int index, const char* kind, const std::string& user) const {
    if (index < 0 || size_t(index) >= list.size())
      fail(user + " refers to " + kind + " " + std::to_string(index) + ", but the file has " + std::to_string(list.size()));
    return list[size_t(index)];
  }

  // Reads `count * components` numbers of accessor `index` as floats (normalised integers scaled to [0,1]).
  std::vector<float> readFloats(int index, const std::set<int>& types, const std::string& user) const;
  std::vector<uint32_t> readIndices(int index, const std::string& user) const;
  // The accessor's raw element bytes, after checking that every element lies inside its buffer.
  const unsigned char* elementBytes(const tinygltf::Accessor& accessor, int index, size_t& stride, const std::string& user) const;

  Primitive readPrimitive(const tinygltf::Primitive& in, const std::string& user, RenderScene& scene) const;
  Material readMaterial(const tinygltf::Material& in, RenderScene& scene) const;
  Texture readTexture(int textureIndex, const std::string& user) const;
  void readNodes(RenderScene& scene) const;
  void readAnimations(RenderScene& scene) const;

  const tinygltf::Model& model_;
  std::string path_;
};

const unsigned char* GltfReader::elementBytes(const tinygltf::Accessor& accessor, int index, size_t& stride,
                                              const std::string& user) const {
  const std::string name = user + ": accessor " + std::to_string(index);
  if (accessor.sparse.isSparse) fail(name + " is sparse, which obvh does not read");
  if (accessor.bufferView < 0) return nullptr;  // all zeros, as glTF defines it
  const tinygltf::BufferView& view = element(model_.bufferViews, accessor.bufferView, "buffer view", name);
  const tinygltf::Buffer& buffer = element(model_.buffers, view.buffer, "buffer", name);
  const int componentSize = tinygltf::GetComponentSizeInBytes(uint32_t(accessor.componentType));
  const int components = tinygltf::GetNumComponentsInType(uint32_t(accessor.type));
  if (componentSize <= 0 || components <= 0) fail(name + " has an unknown component type or element type");
  const size_t elementSize = size_t(componentSize) * size_t(components);
  stride = view.byteStride ? view.byteStride : elementSize;
  if (stride < elementSize) fail(name + ": byte stride " + std::to_string(stride) + " is smaller than its elements");
  if (view.byteOffset + view.byteLength > buffer.data.size())
    fail(name + ": buffer view " + std::to_string(accessor.bufferView) + " ends at byte " +
         std::to_string(view.byteOffset + view.byteLength) + " of a " + std::to_string(buffer.data.size()) +
         "-byte buffer" + (buffer.data.empty() ? " (is the buffer's file missing?)" : ""));
  if (accessor.count > 0 && accessor.byteOffset + stride * (accessor.count - 1) + elementSize > view.byteLength)
    fail(name + ": " + std::to_string(accessor.count) + " elements do not fit in buffer view " +
         std::to_string(accessor.bufferView) + " (" + std::to_string(view.byteLength) + " bytes)");
  return buffer.data.data() + view.byteOffset + accessor.byteOffset;
}

std::vector<float> GltfReader::readFloats(int index, const std::set<int>& types, const std::string& user) const {
  const tinygltf::Accessor& accessor = element(model_.accessors, index, "accessor", user);
  if (!types.count(accessor.type)) fail(user + ": accessor " + std::to_string(index) + " has the wrong element type");
  size_t stride = 0;
  const unsigned char* bytes = elementBytes(accessor, index, stride, user);
  const int components = tinygltf::GetNumComponentsInType(uint32_t(accessor.type));
  std::vector<float> out(accessor.count * size_t(components), 0.f);
  if (!bytes) return out;
  const bool normalized = accessor.normalized;
  for (size_t e = 0; e < accessor.count; ++e)
    for (int c = 0; c < components; ++c) {
      const unsigned char* p = bytes + e * stride;
      float value = 0.f;
      switch (accessor.componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: std::memcpy(&value, p + 4 * c, 4); break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: value = p[c] / (normalized ? 255.f : 1.f); break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
          uint16_t s;
          std::memcpy(&s, p + 2 * c, 2);
          value = s / (normalized ? 65535.f : 1.f);
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_BYTE: value = std::max(float(int8_t(p[c])) / (normalized ? 127.f : 1.f), -1.f); break;
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
          int16_t s;
          std::memcpy(&s, p + 2 * c, 2);
          value = normalized ? std::max(s / 32767.f, -1.f) : float(s);
          break;
        }
        default: fail(user + ": accessor " + std::to_string(index) + " has a component type obvh cannot read as numbers");
      }
      out[e * components + c] = value;
    }
  return out;
}

std::vector<uint32_t> GltfReader::readIndices(int index, const std::string& user) const {
  const tinygltf::Accessor& accessor = element(model_.accessors, index, "accessor", user);
  if (accessor.type != TINYGLTF_TYPE_SCALAR) fail(user + ": index accessor " + std::to_string(index) + " is not SCALAR");
  size_t stride = 0;
  const unsigned char* bytes = elementBytes(accessor, index, stride, user);
  std::vector<uint32_t> out(accessor.count, 0u);
  if (!bytes) return out;
  for (size_t e = 0; e < accessor.count; ++e) {
    const unsigned char* p = bytes + e * stride;
    switch (accessor.componentType) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: out[e] = p[0]; break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t s;
        std::memcpy(&s, p, 2);
        out[e] = s;
        break;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: std::memcpy(&out[e], p, 4); break;
      default: fail(user + ": index accessor " + std::to_string(index) + " is not an unsigned integer type");
    }
  }
  return out;
}

Texture GltfReader::readTexture(int textureIndex, const std::string& user) const {
  const tinygltf::Texture& texture = element(model_.textures, textureIndex, "texture", user);
  const tinygltf::Image& image = element(model_.images, texture.source, "image", user + ": texture " + std::to_string(textureIndex));
  if (image.width <= 0 || image.height <= 0 || image.image.empty())
    fail(user + ": image " + std::to_string(texture.source) + " could not be decoded");
  const int channels = image.component;
  const int bytesPerChannel = image.bits == 16 ? 2 : 1;
  if (channels < 1 || channels > 4 || image.image.size() < size_t(image.width) * image.height * channels * bytesPerChannel)
    fail(user + ": image " + std::to_string(texture.source) + " has an unexpected pixel layout");
  // sRGB transfer to linear, once per 8-bit value.
  float decode[256];
  for (int i = 0; i < 256; ++i) {
    const float c = i / 255.f;
    decode[i] = c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
  }
  Texture out;
  out.width = image.width, out.height = image.height;
  out.rgba.resize(size_t(image.width) * image.height * 4);
  for (size_t p = 0; p < size_t(image.width) * image.height; ++p) {
    float texel[4] = {0.f, 0.f, 0.f, 1.f};
    for (int c = 0; c < channels; ++c) {
      const size_t at = (p * channels + c) * bytesPerChannel;
      const unsigned value = bytesPerChannel == 2 ? image.image[at + 1] : image.image[at];  // high byte of little-endian 16 bits
      texel[c] = c < 3 || channels < 4 ? decode[value] : value / 255.f;
    }
    if (channels <= 2) texel[3] = channels == 2 ? texel[1] : 1.f, texel[1] = texel[2] = texel[0];
    std::copy_n(texel, 4, &out.rgba[p * 4]);
  }
  return out;
}

double numberOr(const tinygltf::Value& object, const char* key, double fallback) {
  if (!object.IsObject() || !object.Has(key)) return fallback;
  const tinygltf::Value& v = object.Get(key);
  return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
}

Material GltfReader::readMaterial(const tinygltf::Material& in, RenderScene& scene) const {
  Material m;
  m.name = in.name.empty() ? "material" : in.name;
  const std::vector<double>& base = in.pbrMetallicRoughness.baseColorFactor;
  for (size_t c = 0; c < 4 && c < base.size(); ++c) m.baseColor[c] = float(base[c]);
  if (in.pbrMetallicRoughness.baseColorTexture.index >= 0) {
    if (in.pbrMetallicRoughness.baseColorTexture.texCoord != 0)
      scene.warnings.push_back("material '" + m.name + "': base colour texture uses TEXCOORD_" +
                               std::to_string(in.pbrMetallicRoughness.baseColorTexture.texCoord) + "; TEXCOORD_0 is used");
    if (in.pbrMetallicRoughness.baseColorTexture.extensions.count("KHR_texture_transform"))
      scene.warnings.push_back("material '" + m.name + "': KHR_texture_transform is not applied");
    m.baseColorTexture = int(scene.textures.size());
    scene.textures.push_back(readTexture(in.pbrMetallicRoughness.baseColorTexture.index, "material '" + m.name + "'"));
  }
  if (in.emissiveTexture.index >= 0) {
    m.emissiveTexture = int(scene.textures.size());
    scene.textures.push_back(readTexture(in.emissiveTexture.index, "material '" + m.name + "'"));
  }
  for (size_t c = 0; c < 3 && c < in.emissiveFactor.size(); ++c) m.emissive[int(c)] = float(in.emissiveFactor[c]);
  if (in.alphaMode == "MASK") m.alphaMode = AlphaMode::Mask;
  else if (in.alphaMode == "BLEND") m.alphaMode = AlphaMode::Blend;
  else if (!in.alphaMode.empty() && in.alphaMode != "OPAQUE") fail("material '" + m.name + "' has alphaMode '" + in.alphaMode + "'");
  m.alphaCutoff = float(in.alphaCutoff);
  for (const auto& [name, value] : in.extensions) {
    if (name == "KHR_materials_transmission") m.transmission = float(numberOr(value, "transmissionFactor", 0.0));
    else if (name == "KHR_materials_ior") m.ior = float(numberOr(value, "ior", 1.5));
    else if (name == "KHR_materials_dispersion") m.dispersion = float(numberOr(value, "dispersion", 0.0));
    else if (name == "KHR_materials_emissive_strength") m.emissive *= float(numberOr(value, "emissiveStrength", 1.0));
  }
  if (!(m.ior >= 1.f) && m.ior != 0.f) fail("material '" + m.name + "' has ior " + std::to_string(m.ior) + " (must be >= 1)");
  if (m.ior == 0.f) m.ior = 1.f;  // KHR_materials_ior: 0 means "no refraction"
  if (!(m.dispersion >= 0.f)) fail("material '" + m.name + "' has a negative dispersion");
  return m;
}

Primitive GltfReader::readPrimitive(const tinygltf::Primitive& in, const std::string& user, RenderScene& scene) const {
  Primitive p;
  const auto position = in.attributes.find("POSITION");
  if (position == in.attributes.end()) fail(user + " has no POSITION attribute");
  p.positions = readFloats(position->second, {TINYGLTF_TYPE_VEC3}, user + " POSITION");
  for (float v : p.positions)
    if (!std::isfinite(v)) fail(user + " has a non-finite vertex position");
  const size_t vertexCount = p.vertexCount();
  if (const auto normal = in.attributes.find("NORMAL"); normal != in.attributes.end()) {
    p.normals = readFloats(normal->second, {TINYGLTF_TYPE_VEC3}, user + " NORMAL");
    if (p.normals.size() != p.positions.size()) fail(user + ": NORMAL and POSITION counts differ");
    bool finite = true;
    for (float v : p.normals) finite = finite && std::isfinite(v);
    if (!finite) {
      scene.warnings.push_back(user + ": non-finite normals, shaded with geometric normals");
      p.normals.clear();
    }
  }
  if (const auto uv = in.attributes.find("TEXCOORD_0"); uv != in.attributes.end()) {
    p.uvs = readFloats(uv->second, {TINYGLTF_TYPE_VEC2}, user + " TEXCOORD_0");
    if (p.uvs.size() != vertexCount * 2) fail(user + ": TEXCOORD_0 and POSITION counts differ");
  }
  std::vector<uint32_t> order;
  if (in.indices >= 0) {
    order = readIndices(in.indices, user + " indices");
    for (uint32_t i : order)
      if (i >= vertexCount)
        fail(user + ": index " + std::to_string(i) + " is out of range (" + std::to_string(vertexCount) + " vertices)");
  } else {
    order.resize(vertexCount);
    for (size_t i = 0; i < vertexCount; ++i) order[i] = uint32_t(i);
  }
  switch (in.mode) {
    case TINYGLTF_MODE_TRIANGLES:
      if (order.size() % 3) fail(user + ": " + std::to_string(order.size()) + " indices do not make whole triangles");
      p.indices = std::move(order);
      break;
    case TINYGLTF_MODE_TRIANGLE_STRIP:
      for (size_t i = 2; i < order.size(); ++i) {
        const bool even = i % 2 == 0;
        p.indices.insert(p.indices.end(), {order[i - 2], even ? order[i - 1] : order[i], even ? order[i] : order[i - 1]});
      }
      break;
    case TINYGLTF_MODE_TRIANGLE_FAN:
      for (size_t i = 2; i < order.size(); ++i) p.indices.insert(p.indices.end(), {order[0], order[i - 1], order[i]});
      break;
    default:
      scene.warnings.push_back(user + ": points and lines are not rendered");
      break;
  }
  if (in.material >= 0) element(model_.materials, in.material, "material", user);
  p.material = in.material;
  return p;
}

void GltfReader::readNodes(RenderScene& scene) const {
  for (size_t n = 0; n < model_.nodes.size(); ++n) {
    const tinygltf::Node& in = model_.nodes[n];
    const std::string user = "node " + std::to_string(n) + (in.name.empty() ? "" : " '" + in.name + "'");
    Node node;
    node.name = in.name;
    if (in.matrix.size() == 16) {
      node.hasMatrix = true;
      for (int i = 0; i < 16; ++i) node.matrix.m[size_t(i)] = float(in.matrix[size_t(i)]);
    } else if (!in.matrix.empty()) {
      fail(user + " has a matrix of " + std::to_string(in.matrix.size()) + " numbers");
    }
    if (in.translation.size() == 3) node.translation = {float(in.translation[0]), float(in.translation[1]), float(in.translation[2])};
    if (in.rotation.size() == 4)
      node.rotation = {float(in.rotation[0]), float(in.rotation[1]), float(in.rotation[2]), float(in.rotation[3])};
    if (in.scale.size() == 3) node.scale = {float(in.scale[0]), float(in.scale[1]), float(in.scale[2])};
    for (int child : in.children) element(model_.nodes, child, "node", user + " (child)");
    node.children = in.children;
    if (in.mesh >= 0) node.mesh = (element(model_.meshes, in.mesh, "mesh", user), in.mesh);
    if (in.camera >= 0) node.camera = (element(model_.cameras, in.camera, "camera", user), in.camera);
    if (const auto light = in.extensions.find("KHR_lights_punctual"); light != in.extensions.end()) {
      const int index = int(numberOr(light->second, "light", -1));
      node.light = (element(model_.lights, index, "light", user), index);
    }
    if (in.skin >= 0) scene.warnings.push_back(user + ": skinning is not applied (rendered in bind pose)");
    scene.nodes.push_back(std::move(node));
  }

  if (!model_.scenes.empty()) {
    const int chosen = model_.defaultScene >= 0 ? model_.defaultScene : 0;
    const tinygltf::Scene& shown = element(model_.scenes, chosen, "scene", "the file's default scene");
    for (int root : shown.nodes) element(model_.nodes, root, "node", "scene " + std::to_string(chosen));
    scene.roots = shown.nodes;
  } else {
    // No scene: every node that is nobody's child is shown.
    std::vector<bool> isChild(scene.nodes.size(), false);
    for (const Node& node : scene.nodes)
      for (int c : node.children) isChild[size_t(c)] = true;
    for (size_t n = 0; n < scene.nodes.size(); ++n)
      if (!isChild[n]) scene.roots.push_back(int(n));
  }

  // Depth-first with colours: a node met again while still on the path closes a cycle.
  enum State : char { Unvisited, OnPath, Done };
  std::vector<State> state(scene.nodes.size(), Unvisited);
  std::function<void(int)> visit = [&](int n) {
    if (state[size_t(n)] == OnPath) fail("node " + std::to_string(n) + " is its own ancestor (the node hierarchy has a cycle)");
    if (state[size_t(n)] == Done) return;
    state[size_t(n)] = OnPath;
    for (int c : scene.nodes[size_t(n)].children) visit(c);
    state[size_t(n)] = Done;
  };
  for (size_t n = 0; n < scene.nodes.size(); ++n) visit(int(n));
}

void GltfReader::readAnimations(RenderScene& scene) const {
  for (size_t a = 0; a < model_.animations.size(); ++a) {
    const tinygltf::Animation& in = model_.animations[a];
    Animation animation;
    animation.name = in.name.empty() ? "animation " + std::to_string(a) : in.name;
    for (size_t c = 0; c < in.channels.size(); ++c) {
      const tinygltf::AnimationChannel& channel = in.channels[c];
      const std::string user = "animation '" + animation.name + "' channel " + std::to_string(c);
      if (channel.target_path == "weights") {
        scene.warnings.push_back(user + ": morph target weights are not animated");
        continue;
      }
      AnimationChannel out;
      out.node = (element(model_.nodes, channel.target_node, "node", user), channel.target_node);
      if (channel.target_path == "translation") out.path = AnimatedPath::Translation;
      else if (channel.target_path == "rotation") out.path = AnimatedPath::Rotation;
      else if (channel.target_path == "scale") out.path = AnimatedPath::Scale;
      else fail(user + " animates unknown property '" + channel.target_path + "'");
      const tinygltf::AnimationSampler& sampler = element(in.samplers, channel.sampler, "sampler", user);
      out.times = readFloats(sampler.input, {TINYGLTF_TYPE_SCALAR}, user + " input");
      const int width = out.path == AnimatedPath::Rotation ? 4 : 3;
      std::vector<float> values =
          readFloats(sampler.output, {out.path == AnimatedPath::Rotation ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3}, user + " output");
      const bool cubic = sampler.interpolation == "CUBICSPLINE";
      out.step = sampler.interpolation == "STEP";
      const size_t perKey = cubic ? 3 : 1;
      if (values.size() != out.times.size() * perKey * size_t(width))
        fail(user + ": " + std::to_string(out.times.size()) + " key times but " + std::to_string(values.size() / width) + " values");
      for (size_t k = 1; k < out.times.size(); ++k)
        if (!(out.times[k] >= out.times[k - 1])) fail(user + ": key times are not ascending");
      if (cubic) {  // keep each key's value, drop its tangents
        for (size_t k = 0; k < out.times.size(); ++k)
          out.values.insert(out.values.end(), values.begin() + long((3 * k + 1) * width), values.begin() + long((3 * k + 2) * width));
      } else {
        out.values = std::move(values);
      }
      animation.channels.push_back(std::move(out));
    }
    if (!animation.channels.empty()) scene.animations.push_back(std::move(animation));
  }
}

RenderScene GltfReader::read() {
  RenderScene scene;
  scene.name = path_.substr(path_.find_last_of('/') + 1);
  for (const tinygltf::Material& material : model_.materials) scene.materials.push_back(readMaterial(material, scene));
  for (size_t m = 0; m < model_.meshes.size(); ++m) {
    Mesh mesh;
    mesh.name = model_.meshes[m].name;
    for (size_t p = 0; p < model_.meshes[m].primitives.size(); ++p)
      mesh.primitives.push_back(readPrimitive(model_.meshes[m].primitives[p],
                                              "mesh " + std::to_string(m) + " primitive " + std::to_string(p), scene));
    scene.meshes.push_back(std::move(mesh));
  }
  for (const tinygltf::Light& in : model_.lights) {
    Light light;
    if (in.type == "directional") light.type = LightType::Directional;
    else if (in.type == "spot") light.type = LightType::Spot;
    else if (in.type == "point") light.type = LightType::Point;
    else fail("light '" + in.name + "' has unknown type '" + in.type + "'");
    if (in.color.size() == 3) light.color = {float(in.color[0]), float(in.color[1]), float(in.color[2])};
    light.intensity = float(in.intensity);
    light.range = float(in.range);
    light.innerConeAngle = float(in.spot.innerConeAngle), light.outerConeAngle = float(in.spot.outerConeAngle);
    scene.lights.push_back(light);
  }
  for (const tinygltf::Camera& in : model_.cameras) {
    Camera camera;
    camera.orthographic = in.type == "orthographic";
    if (camera.orthographic) {
      camera.xmag = float(in.orthographic.xmag), camera.ymag = float(in.orthographic.ymag);
      if (!(camera.xmag != 0.f && camera.ymag != 0.f)) fail("orthographic camera '" + in.name + "' has a zero magnification");
    } else {
      camera.yfov = float(in.perspective.yfov), camera.aspectRatio = float(in.perspective.aspectRatio);
      if (!(camera.yfov > 0.f && camera.yfov < 3.14159f)) fail("camera '" + in.name + "' has yfov " + std::to_string(camera.yfov));
    }
    scene.cameras.push_back(camera);
  }
  readNodes(scene);
  readAnimations(scene);
  if (scene.triangleCount() == 0) fail("the scene has no triangles to render");
  return scene;
}

}  // namespace

RenderScene loadGltfScene(const std::string& path) {
  checkGltfJsonTypes(path);
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string error, warning;
  const bool binary = path.size() >= 4 && (path.compare(path.size() - 4, 4, ".glb") == 0 || path.compare(path.size() - 4, 4, ".GLB") == 0);
  const bool loaded = binary ? loader.LoadBinaryFromFile(&model, &error, &warning, path)
                             : loader.LoadASCIIFromFile(&model, &error, &warning, path);
  if (!loaded) {
    while (!error.empty() && (error.back() == '\n' || error.back() == ' ')) error.pop_back();
    throw std::runtime_error("glTF '" + path + "': " + (error.empty() ? std::string("cannot be read") : error));
  }
  RenderScene scene = GltfReader(model, path).read();
  return scene;
}

}  // namespace obvh::render
