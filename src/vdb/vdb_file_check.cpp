#include "vdb/vdb_file_check.h"

#include "core/error.h"
#include "vdb/grid_checksums.h"
#include "vdb/vdb_index.h"

#include <filesystem>

namespace yv {

VdbFileCheck checkVdbFile(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw Error(path + ": no such file");
    const VdbIndex index(path);
    VdbFileCheck check;
    for (const StoredMetadata& m : index.fileMetadata()) check.yarnvox = check.yarnvox || m.name == "yarnvox_version";
    if (!check.yarnvox) return check;
    // The topology first: a damaged count is named as such, not as a changed checksum.
    if (index.inSubset())
        for (const VdbGridInfo& grid : index.grids()) index.leaves(grid);
    check.gridsChecked = verifyGridChecksums(index);
    return check;
}

} // namespace yv
