// `yarnvox inspect WORKDIR`: the zoom regions of a work directory (what
// each holds, on disk and in voxels) and, with verification, every region
// read back through its checksums.
#pragma once

#include "core/voxel_statistics.h"
#include "store/brick_store.h"

#include <cstdint>
#include <string>
#include <vector>

namespace yv {

struct RegionRow {
    RegionInfo info;
    std::uint64_t valueBytes = 0; ///< what its active voxels hold uncompressed (16 bytes each)
    std::string problem;          ///< empty when the region is sound (or was not verified)
};

struct StoreSummary {
    std::string dir;
    StoreManifest manifest;
    std::vector<RegionRow> regions; ///< by id
    std::uint64_t bricks = 0, activeVoxels = 0, bytesOnDisk = 0, valueBytes = 0;
    bool verified = false;
    std::uint64_t badRegions = 0;
    VoxelStatistics voxels; ///< over every region read (verify only)
};

/// Lists `dir`'s regions from their headers; with `verify`, reads every
/// region in full (checksums, decompression, identity against the manifest),
/// records what is wrong with each bad one instead of stopping, and gathers
/// the voxel statistics. Throws yv::Error when `dir` is not a work directory.
StoreSummary inspectStore(const std::string& dir, bool verify);

} // namespace yv
