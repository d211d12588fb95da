// What a run will need. Before any slicing: a lower bound on its active
// voxels and output bytes, from the yarns' length and radius. Once the slices
// are placed on the grid: what it is expected to write. A run whose bound, or
// whose expected output, exceeds the free disk is refused before it
// voxelizes, with the numbers, instead of failing after minutes.
//
// For tests only, YARNVOX_TEST_FREE_BYTES=N stands for the free bytes of
// every file system these checks look at (as ulimit -f stands for a full
// disk in the tests of writes that fail): never set it in a real run.
#pragma once

#include "garment/cross_section.h"
#include "garment/garment.h"
#include "garment/slices.h"
#include "plan/grid.h"

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

/// How the .vdb will store each active voxel, for the bytes it takes.
struct VdbShape {
    bool halfPrecision = false; ///< --precision half
    bool albedo = false;        ///< an albedo grid beside density and orientation
    int lodLevels = 0;          ///< --lod: the coarsest level (0: none)
    int lodFirstLevel = 1;      ///< the finest coarse level: 1, or 3 for the preview pyramid
};

/// A run as the disk estimate sees it, once its slices and grid are known.
struct OutputPlan {
    double yarnLength = 0.0; ///< every yarn's arc length: its slices' thicknesses summed
    double radius = 0.0;     ///< yarn radius, world units
    double voxelSize = 0.0;  ///< world units
    const CrossSection* xs = nullptr; ///< where the slices hold fibre (outlives the plan)
    VdbShape shape;
};
OutputPlan outputPlan(const SlicePlan& plan, const VoxelGrid& grid, const CrossSection& xs, const VdbShape& shape);

/// The area (world units^2) a slice's fibre covers once grown by a voxel
/// face of side `h`: where a voxel column of side h meets fibre. Its texels
/// with fibre, dilated by h (for the disk, pi r^2 + 4 r h + h^2); a fibre
/// texture's gaps narrower than a voxel fill, wider ones stay empty.
double grownFibreArea(const CrossSection& xs, double radius, double h);

/// What a run is expected to write: the yarns' length times the voxels a
/// yarn crosses per unit length on the grid (grownFibreArea / h^3). An
/// estimate, not a bound: it counts the voxels where yarns overlap twice, so
/// it errs high where yarns touch or interpenetrate (docs/reliability.md
/// gives how far on real and generated garments).
struct ExpectedOutput {
    double activeVoxels = 0.0;
    double vdbBytes = 0.0;    ///< the .vdb, its levels of detail included
    double regionBytes = 0.0; ///< a work dir's region files (lz4-compressed full-precision bricks)
};
ExpectedOutput expectOutput(const OutputPlan& run);

/// Empty when the expected output fits the free disk with a margin (5 % of
/// what it needs, and 1 MB): on the output's file system the .vdb and its
/// scratch file (which holds the leaves until they are put in tree order),
/// and the region files where the work dir shares it. Else one line: the
/// bytes expected and free, where, and what to change (--precision half,
/// and the finest --resolution or --voxel-size that fits). `scaleOption` is
/// how the grid was asked for ("--resolution 16384", "--voxel-size 0.01").
std::string checkExpectedDisk(const OutputPlan& run, const RunPlace& place, const std::string& scaleOption);
} // namespace yv
