// NanoVDB output (.nvdb): the OpenVDB grids converted by NanoVDB's own
// converter (nanovdb::openToNanoVDB) and written with its own writer, one
// file holding `density` (float, a fog volume) and `orientation` (Vec3f),
// names kept. pbrt-v4's `nanovdb` medium and GPU path tracers read it.
#pragma once

#include "export/fiber_grids.h"

#include <cstdint>
#include <string>

namespace yv {

struct NanoVdbExportResult {
    std::uint64_t bytes = 0; ///< the file's size
    int grids = 0;           ///< grids written
};

/// Converts every grid of `grids` and writes them, uncompressed, to `path`
/// through a temporary name and a rename. Refuses before writing anything,
/// naming the size and the free space, when the file would not fit the file
/// system; any failed write throws yv::Error and leaves nothing behind.
NanoVdbExportResult exportNanoVdb(const FiberGrids& grids, const std::string& path);

} // namespace yv
