#include "ply_reader.h"

#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace obvh::tools {
namespace {

enum class Scalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool parseScalar(const std::string& name, Scalar& out) {
  static const std::pair<const char*, Scalar> names[] = {
      {"char", Scalar::Int8},     {"int8", Scalar::Int8},     {"uchar", Scalar::UInt8},   {"uint8", Scalar::UInt8},
      {"short", Scalar::Int16},   {"int16", Scalar::Int16},   {"ushort", Scalar::UInt16}, {"uint16", Scalar::UInt16},
      {"int", Scalar::Int32},     {"int32", Scalar::Int32},   {"uint", Scalar::UInt32},   {"uint32", Scalar::UInt32},
      {"float", Scalar::Float32}, {"float32", Scalar::Float32}, {"double", Scalar::Float64}, {"float64", Scalar::Float64}};
  for (const auto& [text, scalar] : names)
    if (name == text) {
      out = scalar;
      return true;
    }
  return false;
}

size_t sizeOf(Scalar s) {
  switch (s) {
    case Scalar::Int8: case Scalar::UInt8: return 1;
    case Scalar::Int16: case Scalar::UInt16: return 2;
    case Scalar::Int32: case Scalar::UInt32: case Scalar::Float32: return 4;
    case Scalar::Float64: return 8;
  }
  return 0;
}

struct Property {
  std::string name;
  Scalar type = Scalar::Float32;
  bool isList = false;
  Scalar countType = Scalar::UInt8;
};

struct Element {
  std::string name;
  size_t count = 0;
  std::vector<Property> properties;
};

// Values come either from whitespace-separated text or from little-endian bytes.
class ValueSource {
 public:
  ValueSource(std::istream& in, bool binary, const std::string& path) : in_(in), binary_(binary), path_(path) {}

  double read(Scalar type) {
    if (!binary_) {
      double v;
      if (!(in_ >> v)) fail("ends early or holds a value that is not a number");
      return v;
    }
    unsigned char bytes[8];
    if (!in_.read(reinterpret_cast<char*>(bytes), std::streamsize(sizeOf(type)))) fail("ends early");
    switch (type) {
      case Scalar::Int8: return double(int8_t(bytes[0]));
      case Scalar::UInt8: return double(bytes[0]);
      case Scalar::Int16: { int16_t v; std::memcpy(&v, bytes, 2); return v; }
      case Scalar::UInt16: { uint16_t v; std::memcpy(&v, bytes, 2); return v; }
      case Scalar::Int32: { int32_t v; std::memcpy(&v, bytes, 4); return v; }
      case Scalar::UInt32: { uint32_t v; std::memcpy(&v, bytes, 4); return v; }
      case Scalar::Float32: { float v; std::memcpy(&v, bytes, 4); return v; }
      case Scalar::Float64: { double v; std::memcpy(&v, bytes, 8); return v; }
    }
    return 0.0;
  }

  [[noreturn]] void fail(const std::string& what) const { throw std::runtime_error("PLY '" + path_ + "' " + what); }

 private:
  std::istream& in_;
  bool binary_;
  const std::string& path_;
};

std::vector<Element> readHeader(std::istream& in, const std::string& path, bool& binary) {
  std::string line;
  if (!std::getline(in, line) || line.rfind("ply", 0) != 0) throw std::runtime_error("'" + path + "' is not a PLY file");
  std::vector<Element> elements;
  bool formatSeen = false;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "end_header") {
      if (!formatSeen) throw std::runtime_error("PLY '" + path + "' has no format line");
      return elements;
    }
    if (keyword == "format") {
      std::string format;
      words >> format;
      if (format == "binary_big_endian")
        throw std::runtime_error("PLY '" + path + "' is big-endian binary, which obvh does not read");
      if (format != "ascii" && format != "binary_little_endian")
        throw std::runtime_error("PLY '" + path + "' has an unknown format '" + format + "'");
      binary = format != "ascii";
      formatSeen = true;
    } else if (keyword == "element") {
      Element e;
      long long count = -1;
      words >> e.name >> count;
      if (count < 0) throw std::runtime_error("PLY '" + path + "' has a bad element line: " + line);
      e.count = size_t(count);
      elements.push_back(e);
    } else if (keyword == "property") {
      if (elements.empty()) throw std::runtime_error("PLY '" + path + "' declares a property before any element");
      Property p;
      std::string type;
      words >> type;
      if (type == "list") {
        std::string countType, itemType;
        words >> countType >> itemType >> p.name;
        p.isList = true;
        if (!parseScalar(countType, p.countType) || !parseScalar(itemType, p.type))
          throw std::runtime_error("PLY '" + path + "' has an unknown list type: " + line);
      } else {
        words >> p.name;
        if (!parseScalar(type, p.type)) throw std::runtime_error("PLY '" + path + "' has an unknown type: " + line);
      }
      elements.back().properties.push_back(p);
    }  // comment, obj_info: ignored
  }
  throw std::runtime_error("PLY '" + path + "' has no end_header");
}

}  // namespace

MeshData readPly(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open mesh file '" + path + "'");
  bool binary = false;
  const std::vector<Element> elements = readHeader(in, path, binary);
  ValueSource source(in, binary, path);
  MeshData mesh;
  size_t vertexCount = 0;
  bool verticesSeen = false;
  for (const Element& e : elements) {
    if (e.name == "vertex") {
      int axisOf[64];
      if (e.properties.size() > 64) source.fail("has too many vertex properties");
      int found = 0;
      for (size_t p = 0; p < e.properties.size(); ++p) {
        const std::string& n = e.properties[p].name;
        axisOf[p] = n == "x" ? 0 : n == "y" ? 1 : n == "z" ? 2 : -1;
        if (axisOf[p] >= 0) found |= 1 << axisOf[p];
      }
      if (found != 7) source.fail("has vertices without x, y and z");
      mesh.vertices.resize(3 * e.count);
      for (size_t v = 0; v < e.count; ++v)
        for (size_t p = 0; p < e.properties.size(); ++p) {
          const Property& prop = e.properties[p];
          const size_t items = prop.isList ? size_t(source.read(prop.countType)) : 1;
          for (size_t i = 0; i < items; ++i) {
            const double value = source.read(prop.type);
            if (axisOf[p] >= 0 && !prop.isList) mesh.vertices[3 * v + size_t(axisOf[p])] = float(value);
          }
        }
      vertexCount = e.count;
      verticesSeen = true;
    } else {
      const bool faces = e.name == "face";
      if (faces && !verticesSeen) source.fail("lists faces before vertices");
      for (size_t f = 0; f < e.count; ++f)
        for (const Property& prop : e.properties) {
          const size_t items = prop.isList ? size_t(source.read(prop.countType)) : 1;
          const bool indices = faces && prop.isList && (prop.name == "vertex_indices" || prop.name == "vertex_index");
          std::vector<uint32_t> polygon;
          for (size_t i = 0; i < items; ++i) {
            const double value = source.read(prop.type);
            if (!indices) continue;
            if (value < 0 || value >= double(vertexCount)) source.fail("has a face index out of range");
            polygon.push_back(uint32_t(value));
          }
          for (size_t k = 2; k < polygon.size(); ++k)
            mesh.indices.insert(mesh.indices.end(), {polygon[0], polygon[k - 1], polygon[k]});
        }
    }
  }
  if (mesh.indices.empty()) source.fail("has no faces");
  return mesh;
}

}  // namespace obvh::tools
