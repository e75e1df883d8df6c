#include "gltf_schema_check.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <stdexcept>

namespace obvh::render {
namespace {

using Json = nlohmann::json;

enum class Kind { Uint, Number, String, Bool, Object, UintArray, NumberArray, StringArray, ObjectArray, UintMap };

struct Rule {
  Kind kind;
  const char* schema = "";  // for ObjectArray / Object: the schema of the elements
};
using Schema = std::map<std::string, Rule>;

const std::map<std::string, Schema>& schemas() {
  static const std::map<std::string, Schema> all = {
      {"root",
       {{"asset", {Kind::Object, "asset"}}, {"scene", {Kind::Uint}}, {"scenes", {Kind::ObjectArray, "scene"}},
        {"nodes", {Kind::ObjectArray, "node"}}, {"meshes", {Kind::ObjectArray, "mesh"}},
        {"accessors", {Kind::ObjectArray, "accessor"}}, {"bufferViews", {Kind::ObjectArray, "bufferView"}},
        {"buffers", {Kind::ObjectArray, "buffer"}}, {"materials", {Kind::ObjectArray, "material"}},
        {"textures", {Kind::ObjectArray, "texture"}}, {"images", {Kind::ObjectArray, "image"}},
        {"samplers", {Kind::ObjectArray, "sampler"}}, {"cameras", {Kind::ObjectArray, "camera"}},
        {"animations", {Kind::ObjectArray, "animation"}}, {"skins", {Kind::ObjectArray, "skin"}},
        {"extensionsUsed", {Kind::StringArray}}, {"extensionsRequired", {Kind::StringArray}}}},
      {"asset", {{"version", {Kind::String}}, {"minVersion", {Kind::String}}, {"generator", {Kind::String}}, {"copyright", {Kind::String}}}},
      {"scene", {{"nodes", {Kind::UintArray}}}},
      {"node",
       {{"children", {Kind::UintArray}}, {"mesh", {Kind::Uint}}, {"camera", {Kind::Uint}}, {"skin", {Kind::Uint}},
        {"matrix", {Kind::NumberArray}}, {"translation", {Kind::NumberArray}}, {"rotation", {Kind::NumberArray}},
        {"scale", {Kind::NumberArray}}, {"weights", {Kind::NumberArray}}}},
      {"mesh", {{"primitives", {Kind::ObjectArray, "primitive"}}, {"weights", {Kind::NumberArray}}}},
      {"primitive", {{"attributes", {Kind::UintMap}}, {"indices", {Kind::Uint}}, {"material", {Kind::Uint}}, {"mode", {Kind::Uint}},
                     {"targets", {Kind::ObjectArray, "target"}}}},
      {"target", {}},
      {"accessor",
       {{"bufferView", {Kind::Uint}}, {"byteOffset", {Kind::Uint}}, {"componentType", {Kind::Uint}}, {"normalized", {Kind::Bool}},
        {"count", {Kind::Uint}}, {"type", {Kind::String}}, {"max", {Kind::NumberArray}}, {"min", {Kind::NumberArray}},
        {"sparse", {Kind::Object, "sparse"}}}},
      {"sparse", {{"count", {Kind::Uint}}, {"indices", {Kind::Object, "any"}}, {"values", {Kind::Object, "any"}}}},
      {"bufferView", {{"buffer", {Kind::Uint}}, {"byteOffset", {Kind::Uint}}, {"byteLength", {Kind::Uint}}, {"byteStride", {Kind::Uint}},
                      {"target", {Kind::Uint}}}},
      {"buffer", {{"uri", {Kind::String}}, {"byteLength", {Kind::Uint}}}},
      {"material",
       {{"pbrMetallicRoughness", {Kind::Object, "pbr"}}, {"normalTexture", {Kind::Object, "textureInfo"}},
        {"occlusionTexture", {Kind::Object, "textureInfo"}}, {"emissiveTexture", {Kind::Object, "textureInfo"}},
        {"emissiveFactor", {Kind::NumberArray}}, {"alphaMode", {Kind::String}}, {"alphaCutoff", {Kind::Number}},
        {"doubleSided", {Kind::Bool}}}},
      {"pbr", {{"baseColorFactor", {Kind::NumberArray}}, {"baseColorTexture", {Kind::Object, "textureInfo"}},
               {"metallicFactor", {Kind::Number}}, {"roughnessFactor", {Kind::Number}},
               {"metallicRoughnessTexture", {Kind::Object, "textureInfo"}}}},
      {"textureInfo", {{"index", {Kind::Uint}}, {"texCoord", {Kind::Uint}}, {"scale", {Kind::Number}}, {"strength", {Kind::Number}}}},
      {"texture", {{"sampler", {Kind::Uint}}, {"source", {Kind::Uint}}}},
      {"image", {{"uri", {Kind::String}}, {"mimeType", {Kind::String}}, {"bufferView", {Kind::Uint}}}},
      {"sampler", {{"magFilter", {Kind::Uint}}, {"minFilter", {Kind::Uint}}, {"wrapS", {Kind::Uint}}, {"wrapT", {Kind::Uint}}}},
      {"camera", {{"type", {Kind::String}}, {"perspective", {Kind::Object, "perspective"}}, {"orthographic", {Kind::Object, "orthographic"}}}},
      {"perspective", {{"aspectRatio", {Kind::Number}}, {"yfov", {Kind::Number}}, {"zfar", {Kind::Number}}, {"znear", {Kind::Number}}}},
      {"orthographic", {{"xmag", {Kind::Number}}, {"ymag", {Kind::Number}}, {"zfar", {Kind::Number}}, {"znear", {Kind::Number}}}},
      {"animation", {{"channels", {Kind::ObjectArray, "channel"}}, {"samplers", {Kind::ObjectArray, "animationSampler"}}}},
      {"channel", {{"sampler", {Kind::Uint}}, {"target", {Kind::Object, "channelTarget"}}}},
      {"channelTarget", {{"node", {Kind::Uint}}, {"path", {Kind::String}}}},
      {"animationSampler", {{"input", {Kind::Uint}}, {"output", {Kind::Uint}}, {"interpolation", {Kind::String}}}},
      {"skin", {{"inverseBindMatrices", {Kind::Uint}}, {"skeleton", {Kind::Uint}}, {"joints", {Kind::UintArray}}}},
      {"any", {}},
  };
  return all;
}

const char* typeName(const Json& v) {
  switch (v.type()) {
    case Json::value_t::object: return "an object";
    case Json::value_t::array: return "an array";
    case Json::value_t::string: return "a string";
    case Json::value_t::boolean: return "a boolean";
    case Json::value_t::number_integer: return v.get<long long>() < 0 ? "a negative integer" : "an integer";
    case Json::value_t::number_unsigned: return "an integer";
    case Json::value_t::number_float: return "a number";
    case Json::value_t::null: return "null";
    default: return "something else";
  }
}

bool isUint(const Json& v) { return v.is_number_unsigned() || (v.is_number_integer() && v.get<long long>() >= 0); }

class TypeChecker {
 public:
  explicit TypeChecker(std::string path) : path_(std::move(path)) {}

