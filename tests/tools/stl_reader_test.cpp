// The STL reader on small files written by the test: ASCII and binary (also binary files whose
// header begins with "solid"), merged vertices, and broken files reported by name.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "mesh_loader.h"
#include "reader_test_files.h"
#include "stl_reader.h"

namespace obvh::tools {
namespace {

std::string errorOf(const std::string& path) { return readError(readStl, path); }

// Two triangles of the unit square sharing the diagonal (0,0,0)-(1,1,0).
const float kSquare[2][3][3] = {{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, {{0, 0, 0}, {1, 1, 0}, {0, 1, 0}}};

std::string asciiSquare() {
  std::string s = "solid square\n";
  for (const auto& facet : kSquare) {
    s += "  facet normal 0 0 1\n    outer loop\n";
    for (const auto& v : facet)
      s += "      vertex " + std::to_string(v[0]) + " " + std::to_string(v[1]) + " " + std::to_string(v[2]) + "\n";
    s += "    endloop\n  endfacet\n";
  }
  return s + "endsolid square\n";
}

std::string binarySquare(const std::string& header) {
  std::string s = header;
  s.resize(80, ' ');
  const uint32_t count = 2;
  s.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& facet : kSquare) {
    const float normal[3] = {0, 0, 1};
    s.append(reinterpret_cast<const char*>(normal), 12);
    for (const auto& v : facet) s.append(reinterpret_cast<const char*>(v), 12);
    s.append(2, '\0');
  }
  return s;
}

void expectSquare(const MeshData& mesh) {
  ASSERT_EQ(mesh.primitiveCount(), 2u);
  EXPECT_EQ(mesh.vertexCount(), 4u) << "the shared diagonal's two vertices are merged";
  for (int f = 0; f < 2; ++f)
    for (int v = 0; v < 3; ++v)
      for (int k = 0; k < 3; ++k)
        EXPECT_EQ(mesh.vertices[3 * mesh.indices[size_t(3 * f + v)] + size_t(k)], kSquare[f][v][k]) << f << v << k;
}

TEST(StlReader, AsciiAndBinaryFilesGiveTheSameMergedMesh) {
  expectSquare(readStl(writeFile("square_ascii.stl", asciiSquare())));
  expectSquare(readStl(writeFile("square_binary.stl", binarySquare("binary square"))));
  // Many exporters start binary headers with "solid": the size decides.
  expectSquare(readStl(writeFile("square_solid_binary.stl", binarySquare("solid exported by some CAD tool"))));
  expectSquare(loadMesh(writeFile("square_loaded.stl", asciiSquare())).meshes.at(0));
}

TEST(StlReader, BrokenFilesAreReportedByName) {
  std::string twoVertices = asciiSquare();
  twoVertices.erase(twoVertices.find("      vertex 1.0"), twoVertices.find("\n", twoVertices.find("      vertex 1.0")) + 1 - twoVertices.find("      vertex 1.0"));
  const std::string missing = errorOf(writeFile("two_vertices.stl", twoVertices));
  EXPECT_NE(missing.find("without three vertices"), std::string::npos) << missing;
  EXPECT_NE(missing.find("two_vertices.stl"), std::string::npos) << missing;
  std::string badNumber = asciiSquare();
  badNumber.replace(badNumber.find("vertex 0.0"), 10, "vertex abc");
  EXPECT_NE(errorOf(writeFile("bad_number.stl", badNumber)).find("bad vertex line on line"), std::string::npos);
  std::string infinite = binarySquare("inf");
  const float inf = std::numeric_limits<float>::infinity();
  std::memcpy(&infinite[84 + 12], &inf, 4);
  EXPECT_NE(errorOf(writeFile("infinite.stl", infinite)).find("non-finite"), std::string::npos);
  std::string truncated = binarySquare("truncated");
  truncated.resize(truncated.size() - 10);
  EXPECT_NE(errorOf(writeFile("truncated.stl", truncated)).find("neither ASCII STL"), std::string::npos);
  std::string open = asciiSquare();
  open.resize(open.find("endloop"));
  EXPECT_NE(errorOf(writeFile("open.stl", open)).find("ends inside a facet"), std::string::npos);
  EXPECT_NE(errorOf(writeFile("empty.stl", "solid nothing\nendsolid nothing\n")).find("has no facets"), std::string::npos);
  EXPECT_NE(errorOf(writeFile("tiny.stl", "abc")).find("too short"), std::string::npos);
  EXPECT_NE(errorOf(::testing::TempDir() + "missing.stl").find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace obvh::tools
