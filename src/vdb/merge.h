// The last step of the out-of-core pipeline: a brick store's regions become
// one OpenVDB file, the same file writeVdb would write for the same bricks.
#pragma once

#include "core/bricks.h"
#include "store/brick_store.h"
#include "vdb/vdb_writer.h"

#include <string>
#include <vector>

namespace yv {

/// Writes every region of a finished store (BrickStore::markComplete) to
/// `outPath` as writeVdb does: same grids, transform, metadata and atomic
/// write, with the store's regions as the density grid's recorded regions. Regions are read, verified and turned into leaves in parallel, a few
/// at a time, so only the leaves and a few regions' bricks are in memory.
/// Throws yv::Error when the run is unfinished, a region is damaged or
/// missing, or two regions hold the same brick.
void mergeStoreToVdb(const BrickStore& store, const std::string& outPath, const VolumeMetadata& metadata,
                     const VdbWriteOptions& options = {});

/// Same, opening the work dir `dir` read-only (`yarnvox merge WORKDIR`).
void mergeStoreToVdb(const std::string& dir, const std::string& outPath, const VolumeMetadata& metadata,
                     const VdbWriteOptions& options = {});

/// The regions a .vdb records (VolumeMetadata::regions) from a store's or a
/// region writer's list, in its order (by id).
std::vector<RecordedRegion> recordedRegions(const std::vector<RegionInfo>& regions);

/// Every brick of the store in `dir`, sorted by key, from whatever regions are
/// on disk (finished run or not): for tests and tools. Throws yv::Error on a
/// damaged region or a brick held by two regions.
BrickVolume loadStore(const std::string& dir);

} // namespace yv
