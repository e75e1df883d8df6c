// Procedural meshes for the tests and the accuracy study: triangle soups, closed meshes, quad meshes.
#pragma once

#include <cstdint>

#include "scene_data.h"

namespace obvh::tools {

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

// Closed axis-aligned box whose faces are n x n grids of triangle pairs (shared edges everywhere).
MeshData cubeGrid(int n, const float lower[3], const float upper[3]);

// Closed double cone: a ring of `count` vertices of radius r around c joined to two apices at
// c +- height on z, so `count` long thin triangles meet at each apex.
MeshData closedFan(int count, float radius, float height, const float center[3]);

// Adds an offset to every vertex and scales about the origin.
void transformMesh(MeshData& mesh, float scale, const float offset[3]);

// A grid mesh (RTC_GEOMETRY_TYPE_GRID) over one jittered height field of (n + 1) x (n + 1) vertices
// in [0,1]^2: grids of several sizes cut from it at strides wider than themselves, neighbours
// sharing their border vertices. (No grid of one row or column: Debian's Embree aborts on those.)
MeshData gridPatches(int n, float jitter, uint32_t seed);

// The cells of a grid mesh as a quad mesh over the same vertices (cell by cell, grid by grid).
MeshData gridCellsAsQuads(const MeshData& gridMesh);

// The mesh set in motion (motion blur) with steps - 1 later time steps: it slides along x while
// each vertex wanders on its own, so its primitives change shape between steps.
MeshData moving(MeshData mesh, int steps, uint32_t seed);

}  // namespace obvh::tools
