// Buffer layouts shared by C++ and shaders/layout.glsl (std430), GL-free.
#pragma once

#include "core/default_init_allocator.h"
#include "garment/slices.h"
#include "plan/grid.h"

#include <cstdint>
#include <vector>

namespace yv {

/// Vertices of one slice's triangle strip (shaders/slice.vert): a square, or
/// one triangle and a repeated corner.
constexpr int kSliceVertices = 4;

/// shaders/layout.glsl: GpuSegment.
struct GpuSegment {
    /// Control points, voxel units from the segment's anchor (an integer voxel
    /// near P[i], in p[1..3].w), so that floats keep their precision however
    /// large the grid; p[0].w = twist rate (radians per voxel unit).
    float p[4][4];
    float up[4];        ///< knot frame up; w = twist phase at the segment's start (radians, in [0, 2 pi))
    std::uint32_t info[4]; ///< first slice, slice count, float bits of the length (voxel units), yarn
};
static_assert(sizeof(GpuSegment) == 96, "GpuSegment must match shaders/layout.glsl");

/// Point sprites draw runs of consecutive slices (shaders/slice_runs.comp)
/// where the yarn's support is under kSliceRunSupportPixels pixels in radius:
/// at most kSliceRunMax slices a run, whose centres lie within
/// kSliceRunSpread pixels of each other on each axis of the face. Chosen on
/// an H100 (bench/results/slice-runs-2026-11-25-h100): runs of 2 took 7 to
/// 9 % off the raster of the 41 M-slice garments at 2048 (a yarn about one
/// pixel in radius), runs of 3 or 4 gave less or cost more, and wider yarns
/// (2 pixels and more) drew slower in runs.
constexpr int kSliceRunMax = 2;
/// The most slices a run may be set to hold: each takes two of the
/// fragment shader's input slots, of which GL promises 16.
constexpr int kSliceRunLimit = 4;
constexpr float kSliceRunSpread = 2.0f;
constexpr double kSliceRunSupportPixels = 1.5;

/// shaders/slice_runs.comp: one run, drawn as one point sprite.
struct GpuSliceRun {
    std::uint32_t first; ///< the run's first slice (its record)
    std::uint32_t count; ///< its slices, 1 to the run length
};
static_assert(sizeof(GpuSliceRun) == 8, "GpuSliceRun must match shaders/slice_runs.comp");

/// shaders/layout.glsl: SliceRecord, one placed slice (shaders/slice_setup.comp
/// writes them; the host only sizes their buffer).
struct GpuSliceRecord {
    float center[4];    ///< voxel units from the anchor; w: projection axis (int bits)
    std::int32_t anchor[4];
    float right[4];     ///< w: thickness
    float up[4];        ///< w: twist step
    float tangent[4];   ///< w: slab depth along the projection axis
    float curvature[4];
};
static_assert(sizeof(GpuSliceRecord) == 96, "GpuSliceRecord must match shaders/layout.glsl");

/// shaders/append.frag and sample.comp: one sample item, a slice's instance
/// and a pixel of the region's face (x | y << 16).
struct GpuSampleItem {
    std::uint32_t instance;
    std::uint32_t pixel;
};
static_assert(sizeof(GpuSampleItem) == 8, "GpuSampleItem must match shaders/append.frag");

/// shaders/layout.glsl: Fragment.
struct GpuFragment {
    std::uint32_t key;     ///< region brick index << 9 | voxel offset in the brick
    std::uint32_t weight;  ///< fixed-point volume fraction
    std::uint32_t axis;    ///< octahedral axis code
    std::uint32_t density; ///< float bits of the cross-section density
};
static_assert(sizeof(GpuFragment) == 16, "GpuFragment must match shaders/layout.glsl");

/// shaders/append.frag and brick_scatter.comp: AlbedoFragments (--albedo
/// only), at the same slot as its fragment.
struct GpuAlbedoFragment {
    std::uint32_t weighted[3]; ///< fixed-point volume fraction times linear R, G, B
    std::uint32_t unused;
};
static_assert(sizeof(GpuAlbedoFragment) == 16, "GpuAlbedoFragment must match shaders/append.frag");

/// The plan's segments as the vertex shader reads them: control points and
/// lengths in voxel units from the grid origin, so floats keep their precision.
/// Segments as GpuSegment records, packed on every core (a 410k-crossing
/// garment has 0.8 M of them); the records are left uninitialized until packed.
using GpuSegments = std::vector<GpuSegment, DefaultInitAllocator<GpuSegment>>;
GpuSegments packSegments(const SlicePlan& plan, const VoxelGrid& grid);
/// The same into `out` (plan.segments.size() records), e.g. a mapped buffer.
void packSegments(const SlicePlan& plan, const VoxelGrid& grid, GpuSegment* out);

} // namespace yv
