// `yarnvox inspect PATH --mesh FILE`: the isosurface written as a mesh, and
// the line (or JSON object) that says what was written.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace yv {

struct MeshRequest {
    std::string input;                   ///< a work directory or a .vdb
    std::string mesh;                    ///< the .ply or .obj to write
    double iso = 0.5;                    ///< the density the surface lies at
    std::optional<int> level;            ///< --mesh-level; none: full resolution, refused when too large
    std::optional<std::uint64_t> region; ///< only this zoom region's box
    bool json = false;
};

/// Extracts and writes the mesh `request` asks for and returns what inspect
/// prints about it. Throws yv::Error (a bad mesh path, an output that would
/// overwrite the input, an empty volume, a full-resolution mesh above
/// kMeshTriangleLimit, saying which --mesh-level fits).
std::string meshToFile(const MeshRequest& request);

} // namespace yv
