// The grids an export starts from: a .vdb as yarnvox writes it (or anyone's
// with a float `density` grid), read back through OpenVDB. Exports convert
// the leaves already written; nothing is voxelized again.
#pragma once

#include <openvdb/openvdb.h>

#include <string>

namespace yv {

struct FiberGrids {
    openvdb::FloatGrid::Ptr density;       ///< never null
    openvdb::Vec3SGrid::Ptr orientation;   ///< null when the file has none
    openvdb::Vec3SGrid::Ptr albedo;        ///< linear RGB (--albedo); null when the file has none
};

/// Reads `density` (a float grid, required), `orientation` and `albedo`
/// (vec3s grids, optional) from `path`. Throws yv::Error naming the file when
/// it is not an OpenVDB file, has no float `density` grid, or an
/// `orientation` or `albedo` grid of another type.
FiberGrids readFiberGrids(const std::string& path);

} // namespace yv
