#include "gltf_builder.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace obvh::tools {

void TriangleList::quad(const std::array<float, 3>& a, const std::array<float, 3>& b, const std::array<float, 3>& c,
                        const std::array<float, 3>& d) {
  const uint32_t base = uint32_t(positions.size() / 3);
  for (const auto* p : {&a, &b, &c, &d}) positions.insert(positions.end(), p->begin(), p->end());
  uvs.insert(uvs.end(), {0.f, 1.f, 1.f, 1.f, 1.f, 0.f, 0.f, 0.f});
  indices.insert(indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

void TriangleList::triangle(const std::array<float, 3>& a, const std::array<float, 3>& b, const std::array<float, 3>& c) {
  const uint32_t base = uint32_t(positions.size() / 3);
  for (const auto* p : {&a, &b, &c}) positions.insert(positions.end(), p->begin(), p->end());
  uvs.insert(uvs.end(), {0.f, 0.f, 1.f, 0.f, 0.f, 1.f});
  indices.insert(indices.end(), {base, base + 1, base + 2});
}

void TriangleList::box(const std::array<float, 3>& l, const std::array<float, 3>& u) {
  quad({l[0], l[1], u[2]}, {u[0], l[1], u[2]}, {u[0], u[1], u[2]}, {l[0], u[1], u[2]});  // +z
  quad({u[0], l[1], l[2]}, {l[0], l[1], l[2]}, {l[0], u[1], l[2]}, {u[0], u[1], l[2]});  // -z
  quad({u[0], l[1], u[2]}, {u[0], l[1], l[2]}, {u[0], u[1], l[2]}, {u[0], u[1], u[2]});  // +x
  quad({l[0], l[1], l[2]}, {l[0], l[1], u[2]}, {l[0], u[1], u[2]}, {l[0], u[1], l[2]});  // -x
  quad({l[0], u[1], u[2]}, {u[0], u[1], u[2]}, {u[0], u[1], l[2]}, {l[0], u[1], l[2]});  // +y
  quad({l[0], l[1], l[2]}, {u[0], l[1], l[2]}, {u[0], l[1], u[2]}, {l[0], l[1], u[2]});  // -y
}

GltfBuilder::GltfBuilder() : model_(new tinygltf::Model) {
  model_->asset.version = "2.0";
  model_->asset.generator = "obvh_scenegen";
  model_->buffers.emplace_back();
}

GltfBuilder::~GltfBuilder() { delete model_; }

int GltfBuilder::addAccessor(const void* data, size_t bytes, int componentType, int type, size_t count,
                             const std::vector<double>& lo, const std::vector<double>& hi) {
  std::vector<unsigned char>& buffer = model_->buffers[0].data;
  while (buffer.size() % 4) buffer.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0, view.byteOffset = buffer.size(), view.byteLength = bytes;
  buffer.resize(buffer.size() + bytes);
  std::memcpy(buffer.data() + view.byteOffset, data, bytes);
  model_->bufferViews.push_back(view);
  tinygltf::Accessor accessor;
  accessor.bufferView = int(model_->bufferViews.size() - 1);
  accessor.componentType = componentType, accessor.type = type, accessor.count = count;
  accessor.minValues = lo, accessor.maxValues = hi;
  model_->accessors.push_back(accessor);
  return int(model_->accessors.size() - 1);
}

int GltfBuilder::addMaterial(const GltfMaterialDesc& d) {
  tinygltf::Material m;
  m.name = d.name;
  m.pbrMetallicRoughness.baseColorFactor.assign(d.baseColor.begin(), d.baseColor.end());
  m.pbrMetallicRoughness.metallicFactor = 0.0;
  m.pbrMetallicRoughness.roughnessFactor = 0.5;
  m.pbrMetallicRoughness.baseColorTexture.index = d.baseColorTexture;
  m.emissiveFactor.assign(d.emissive.begin(), d.emissive.end());
  m.alphaMode = d.alphaMode;
  m.alphaCutoff = d.alphaCutoff;
  const auto extension = [&](const std::string& name, const std::string& key, double value) {
    tinygltf::Value::Object object;
    object[key] = tinygltf::Value(value);
    m.extensions[name] = tinygltf::Value(object);
    if (std::find(model_->extensionsUsed.begin(), model_->extensionsUsed.end(), name) == model_->extensionsUsed.end())
      model_->extensionsUsed.push_back(name);
  };
  if (d.transmission > 0.0) extension("KHR_materials_transmission", "transmissionFactor", d.transmission);
  if (d.ior != 1.5) extension("KHR_materials_ior", "ior", d.ior);
  if (d.dispersion > 0.0) extension("KHR_materials_dispersion", "dispersion", d.dispersion);
  model_->materials.push_back(m);
  return int(model_->materials.size() - 1);
}

int GltfBuilder::addTexture(int width, int height, const std::vector<uint8_t>& rgba) {
  tinygltf::Image image;
  image.width = width, image.height = height, image.component = 4, image.bits = 8;
  image.pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  image.image = rgba;
  image.mimeType = "image/png";
  model_->images.push_back(image);
  tinygltf::Sampler sampler;
  sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  model_->samplers.push_back(sampler);
  tinygltf::Texture texture;
  texture.source = int(model_->images.size() - 1);
  texture.sampler = int(model_->samplers.size() - 1);
  model_->textures.push_back(texture);
  return int(model_->textures.size() - 1);
}

int GltfBuilder::addMesh(const std::string& name, const TriangleList& t, int material) {
  std::vector<double> lo(3, std::numeric_limits<double>::infinity()), hi(3, -std::numeric_limits<double>::infinity());
  for (size_t i = 0; i < t.positions.size(); ++i)
    lo[i % 3] = std::min(lo[i % 3], double(t.positions[i])), hi[i % 3] = std::max(hi[i % 3], double(t.positions[i]));
  tinygltf::Primitive primitive;
  primitive.attributes["POSITION"] = addAccessor(t.positions.data(), t.positions.size() * 4, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                                 TINYGLTF_TYPE_VEC3, t.positions.size() / 3, lo, hi);
  if (!t.uvs.empty())
    primitive.attributes["TEXCOORD_0"] =
        addAccessor(t.uvs.data(), t.uvs.size() * 4, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, t.uvs.size() / 2);
  primitive.indices = addAccessor(t.indices.data(), t.indices.size() * 4, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                  TINYGLTF_TYPE_SCALAR, t.indices.size());
  primitive.material = material;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  tinygltf::Mesh mesh;
  mesh.name = name;
  mesh.primitives.push_back(primitive);
  model_->meshes.push_back(mesh);
  return int(model_->meshes.size() - 1);
}

int GltfBuilder::addNode(const std::string& name, int mesh, const std::array<float, 3>& translation,
                         const std::array<float, 4>& rotation, const std::array<float, 3>& scale) {
  tinygltf::Node node;
  node.name = name;
  node.mesh = mesh;
  node.translation.assign(translation.begin(), translation.end());
  if (rotation != std::array<float, 4>{0, 0, 0, 1}) node.rotation.assign(rotation.begin(), rotation.end());
  if (scale != std::array<float, 3>{1, 1, 1}) node.scale.assign(scale.begin(), scale.end());
  model_->nodes.push_back(node);
  roots_.push_back(int(model_->nodes.size() - 1));
  return roots_.back();
}

void GltfBuilder::addChild(int parent, int child) {
  model_->nodes.at(size_t(parent)).children.push_back(child);
  roots_.erase(std::remove(roots_.begin(), roots_.end(), child), roots_.end());
}

int GltfBuilder::addLight(const std::string& type, const std::array<float, 3>& colour, double intensity,
                          const std::array<float, 3>& position, const std::array<float, 4>& rotation) {
  tinygltf::Light light;
  light.type = type;
  light.color.assign(colour.begin(), colour.end());
  light.intensity = intensity;
  if (type == "spot") light.spot.innerConeAngle = 0.3, light.spot.outerConeAngle = 0.6;
  model_->lights.push_back(light);
  if (std::find(model_->extensionsUsed.begin(), model_->extensionsUsed.end(), "KHR_lights_punctual") == model_->extensionsUsed.end())
    model_->extensionsUsed.push_back("KHR_lights_punctual");
  const int node = addNode(type + " light", -1, position, rotation);
  tinygltf::Value::Object reference;
  reference["light"] = tinygltf::Value(int(model_->lights.size() - 1));
  model_->nodes[size_t(node)].extensions["KHR_lights_punctual"] = tinygltf::Value(reference);
  return node;
}

int GltfBuilder::addCamera(const std::array<float, 3>& eye, const std::array<float, 3>& target, double yfov) {
  tinygltf::Camera camera;
  camera.type = "perspective";
  camera.perspective.yfov = yfov;
  camera.perspective.znear = 0.01;
  model_->cameras.push_back(camera);
  // Rotation taking -Z to the viewing direction with +Y kept up: yaw about Y, then pitch about X.
  const double dx = target[0] - eye[0], dy = target[1] - eye[1], dz = target[2] - eye[2];
  const double yaw = std::atan2(-dx, -dz), pitch = std::atan2(dy, std::sqrt(dx * dx + dz * dz));
  const double cy = std::cos(yaw / 2), sy = std::sin(yaw / 2), cp = std::cos(pitch / 2), sp = std::sin(pitch / 2);
  const std::array<float, 4> rotation{float(cy * sp), float(sy * cp), float(-sy * sp), float(cy * cp)};
  const int node = addNode("camera", -1, eye, rotation);
  model_->nodes[size_t(node)].camera = int(model_->cameras.size() - 1);
  return node;
}

void GltfBuilder::animate(int node, const std::string& path, const std::vector<float>& times, const std::vector<float>& values) {
  if (model_->animations.empty()) model_->animations.emplace_back(), model_->animations[0].name = "motion";
  tinygltf::Animation& animation = model_->animations[0];
  tinygltf::AnimationSampler sampler;
  sampler.input = addAccessor(times.data(), times.size() * 4, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR,
                              times.size(), {double(times.front())}, {double(times.back())});
  const int width = path == "rotation" ? 4 : 3;
  sampler.output = addAccessor(values.data(), values.size() * 4, TINYGLTF_COMPONENT_TYPE_FLOAT,
                               width == 4 ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3, values.size() / size_t(width));
  sampler.interpolation = "LINEAR";
  animation.samplers.push_back(sampler);
  tinygltf::AnimationChannel channel;
  channel.sampler = int(animation.samplers.size() - 1);
  channel.target_node = node;
  channel.target_path = path;
  animation.channels.push_back(channel);
}

void GltfBuilder::write(const std::string& path) {
  tinygltf::Scene scene;
  scene.nodes = roots_;
  model_->scenes = {scene};
  model_->defaultScene = 0;
  const bool binary = path.size() > 4 && path.compare(path.size() - 4, 4, ".glb") == 0;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToFile(model_, path, true, true, !binary, binary)) throw std::runtime_error("cannot write '" + path + "'");
}

}  // namespace obvh::tools
