// A yarnvox .vdb's file metadata (formats/vdb-subset.md): the run's
// description, field by field as core/run_metadata.h lists them, and what
// the writer itself knows of the file.
#pragma once

#include "core/bricks.h"
#include "core/run_metadata.h"
#include "core/sampling.h"
#include "core/voxel_grid.h"

#include <openvdb/openvdb.h>

namespace yv {

/// File metadata: level 0's voxel statistics (core/voxel_statistics.h,
/// statisticsRecord), so a summary of a large file reads no voxel.
inline constexpr const char* kVoxelStatisticsName = "yarnvox_statistics";

/// The items of the file's metadata: yarnvox_version; every field of
/// metadataFields(metadata) but albedo, as string, int32, int64 or double
/// items; voxel_size, reduce and grid_dims of `grid`; lod_levels with
/// `lodLevels` > 0, and lod_first_level too when `lodFirstLevel` is not 1
/// (the preview pyramid: files with every level keep the items they had);
/// and "albedo" (what the albedo grids hold) with `albedo`. OpenVDB writes
/// them sorted by name, whatever the order they are added in.
openvdb::MetaMap vdbFileMetadata(const VolumeMetadata& metadata, const VoxelGrid& grid, Reduce reduce, int lodLevels,
                                 int lodFirstLevel, bool albedo);

/// The run's description a .vdb's file metadata holds (what vdbFileMetadata
/// wrote), read through runMetadataFromJson: fields the file lacks (older or
/// foreign files) keep VolumeMetadata's defaults, albedo is whether the
/// "albedo" item is there, and the writer's own items are skipped. Throws
/// yv::Error naming `where` and the item when a field is of another type.
VolumeMetadata vdbRunMetadata(const openvdb::MetaMap& meta, const std::string& where);

} // namespace yv
