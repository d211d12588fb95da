// A .vdb checked whole before it is read for its values by a reader that
// trusts it (OpenVDB, for export): a cut or damaged yarnvox file is refused in
// one line naming the file and where, instead of read into a wrong volume,
// a huge allocation or a crash.
#pragma once

#include <cstddef>
#include <string>

namespace yv {

struct VdbFileCheck {
    bool yarnvox = false;        ///< written by yarnvox (file metadata yarnvox_version)
    std::size_t gridsChecked = 0; ///< grids whose checksum matched (0: the file records none)
};

/// For a yarnvox file: its header and grid descriptors (vdb/vdb_index.h),
/// each grid's topology where the file is in the reader's subset, and every
/// grid's checksum where the file records them (vdb/grid_checksums.h). A
/// file of another writer is only opened (it must be an OpenVDB file) and
/// left to its reader. Throws yv::Error naming the file and where.
VdbFileCheck checkVdbFile(const std::string& path);

} // namespace yv
