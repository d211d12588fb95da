// `yarnvox inspect FILE.vdb`: what is in an OpenVDB file with a float
// `density` grid (yarnvox's own or anyone's), read through OpenVDB.
#pragma once

#include "core/stage_seconds.h"
#include "core/voxel_statistics.h"
#include "core/run_metadata.h"

#include <glm/vec3.hpp>
#include <openvdb/Grid.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace yv {

struct GridSummary {
    std::string name, type;
    std::uint64_t activeVoxels = 0, leaves = 0;
    glm::ivec3 boundsMin{0}, boundsMax{0}; ///< active voxels, inclusive; empty grid: min > max
    bool halfFloat = false;
    std::string compression; ///< as the file records it, when it does
};

struct VdbSummary {
    std::string path;
    std::uint64_t fileBytes = 0;
    std::string libraryVersion; ///< the OpenVDB version that wrote the file
    double voxelSize = 0.0;
    std::vector<std::pair<std::string, std::string>> fileMetadata; ///< name, value as text
    std::vector<GridSummary> grids;
    VoxelStatistics voxels; ///< density, with orientation where an `orientation` grid is there
    /// Where `voxels` came from: the writer's record in the file (a yarnvox
    /// .vdb; nothing but the header is read), or a count of every voxel.
    bool statisticsRecorded = false;
    /// Counted, and equal to the file's record (which a count always checks when there is one).
    bool statisticsChecked = false;
    bool hasOrientation = false;
    StageSeconds stageSeconds; ///< from a "stage_seconds" string metadata item (NAME=SECONDS words); empty where the file has none
    std::vector<RecordedRegion> regions; ///< the density grid's "yarnvox_regions"; empty where it has none
};

/// Why a .vdb without "stage_seconds" metadata has no time per stage, as inspect says it.
constexpr const char* kVdbStagesNotRecorded =
    "the file has no stage_seconds metadata; yarnvox writes none, so that its .vdb files are the same bytes run "
    "after run: see the work directory or the --stats file";

/// Why a .vdb without recorded regions cannot frame or outline them, as inspect says it.
std::string vdbHasNoRegions(const std::string& path);

/// The zoom regions recorded in the density grid's metadata of `path` (read
/// from the grid's header only), empty when it records none; throws
/// yv::Error naming `path` when it is not an OpenVDB file with a density grid
/// or the record is malformed.
std::vector<RecordedRegion> readVdbRegions(const std::string& path);
/// The same from a density grid already read.
std::vector<RecordedRegion> recordedRegionsOf(const openvdb::GridBase& density, const std::string& path);

/// How inspectVdb finds the voxel statistics: from the record a yarnvox
/// .vdb holds (file metadata "yarnvox_statistics") where there is one, or
/// by counting every voxel (--verify), checked against the record.
enum class VoxelCount { RecordedWhereThere, EveryVoxel };

/// Reads `path`; throws yv::Error naming it when it is not an OpenVDB file
/// or has no float grid named `density`, or its "stage_seconds" or
/// "yarnvox_statistics" is malformed, or a count of every voxel differs from
/// the recorded statistics.
VdbSummary inspectVdb(const std::string& path, VoxelCount count = VoxelCount::RecordedWhereThere);

} // namespace yv
