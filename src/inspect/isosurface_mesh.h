// `yarnvox inspect --mesh FILE.ply|obj`: the density grid's isosurface as a
// polygon mesh, extracted by OpenVDB's own mesher (tools::volumeToMesh), at
// full resolution or at a coarser level of detail. Vertices are in voxel
// coordinates of the full-resolution grid (voxel (i, j, k) fills
// [i, i+1) x [j, j+1) x [k, k+1)), as in the renders.
#pragma once

#include "inspect/volume_source.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace yv {

struct IsosurfaceMesh {
    std::vector<glm::vec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles; ///< counter-clockwise seen from outside (low density)
};

/// Triangles a mesh at `level` is expected to have: 384 per occupied brick
/// of that level. Yarns a few voxels thick cross an 8^3 brick several
/// times: the real sweater at 2048 has 311 triangles a brick at iso 0.5,
/// the demo garment 104.
std::uint64_t estimateMeshTriangles(const VolumeSource& source, const VoxelBox& box, int level);

/// The most triangles `--mesh` writes without --mesh-level (about 2 GB as binary PLY).
constexpr std::uint64_t kMeshTriangleLimit = 100'000'000;

/// The isosurface of the density at `isoValue` over the bricks in `box`, at
/// `level` (each voxel the mean of the 2^level cube under it). Throws
/// yv::Error when the surface is empty (no voxel reaches the iso value).
IsosurfaceMesh extractIsosurface(const VolumeSource& source, const VoxelBox& box, double isoValue, int level);

/// Writes `mesh` as binary little-endian PLY (.ply) or Wavefront OBJ (.obj),
/// by the path's extension, atomically. Throws yv::Error naming `path`.
void writeMesh(const std::string& path, const IsosurfaceMesh& mesh);

/// Throws yv::Error unless `path` ends in .ply or .obj.
void checkMeshPath(const std::string& path);

} // namespace yv
