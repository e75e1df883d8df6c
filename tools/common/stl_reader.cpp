#include "stl_reader.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace obvh::tools {
namespace {

class StlMeshBuilder {
 public:
  explicit StlMeshBuilder(const std::string& path) : path_(path) {}

  [[noreturn]] void fail(const std::string& what) const { throw std::runtime_error("STL '" + path_ + "' " + what); }

  // where() says where the vertex is, for the error only.
  template <typename Where>
  void addVertex(const float p[3], Where&& where) {
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(p[k])) fail("has a non-finite vertex coordinate " + where());
    uint32_t bits[3];
    std::memcpy(bits, p, sizeof bits);
    const Key key{bits[0], bits[1], bits[2]};
    auto [it, inserted] = index_.try_emplace(key, uint32_t(mesh_.vertexCount()));
    if (inserted) mesh_.vertices.insert(mesh_.vertices.end(), {p[0], p[1], p[2]});
    mesh_.indices.push_back(it->second);
  }

  MeshData finish() {
    if (mesh_.indices.empty()) fail("has no facets");
    return std::move(mesh_);
  }

 private:
  struct Key {
    uint32_t x, y, z;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct KeyHash {
    size_t operator()(const Key& k) const { return (size_t(k.x) * 0x9E3779B97F4A7C15ull) ^ (size_t(k.y) * 0xC2B2AE3D27D4EB4Full) ^ k.z; }
  };

  std::string path_;
  MeshData mesh_;
  std::unordered_map<Key, uint32_t, KeyHash> index_;
};

constexpr size_t kBinaryHeader = 84, kBinaryFacet = 50;

MeshData readBinary(const std::string& bytes, uint32_t facets, StlMeshBuilder& builder) {
  for (uint32_t f = 0; f < facets; ++f) {
    const char* facet = bytes.data() + kBinaryHeader + size_t(f) * kBinaryFacet;
    for (int v = 0; v < 3; ++v) {
      float p[3];
      std::memcpy(p, facet + 12 * (v + 1), sizeof p);  // after the facet normal
      builder.addVertex(p, [f] { return "in facet " + std::to_string(f); });
    }
  }
  return builder.finish();
}

MeshData readAscii(const std::string& text, StlMeshBuilder& builder) {
  std::istringstream in(text);
  std::string line;
  int lineNumber = 0, verticesInFacet = -1;
  while (std::getline(in, line)) {
    ++lineNumber;
    std::istringstream words(line);
    std::string keyword;
    if (!(words >> keyword)) continue;
    const auto where = [lineNumber] { return "on line " + std::to_string(lineNumber); };
    if (keyword == "facet") {
      if (verticesInFacet >= 0) builder.fail("starts a facet inside another " + where());
      verticesInFacet = 0;
    } else if (keyword == "vertex") {
      if (verticesInFacet < 0) builder.fail("has a vertex outside a facet " + where());
      float p[3];
      std::string rest;
      if (!(words >> p[0] >> p[1] >> p[2]) || (words >> rest)) builder.fail("has a bad vertex line " + where() + ": " + line);
      if (++verticesInFacet > 3) builder.fail("has a facet with more than three vertices " + where());
      builder.addVertex(p, where);
    } else if (keyword == "endfacet") {
      if (verticesInFacet != 3) builder.fail("has a facet without three vertices, ending " + where());
      verticesInFacet = -1;
    } else if (keyword != "solid" && keyword != "endsolid" && keyword != "outer" && keyword != "endloop") {
      builder.fail("has an unknown keyword '" + keyword + "' " + where());
    }
  }
  if (verticesInFacet >= 0) builder.fail("ends inside a facet");
  return builder.finish();
}

}  // namespace

MeshData readStl(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw std::runtime_error("cannot open '" + path + "'");
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  StlMeshBuilder builder(path);
  if (bytes.size() >= kBinaryHeader) {
    uint32_t facets = 0;
    std::memcpy(&facets, bytes.data() + 80, sizeof facets);
    if (bytes.size() == kBinaryHeader + size_t(facets) * kBinaryFacet) return readBinary(bytes, facets, builder);
  }
  if (bytes.compare(0, 5, "solid") == 0) return readAscii(bytes, builder);
  builder.fail(bytes.size() < kBinaryHeader ? "is too short for an STL file"
                                            : "is neither ASCII STL (no leading 'solid') nor binary STL (its size does "
                                              "not match the facet count at byte 80)");
}

}  // namespace obvh::tools
