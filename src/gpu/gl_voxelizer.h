// The GL backend: slices placed by a compute pass and rasterised, a sample
// item appended per pixel that can hold fibre, the items sampled by a compute
// pass into voxel fragments appended to an SSBO through an atomic counter,
// bricks built and resolved by compute passes; only finished bricks come back
// to the host, packed.
#pragma once

#include "core/bricks.h"
#include "core/packed_bricks.h"
#include "core/voxelize_settings.h"
#include "gpu/cross_section_texture.h"
#include "gpu/egl_context.h"
#include "garment/cross_section.h"
#include "garment/slices.h"
#include "plan/grid.h"
#include "core/region_rasterizer.h"
#include "plan/zoom_plan.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace yv {

/// Where the GL backend resolves its bricks. Gpu: compute passes, and only
/// finished bricks come back (packed). Host: the raw accumulators come back
/// and the sink's writer threads resolve them, as the CPU backend's are.
/// Auto: Host on llvmpipe (EGL's surfaceless platform), where the resolve's
/// double-precision compute shader took three times the host's time on the
/// same cores; Gpu on a GPU. On llvmpipe both give the same bricks, bit for
/// bit (the tests); on NVIDIA's driver the same densities, and axes that
/// differ in their last bits (1,253 bytes of a 28 MB half .vdb:
/// bench/results/2026-12-06-h100-first-run-tradeoffs-af5fc46/).
enum class BrickResolve { Auto, Gpu, Host };

/// What each slice is drawn as. Each covers every pixel whose sample can hold
/// fibre, and the sampling decides from the pixel alone, so all give the
/// same voxels, bit for bit. Compute: no draw; a compute pass tests the
/// pixels of each slice's box on the face and appends its sample items
/// (shaders/slice_items.comp), on every unit of the GPU where the raster
/// runs on few of them. Point: one sprite, an axis-aligned square
/// on the face around the slice's projection (no inner edge, so no 2x2 quad
/// is shaded twice; 11 to 18 % off the raster on the H100 for the sweater and
/// the draped garment), or around a run of consecutive slices' projections
/// where the yarn is thin on the face (GlVoxelizeSettings::sliceRun).
/// Triangle: one triangle around the fibre's disk, or the slice's square (17
/// to 20 % faster than sprites on llvmpipe). Raster: Point on a GPU,
/// Triangle on llvmpipe, and Triangle where the driver's largest point size
/// cannot hold the largest sprite. Auto: Compute (the raster's step 3 times
/// faster on llvmpipe, the same items).
enum class SlicePrimitive { Auto, Raster, Triangle, Point, Compute };

struct GlVoxelizeSettings {
    VoxelizeSettings base;
    /// Seconds the caller took to make the GL context it gives the backend
    /// (reported as gl_context_seconds).
    double contextSeconds = 0.0;
    /// Fragment-list capacity in fragments (0: from queried limits and free
    /// GPU memory). Tests force it small to exercise overflow and retry.
    std::uint64_t fragmentCapacity = 0;
    /// Slots the fragment and item lists start with (0: 2^20); they grow to
    /// what a pass needs, up to the capacity. Tests start them small.
    std::uint64_t initialListSlots = 0;
    bool verbose = false;
    /// How the sampling shader reads the cross-section's texels: as suits the
    /// platform (Auto), or forced (tests compare the two).
    TexelReads texelReads = TexelReads::Auto;
    BrickResolve brickResolve = BrickResolve::Auto;
    SlicePrimitive slicePrimitive = SlicePrimitive::Auto;
    /// Slices one point sprite draws at most, 1 to kSliceRunLimit (0: as
    /// suits the yarn's width in pixels, gpu_layout.h:
    /// kSliceRunSupportPixels); tests compare runs with single slices.
    int sliceRun = 0;
    /// Where the first pass's 32-bit fragment counter, and its sample item
    /// counter, start (tests set them near 2^32 to make them wrap; runs leave
    /// them at 0).
    std::uint32_t firstCounterStart = 0;
    std::uint32_t firstItemCounterStart = 0;
};

