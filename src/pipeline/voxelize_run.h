// One voxelization, garment file to .vdb: read and check the garment, place
// the slices, plan the zoom regions, rasterize them with either backend (both
// are region rasterizers feeding the same writer), and write the .vdb,
// straight from memory or through a work directory that --resume can pick up.
// The CLI only parses options into a VoxelizeRequest and prints the report.
#pragma once

#include "core/bricks.h"
#include "core/stats.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <functional>
#include <string>

namespace yv {

/// What `yarnvox voxelize` is asked (option names in the comments).
struct VoxelizeRequest {
    std::string input, output;      ///< INPUT, -o
    std::string backend = "auto";   ///< --backend: auto, gl or cpu
    std::string method = "sparse";  ///< --method: sparse or dense
    std::string crossSection = "fibers", reduce = "mean", overlap = "clamp";
    std::string compression = "mask", precision = "float"; ///< --vdb-compression, --precision
    std::string statsPath, workDir; ///< --stats, --work-dir
    int resolution = 0, slicesPerSegment = 0, supersample = 1, device = -1;
    double voxelSize = 0.0, yarnRadius = 0.0, spacing = 0.0, twist = 0.0;
    std::uint64_t fragmentCapacity = 0; ///< --fragment-budget
    int lod = 0;                        ///< --lod: level-of-detail grids in the .vdb
    bool quiet = false, verbose = false, resume = false, keepWorkDir = false;
    bool albedo = false; ///< --albedo: the cross-section PNG's colour as an "albedo" grid
    /// Under mpirun: this rank voxelizes the garment by itself, as one
    /// process would (whole garments handed out to ranks), on its own GPU.
    bool alone = false;
};

/// What a run did: for the summary line (the --stats file has all of it).
struct VoxelizeReport {
    std::string backend;   ///< the backend "auto" resolved to
    std::uint64_t slices = 0, activeVoxels = 0, bricks = 0;
    glm::ivec3 dims{0};
    double voxelSize = 0.0, voxelizeSeconds = 0.0;
    Reduce reduce = Reduce::Mean;
    Overlap overlap = Overlap::Clamp;
    ResolveTally tally;
    bool tallyComplete = true; ///< false when regions came from a resumed run
    bool rankOnly = false;     ///< a rank other than 0 of an MPI run: rank 0 wrote and reports
    JsonObject stats;          ///< what --stats writes
};

/// Runs `request`, writing its .vdb (and --stats file). Warnings and notes
/// for the user go to `note`, one line each, as they arise. Throws yv::Error;
/// nothing that looks finished is left behind then.
VoxelizeReport runVoxelize(const VoxelizeRequest& request, const std::function<void(const std::string&)>& note);

} // namespace yv
