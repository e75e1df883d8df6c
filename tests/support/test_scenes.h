// Procedural scenes for the tests: triangle soups, closed meshes, quad meshes, multi-geometry scenes.
#pragma once

#include <cstdint>

#include "scene_data.h"

namespace obvh::test {

using tools::MeshData;
using tools::SceneData;

// count triangles with random positions and sizes spanning two orders of magnitude in [0,1]^3.
MeshData randomTriangleSoup(size_t count, uint32_t seed);

// Closed icosphere of radius r around c, each face split into 4^subdivisions triangles.
MeshData icosphere(int subdivisions, float radius, const float center[3]);

// Closed axis-aligned box made of six quads (or twelve triangles when asQuads is false).
MeshData box(const float lower[3], const float upper[3], bool asQuads);

// n x n grid of quads over [0,1]^2 with random height jitter (non-planar quads when jitter > 0).
MeshData quadGrid(int n, float jitter, uint32_t seed);

// Fan of `count` triangles sharing the vertex at the origin, in the z = 0 plane.
MeshData triangleFan(int count);

// Adds an offset to every vertex and scales about the origin.
void transformMesh(MeshData& mesh, float scale, const float offset[3]);

}  // namespace obvh::test
