// The slices of `yarnvox inspect --render slices` (the paper's own view of
// the garment, its section 3.5): one record a slice in the voxel grid's
// coordinates, as the renderer draws them, and their back-to-front order
// for alpha blending sorted on every core of the host: the reference for
// the order the renderer sorts on the GPU (src/render/slice_renderer.h).
#pragma once

#include "garment/slices.h"
#include "plan/grid.h"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <vector>

namespace yv {

/// Two vec4 a slice, in voxel units (voxel (i, j, k) fills [i, i+1) x ...):
/// (centre, thickness along the yarn) and (unit tangent, place in its run).
/// A run is the consecutive slices of one segment, in order along the yarn;
/// its places count from 0 (as floats, exact: a run restarts every
/// kRunPlaces slices), so a slice finds its neighbours of the same yarn by
/// index (the renderer's level of detail draws every k-th of a run).
struct SliceInstances {
    std::vector<glm::vec4> records; ///< 2 per slice
    float radius = 0.0f;            ///< the yarn's, voxel units (every slice's)
    /// The yarn twist the slices were placed with, radians per voxel of
    /// yarn length (their shading tilts each fibre by it, Eq. 1).
    float twist = 0.0f;
    std::uint64_t count() const { return records.size() / 2; }
    glm::vec3 center(std::uint64_t i) const { return glm::vec3(records[2 * i]); }
    std::uint32_t place(std::uint64_t i) const { return std::uint32_t(records[2 * i + 1].w); }
};

/// Places in a run before it restarts from 0 (all exact as floats).
constexpr std::uint32_t kRunPlaces = 1u << 20;

/// Places every slice of `plan` (in parallel over its segments) in `grid`'s voxel coordinates.
SliceInstances sliceInstances(const SlicePlan& plan, const VoxelGrid& grid);

/// Keeps the slices whose centre lies in [lo, hi) (voxel coordinates), in
/// their order; a run the box cuts becomes runs of the slices kept.
void keepSlicesWithin(SliceInstances& slices, glm::dvec3 lo, glm::dvec3 hi);

/// Fills `order` with the slice indices sorted by distance from `eye`,
/// farthest first (ties by index), sorting on every core (TBB).
void sortBackToFront(const SliceInstances& slices, glm::dvec3 eye, std::vector<std::uint32_t>& order);

} // namespace yv
