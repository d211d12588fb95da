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

/// The items of the file's metadata: yarnvox_version; every field of
/// metadataFields(metadata) but albedo, as string, int32, int64 or double
/// items; voxel_size, reduce and grid_dims of `grid`; lod_levels with
/// `lodLevels` > 0; and "albedo" (what the albedo grids hold) with `albedo`.
/// OpenVDB writes them sorted by name, whatever the order they are added in.
openvdb::MetaMap vdbFileMetadata(const VolumeMetadata& metadata, const VoxelGrid& grid, Reduce reduce, int lodLevels,
                                 bool albedo);

} // namespace yv
