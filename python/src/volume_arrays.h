// A yarnvox .vdb's grids as numpy arrays, read through OpenVDB: a dense box
// of one level, or the level's leaves (8^3 blocks) as they are stored.
#pragma once

#include <pybind11/pybind11.h>

#include <array>
#include <optional>
#include <string>

namespace yv::python {

/// The grids of level `level` (0: `density`, L: `density_lodL`, and the
/// `orientation` and `albedo` grids beside it) of the .vdb at `path` as a
/// dict of arrays over a box of voxel indices: `box` (min inclusive, max
/// exclusive) or, when none, the active voxels' bounding box. Empty voxels
/// hold 0. Throws yv::Error naming the file and the grid it lacks.
pybind11::dict readDenseVolume(const std::string& path, int level, const std::optional<std::array<int, 6>>& box);

/// The same grids as the density's leaves, in the file's order: each leaf's
/// minimum voxel index, its 8^3 values indexed [x][y][z] and which are active.
pybind11::dict readSparseVolume(const std::string& path, int level);

/// The file's metadata (what the run recorded: input, yarn_radius, twist,
/// lod_levels, ...) as a dict of str, int, float and bool.
pybind11::dict readVolumeMetadata(const std::string& path);

} // namespace yv::python
