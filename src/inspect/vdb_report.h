// `yarnvox inspect FILE.vdb`: the report of a .vdb, as text or JSON.
#pragma once

#include <string>

namespace yv {

/// What inspect prints for the .vdb at `path`: its grids, metadata, voxel
/// statistics, time per stage and recorded zoom regions (text, or one JSON
/// object with `json`). Throws yv::Error as inspectVdb does.
std::string vdbReport(const std::string& path, bool json);

} // namespace yv
