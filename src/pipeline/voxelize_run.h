// One voxelization, garment file to .vdb, as named stages (voxelize_run.cpp
// reads as the list): the garment read and sliced (sliced_garment.h) while
// the GL context is made; the backend chosen once (backend_choice.h); the
// grid; the rasterizer made and the zoom regions planned (rasterizers.h);
// the regions rasterized into a destination (region_destination.h: in
// memory, a work dir, or one shared by MPI ranks), which writes the .vdb;
// the statistics (run_stats.h). The CLI parses options into a VoxelizeJob
// and prints the report.
#pragma once

#include "core/bricks.h"
#include "core/stats.h"
#include "pipeline/voxelize_job.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <string>

namespace yv {

/// What a run did: for the summary line (the --stats file has all of it).
struct VoxelizeReport {
    std::string backend; ///< the backend "auto" resolved to
    std::uint64_t slices = 0, activeVoxels = 0, bricks = 0;
    glm::ivec3 dims{0};
    glm::dvec3 origin{0.0}; ///< the grid's corner in world units (VoxelGrid::origin)
    double voxelSize = 0.0, voxelizeSeconds = 0.0;
    Reduce reduce = Reduce::Mean;
    Overlap overlap = Overlap::Clamp;
    ResolveTally tally;
    bool tallyComplete = true; ///< false when regions came from a resumed run
    bool rankOnly = false;     ///< a rank other than 0 of an MPI run: rank 0 wrote and reports
    JsonObject stats;          ///< what --stats writes
};

/// Runs `job`, writing its .vdb (and --stats file). Warnings and notes for
/// the user go to `note`, one line each, as they arise. Throws yv::Error;
/// nothing that looks finished is left behind then.
VoxelizeReport runVoxelize(const VoxelizeJob& job, const Tell& note);

} // namespace yv
