// What a run will need, known before any slicing: a lower bound on its
// active voxels, output bytes and (for the CPU backend, which holds the
// volume) host memory, from the yarns' length and radius. A run whose bound
// already exceeds the disk or the memory is refused at the start, with the
// numbers, instead of failing after minutes.
#pragma once

#include "garment/garment.h"

#include <cstdint>
#include <string>

namespace yv {

struct ResourceNeeds {
    double activeVoxels = 0.0; ///< at least: the yarns' cross-section area over the voxel area, along their length
    double outputBytes = 0.0;  ///< at least: the .vdb, and as much again for its scratch file
};

/// Lower bounds for `garment` at voxel size `h` (world units), yarn radius `radius`.
/// The curve length is bounded below by the polyline through the points the curve passes through.
ResourceNeeds estimateNeeds(const Garment& garment, double radius, double h, bool halfPrecision);

struct RunPlace {
    std::string outputDir;     ///< where the .vdb and its scratch file go
    std::string workDir;       ///< where region files go ("" without a store)
};

/// Empty when the run fits what this machine has (free disk of the output's
/// and the work dir's file systems, physical memory); else one line saying
/// what the run needs at least, what there is, and what to change.
std::string checkNeeds(const ResourceNeeds& needs, const RunPlace& place, const std::string& scaleOption);

} // namespace yv
