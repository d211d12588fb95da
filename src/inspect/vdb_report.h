// `yarnvox inspect FILE.vdb`: the report of a .vdb, as text or JSON.
#pragma once

#include <string>

namespace yv {

/// What inspect prints for the .vdb at `path`: its grids, metadata, voxel
/// statistics, time per stage and recorded zoom regions (text, or one JSON
/// object with `json`); the statistics recorded in the file, or counted from
/// every voxel with `countEveryVoxel` (and checked against the record).
/// Throws yv::Error as inspectVdb does.
std::string vdbReport(const std::string& path, bool json, bool countEveryVoxel = false);

} // namespace yv