struct GlVoxelizeCounters {
    std::string renderer, platform;
    std::string slicePrimitive; ///< "compute", "point" or "triangle", as drawn
    std::uint64_t fragments = 0;        ///< fragments appended, summed over passes that fit
    std::uint64_t sampleItems = 0;      ///< sample items (slice and pixel) the raster appended, likewise
    std::uint64_t slicesDrawn = 0;      ///< slices drawn (a slice near a region's edge is drawn in each region it reaches), likewise
    std::uint64_t primitivesDrawn = 0;  ///< points (each a run of slices) or triangles drawn, likewise
    std::uint64_t passes = 0;           ///< raster passes that fit
    std::uint64_t overflows = 0;        ///< passes redone in smaller pieces
    std::uint64_t listGrowths = 0;      ///< passes redone after growing the fragment list within the budget
    std::uint64_t hostSummedBricks = 0; ///< a brick's passes after its first (segments halved), added up on the host
    std::uint64_t plannedRegions = 0;   ///< zoom regions in the plan
    std::uint64_t regions = 0;          ///< zoom regions computed
    std::uint64_t resumedRegions = 0;   ///< zoom regions taken from a resumed work directory
    std::uint64_t fragmentCapacity = 0; ///< capacity used
    std::uint64_t sliceDataBytes = 0;   ///< GPU bytes of curve/segment data for the slices
    std::uint64_t peakGpuBytes = 0;     ///< largest sum of yarnvox's GPU buffers
    double contextSeconds = 0.0;        ///< creating the GL context (EGL display, device, context), by the caller
    double programSeconds = 0.0;        ///< compiling and linking the backend's shader programs
    double rasterSeconds = 0.0;         ///< time of the raster passes: slices placed, drawn, items appended (GPU drained at both ends)
    double placeSeconds = 0.0;          ///< the part of rasterSeconds that places the slices (slice_setup.comp)
    double sampleSeconds = 0.0;         ///< time of the sampling passes: items sampled, fragments appended (likewise)
    double brickSeconds = 0.0;          ///< time of the brick passes (likewise)
    double resolveSeconds = 0.0;        ///< time of the resolve passes, until their totals are on the host
    double readbackSeconds = 0.0;       ///< wall time of reading back bricks (packed, and raw ones split by segments)
    std::uint64_t readbackBytes = 0;    ///< bytes copied from the GPU to the host (counts and bricks)
};

/// Compiles the backend's programs that take no variant's #defines, on the
/// current context, and waits for them. NVIDIA's driver starts its compiler
/// at a process's first compile (0.35 s on the H200 with no shader cache)
/// and compiles one program after another whatever the threads
/// (bench/compile_threads.cpp): a run calls this while another thread reads
/// and slices the garment, and the backend's own compiles of these programs
/// are then the driver's cache hits.
void compileInvariantPrograms();

/// The GL backend on a live context: budgets from the queried limits, then
/// zoom regions one after another, each through the passes of
/// raster_pass.h, sample_pass.h, brick_pass.h and brick_readback.h. A region
/// whose fragments overflow the list (or whose bricks overflow their buffer)
/// is split and redone; nothing is dropped and nothing is counted twice.
class GlBackend : public RegionRasterizer {
  public:
    /// Runs on `context` (made current on this thread), which it owns: the
    /// pipeline frees both together, on another thread (releaseThread).
    GlBackend(const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid, const GlVoxelizeSettings& settings,
              std::unique_ptr<GlContext> context);
    /// Runs on `context` (made current on this thread), which must outlive the backend.
    GlBackend(const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid, const GlVoxelizeSettings& settings,
              const GlContext& context);
    ~GlBackend() override;
    /// Fragments one pass may append (the zoom planner's budget).
    std::uint64_t fragmentBudget() const override;
    /// Largest region edge in voxels (viewport and key limits).
    int maxRegionSize() const override;
    /// Uploads the slices and the cross-section and compiles the programs.
    void prepare() override;
    void run(const std::vector<ZoomRegion>& regions, RegionSink& sink) override;
    /// Releases the GL context from this thread; the destructor, on any
    /// thread, makes it current there.
    void releaseThread() override;
    /// What the backend counted so far (totals once run() returns).
    const GlVoxelizeCounters& counters() const;
    /// GlVoxelizeCounters under --stats' names, in the order they have always had.
    JsonObject stats() const override;
    std::uint64_t samples() const override { return counters().fragments; }
    /// The raster, sample, brick, resolve and readback times.
    StageSeconds voxelizeParts() const override;
    /// "renderer: NAME (PLATFORM); N overflow retries, M regions resumed".
    std::string describe() const override;

  private:
    class Impl;
    std::unique_ptr<Impl> impl_;
};

/// Voxelizes on the GPU, on `context`, with the same sampling rule and
/// reductions as voxelizeCpu; `counters`, where given, gets the backend's.
BrickVolume voxelizeGl(const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid,
                       const GlVoxelizeSettings& settings, const GlContext& context,
                       GlVoxelizeCounters* counters = nullptr);

} // namespace yv
