// Zoom regions: the grid split octree-wise into boxes that each fit one GPU
// pass, from a coarse heat map of the fragments each part of the garment
// will produce at the target resolution.
#pragma once

#include "core/voxel_box.h"
#include "core/zoom_region.h"
#include "garment/cross_section.h"
#include "garment/slices.h"
#include "plan/grid.h"

#include <glm/vector_relational.hpp>
#include <glm/vec3.hpp>

#include <atomic>
#include <cstdint>
#include <optional>
#include <vector>

namespace yv {

/// The regions a run is cut into by default (ZoomPlanOptions::pipelineRegions):
/// the draped garment at 2048 in 3 regions took 0.3 s to voxelize, in 28
/// regions 0.17 s (H100), the last region's encode no longer after the GPU's end.
constexpr double kPipelineRegions = 32.0;

struct ZoomPlanOptions {
    std::uint64_t fragmentBudget = 0; ///< fragments one pass may produce
    int maxRegionSize = 1024;         ///< voxels per axis (viewport and key limits)
    int supersample = 1;
    /// Where set, the planning stops soon after it is set (a run given up):
    /// the plan it returns is then `givenUp`, with no regions.
    const std::atomic<bool>* stop = nullptr;
    /// Regions a garment expected to be large is cut into, at least (each
    /// region's estimate within this fraction of the garment's), so that
    /// the writer encodes one region while the GPU draws the next
    /// (kPipelineRegions; YV_PIPELINE_REGIONS sets it for a run).
    double pipelineRegions = kPipelineRegions;
};

struct ZoomPlan {
    std::vector<ZoomRegion> regions;
    int heatCell = 32;                 ///< voxels per heat-map cell along each axis
    double estimatedFragments = 0.0;   ///< whole garment
    std::uint64_t heatCellsTouched = 0;
    bool givenUp = false;              ///< ZoomPlanOptions::stop was set: no regions planned
};

/// Voxels of the grid that slices of `segment` can reach: slice centres grown
/// by the segment's reach (slice half-diagonal plus half a slab's depth), the
/// footprints' reach (kSampleReachVoxels) and one voxel. Used to bin segments into regions.
void segmentVoxelBounds(const SlicePlan& plan, const VoxelGrid& grid, std::uint32_t segment, glm::dvec3& lo,
                        glm::dvec3& hi);

/// segmentVoxelBounds in whole voxels: floor of the low corner, ceiling of
/// the high one. A box of whole voxels [min, max) is reached exactly when
/// segmentVoxelBounds' box overlaps it (lo < max and hi > min).
struct SegmentVoxelBox {
    glm::ivec3 lo, hi;
    bool reaches(glm::ivec3 min, glm::ivec3 max) const {
        return glm::all(glm::lessThan(lo, max)) && glm::all(glm::greaterThan(hi, min));
    }
};
SegmentVoxelBox segmentVoxelBox(const SlicePlan& plan, const VoxelGrid& grid, std::uint32_t segment);

/// Segments of `from` whose slices can reach voxels [min, max).
std::vector<std::uint32_t> segmentsReaching(const SlicePlan& plan, const VoxelGrid& grid,
                                            const std::vector<std::uint32_t>& from, glm::ivec3 min, glm::ivec3 max);

/// Builds the heat map (expected fragments per 32^3 cell: each slice adds
/// its projected area in pixels times the cross-section's filled fraction to
/// the cell of its centre) and splits the grid octree-wise, on 128-voxel
/// (OpenVDB internal node) boundaries where the box is large, until each
/// region's estimate is within half the budget (and, past a million
/// fragments, within a 32nd of the garment's) and its size within
/// maxRegionSize. A thin axis (at most 128 voxels and a quarter of the
/// box's longest) is not halved, so a flat garment's regions keep its whole
/// thickness. Regions no segment reaches are left out.
/// With `box` (--bbox: plan only the voxels of this box of the grid), the
/// same over the box rounded out to whole bricks, with a heat map of the
/// segments that reach the box only, and a region's segments are those that
/// reach its voxels inside the box: the voxels on the box's faces get every
/// slice that reaches them, and no other.
ZoomPlan planZoomRegions(const SlicePlan& plan, const VoxelGrid& grid, const CrossSection& xs,
                         const ZoomPlanOptions& options, const std::optional<VoxelBox>& box = std::nullopt);

} // namespace yv
