// `yarnvox inspect WORKDIR`: the report of a work directory, as text or
// JSON: the run, the totals, the time per stage and the region table, and
// with --verify the verdict and the voxel statistics.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace yv {

/// The columns the region table can be ordered by (--sort).
enum class RegionColumn { Id, Bricks, Active, Bytes, Ratio, Volume };

/// The column's name as --sort takes it ("id", "bricks", ...).
const char* regionColumnName(RegionColumn column);

/// Every column, in the order of their names.
const std::vector<RegionColumn>& regionColumns();

struct StoreReportRequest {
    std::string dir;
    bool json = false;
    bool verify = false;                    ///< read every region in full and check its checksums
    RegionColumn sort = RegionColumn::Id;   ///< largest first for every column but the id
    std::size_t limit = 20;                 ///< rows of the text table (0: all; JSON has all)
};

struct StoreReport {
    std::string text;    ///< what inspect prints
    std::string failure; ///< with --verify: the error naming the damaged regions, empty when every region is sound
};

/// Reads the work directory `request.dir` (and, with verify, every region
/// in it). Throws yv::Error when it is not a work directory.
StoreReport storeReport(const StoreReportRequest& request);

} // namespace yv
