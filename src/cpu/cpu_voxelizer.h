// The reference voxelizer: TBB-parallel over slices, sparse 8^3 bricks,
// fixed-point accumulation so results are identical for any thread count.
#pragma once

#include "core/bricks.h"
#include "core/voxelize_settings.h"
#include "garment/cross_section.h"
#include "garment/slices.h"
#include "plan/grid.h"

#include <cstdint>
#include <span>
#include <vector>

namespace yv {

struct CpuVoxelizeCounters {
    std::uint64_t samples = 0; ///< samples that landed on fibre
    std::uint64_t tasks = 0;   ///< slice-range tasks TBB ran (a test checks that the work was split)
    std::uint64_t threads = 0; ///< threads that ran at least one of them
    std::uint64_t slicesSampled = 0; ///< slices whose samples could reach their box (the others are skipped)
    /// Fewest threads that ran a box's tasks, over the boxes with at least 8
    /// slices sampled a thread (UINT64_MAX: none had as many).
    std::uint64_t busyBoxThreadsMin = ~std::uint64_t(0);

    CpuVoxelizeCounters& operator+=(const CpuVoxelizeCounters& o);
};

/// Accumulates the slices of `segments` (indices into plan.segments) into the
/// voxels of the box [boxMin, boxMax) of `grid`; samples elsewhere in the grid
/// belong to other boxes and are left out. Throws yv::Error if a sample falls
/// outside the grid. Sorted by key, the same bits for any thread count.
/// Counters are added to.
std::vector<BrickAccumulator> accumulateBox(const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid,
                                            const VoxelizeSettings& settings, std::span<const std::uint32_t> segments,
                                            glm::ivec3 boxMin, glm::ivec3 boxMax, CpuVoxelizeCounters* counters = nullptr);

/// Voxelizes every slice of `plan` into `grid`. Throws yv::Error if a sample
/// falls outside the grid (a grid that does not contain the plan).
BrickVolume voxelizeCpu(const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid,
                        const VoxelizeSettings& settings, CpuVoxelizeCounters* counters = nullptr);

/// Adds one sample to a brick accumulator (the per-voxel rule of both
/// reductions); `albedo`, when given, to the mean's albedo words.
void accumulateSample(Reduce reduce, std::uint32_t* words, int voxelOffset, double volumeFraction, float density,
                      const glm::dvec3& direction, const glm::dvec3* albedo = nullptr);

} // namespace yv
