#include "vdb/vdb_file_check.h"

#include "vdb/grid_checksums.h"
#include "vdb/vdb_index.h"

namespace yv {

VdbFileCheck checkVdbFile(const std::string& path) {
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