  void object(const Json& v, const std::string& where, const std::string& schemaName) {
    if (!v.is_object()) wrong(where, "an object", v);
    const Schema& schema = schemas().at(schemaName);
    for (const auto& [key, value] : v.items()) {
      const std::string at = where.empty() ? key : where + "." + key;
      if (key == "name") {
        if (!value.is_string()) wrong(at, "a string", value);
      } else if (key == "extensions") {
        if (!value.is_object()) wrong(at, "an object", value);
        for (const auto& [extension, body] : value.items())
          if (!body.is_object()) wrong(at + "." + extension, "an object", body);
      } else if (key == "extras") {
        continue;
      } else if (const auto rule = schema.find(key); rule != schema.end()) {
        check(value, at, rule->second);
      }
    }
  }

 private:
  [[noreturn]] void wrong(const std::string& where, const char* expected, const Json& v) const {
    throw std::runtime_error("glTF '" + path_ + "': " + (where.empty() ? "the document" : where) + " must be " + expected +
                             " (it is " + typeName(v) + ")");
  }

  void check(const Json& v, const std::string& at, const Rule& rule) {
    switch (rule.kind) {
      case Kind::Uint: if (!isUint(v)) wrong(at, "a non-negative integer", v); break;
      case Kind::Number: if (!v.is_number()) wrong(at, "a number", v); break;
      case Kind::String: if (!v.is_string()) wrong(at, "a string", v); break;
      case Kind::Bool: if (!v.is_boolean()) wrong(at, "a boolean", v); break;
      case Kind::Object: object(v, at, rule.schema); break;
      case Kind::UintArray:
      case Kind::NumberArray:
      case Kind::StringArray:
      case Kind::ObjectArray:
        if (!v.is_array()) wrong(at, "an array", v);
        for (size_t i = 0; i < v.size(); ++i) {
          const std::string element = at + "[" + std::to_string(i) + "]";
          if (rule.kind == Kind::UintArray && !isUint(v[i])) wrong(element, "a non-negative integer", v[i]);
          if (rule.kind == Kind::NumberArray && !v[i].is_number()) wrong(element, "a number", v[i]);
          if (rule.kind == Kind::StringArray && !v[i].is_string()) wrong(element, "a string", v[i]);
          if (rule.kind == Kind::ObjectArray) object(v[i], element, rule.schema);
        }
        break;
      case Kind::UintMap:
        if (!v.is_object()) wrong(at, "an object", v);
        for (const auto& [key, value] : v.items())
          if (!isUint(value)) wrong(at + "." + key, "a non-negative integer", value);
        break;
    }
  }

  std::string path_;
};

std::string jsonText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("glTF '" + path + "': cannot open the file");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 4 || bytes.compare(0, 4, "glTF") != 0) return bytes;
  // GLB: 12-byte header, then the JSON chunk (length, type "JSON", data).
  uint32_t length = 0, type = 0;
  if (bytes.size() < 20) throw std::runtime_error("glTF '" + path + "': the binary header is truncated");
  std::memcpy(&length, bytes.data() + 12, 4);
  std::memcpy(&type, bytes.data() + 16, 4);
  if (type != 0x4E4F534Au || size_t(length) > bytes.size() - 20)
    throw std::runtime_error("glTF '" + path + "': the binary file's first chunk is not a complete JSON chunk");
  return bytes.substr(20, length);
}

}  // namespace

void checkGltfJsonTypes(const std::string& path) {
  const Json document = Json::parse(jsonText(path), nullptr, false);
  if (document.is_discarded()) return;  // tinygltf reports the syntax error with its position
  TypeChecker(path).object(document, "", "root");
  static const std::set<std::string> readable = {
      "KHR_lights_punctual", "KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_dispersion",
      "KHR_materials_emissive_strength", "KHR_materials_volume", "KHR_materials_specular", "KHR_texture_transform",
      "KHR_materials_unlit", "KHR_mesh_quantization"};
  if (document.contains("extensionsRequired"))
    for (const Json& required : document["extensionsRequired"])
      if (!readable.count(required.get<std::string>()))
        throw std::runtime_error("glTF '" + path + "': requires extension " + required.get<std::string>() +
                                 ", which obvh's renderer does not read");
}

}  // namespace obvh::render
