// The PLY reader on small files written by the test: ASCII and binary little-endian, polygons,
// skipped properties, and broken files that must be reported by name, never crash.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "mesh_loader.h"
#include "reader_test_files.h"
#include "ply_reader.h"

namespace obvh::tools {
namespace {

std::string errorOf(const std::string& path) { return readError(readPly, path); }

TEST(PlyReader, AsciiWithQuadAndExtraProperties) {
  const std::string path = writeFile("quad.ply",
                                     "ply\nformat ascii 1.0\ncomment test\nelement vertex 4\nproperty float x\n"
                                     "property float y\nproperty float z\nproperty uchar red\nelement face 1\n"
                                     "property list uchar int vertex_indices\nproperty int flags\nend_header\n"
                                     "0 0 0 255\n1 0 0 0\n1 1 0 0\n0 1 0.5 0\n4 0 1 2 3 7\n");
  const MeshData mesh = readPly(path);
  EXPECT_EQ(mesh.vertices, (std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0.5f}));
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(loadMesh(path).meshes.at(0).primitiveCount(), 2u);
}

TEST(PlyReader, BinaryLittleEndian) {
  std::string body;
  auto put = [&](const void* p, size_t n) { body.append(static_cast<const char*>(p), n); };
  const double xyz[3][3] = {{0, 0, 0}, {2, 0, 0}, {0, 3, 1}};
  for (const auto& v : xyz) put(v, sizeof v);
  const unsigned char three = 3;
  const uint32_t face[3] = {2, 1, 0};
  put(&three, 1);
  put(face, sizeof face);
  const std::string path = writeFile("tri.ply",
                                     "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\n"
                                     "property double y\nproperty double z\nelement face 1\n"
                                     "property list uchar uint vertex_index\nend_header\n" + body);
  const MeshData mesh = readPly(path);
  EXPECT_EQ(mesh.vertices, (std::vector<float>{0, 0, 0, 2, 0, 0, 0, 3, 1}));
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{2, 1, 0}));
}

TEST(PlyReader, BrokenFilesAreReportedByName) {
  const std::string header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                             "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  EXPECT_NE(errorOf(writeFile("range.ply", header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n")).find("out of range"),
            std::string::npos);
  EXPECT_NE(errorOf(writeFile("short.ply", header + "0 0 0\n1 0 0\n")).find("ends early"), std::string::npos);
  EXPECT_NE(errorOf(writeFile("big.ply", "ply\nformat binary_big_endian 1.0\nend_header\n")).find("big-endian"),
            std::string::npos);
  EXPECT_NE(errorOf(writeFile("noply.ply", "solid cube\n")).find("not a PLY file"), std::string::npos);
  EXPECT_NE(errorOf(::testing::TempDir() + "missing.ply").find("cannot open"), std::string::npos);
  EXPECT_NE(errorOf(writeFile("noxyz.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n"))
                .find("without x, y and z"),
            std::string::npos);
  EXPECT_THROW(loadMesh("scene.3ds"), std::runtime_error);
}

}  // namespace
}  // namespace obvh::tools
