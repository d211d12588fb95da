#include "gpu/gl_voxelizer.h"

#include "core/error.h"
#include "core/sampling.h"
#include "core/trace.h"
#include "gpu/brick_pass.h"
#include "gpu/brick_readback.h"
#include "gpu/gl_budget.h"
#include "gpu/gl_buffer.h"
#include "gpu/gpu_layout.h"
#include "gpu/raster_pass.h"
#include "gpu/sample_lists.h"
#include "gpu/sample_pass.h"
#include "gpu/work_item.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <iterator>
#include <optional>
#include <utility>

namespace yv {
namespace {

constexpr double kListsPerEstimate = 8.0; // list slots per fragment the zoom plan expects (sizeListsFor)

/// A region being rasterized, or done and waiting for its last packed bricks.
struct RegionInFlight {
    ZoomRegion region;
    PackedBricks packed; ///< its resolved bricks so far
};

/// What became of a work item's passes.
enum class PassResult {
    Done,     ///< its bricks are built and on their way to the host
    Overflow, ///< it did not fit (a list, its bricks or its slices): split it
    Redo,     ///< the item list was short: grown, the passes run again
};

/// The uploaded slices: the plan's segments (GpuSegment), packed on every core
/// straight into a mapped staging buffer, then copied into the GPU's memory
/// by the GPU: handing a packed copy to glNamedBufferSubData took 0.09 s for
/// the draped garment's 78 MB on the H100. (When the raster's vertex shader
/// read the segments, it ran 3 % slower from a buffer filled this way; only
/// the slices' placement pass reads them now.)
void uploadSegments(const SlicePlan& plan, const VoxelGrid& grid, GlBuffer& segments, std::uint64_t* gpuBytes) {
    const std::uint64_t bytes = plan.segments.size() * sizeof(GpuSegment);
    segments.reserve(bytes, gpuBytes);
    if (bytes == 0) return;
    GlBuffer staging;
    staging.reserveMappable(bytes);
    void* mapped = glMapNamedBufferRange(staging.id(), 0, static_cast<GLsizeiptr>(bytes),
                                         GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT);
    if (!mapped) throw Error("cannot map a GPU staging buffer of " + std::to_string(bytes >> 20) + " MiB for the slices");
    packSegments(plan, grid, static_cast<GpuSegment*>(mapped));
    glUnmapNamedBuffer(staging.id());
    glCopyNamedBufferSubData(staging.id(), segments.id(), 0, 0, static_cast<GLsizeiptr>(bytes));
    checkGlError("uploading the slices");
}

} // namespace

class GlBackend::Impl {
  public:
    Impl(const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid, const GlVoxelizeSettings& settings,
         std::unique_ptr<GlContext> owned, const GlContext& context)
        : owned_(std::move(owned)), context_(context), plan_(plan), xs_(xs), grid_(grid), settings_(settings),
          reduce_(settings.base.reduce), albedo_(xs.hasAlbedo()) {
        checkSupersample(settings.base.supersample);
        if (albedo_ && reduce_ != Reduce::Mean)
            throw Error("--albedo needs --reduce mean (a colour is averaged like the density, not maxed)");
        context_.makeCurrent();
        const GlInfo& info = context_.info();
        hostResolve_ = settings.brickResolve == BrickResolve::Host ||
                       (settings.brickResolve == BrickResolve::Auto && !info.hardware());
        counters_.renderer = info.renderer;
        counters_.platform = platformName(info.platform);
        counters_.contextSeconds = settings.contextSeconds;
        const double support = textureSupport(xs);
        const VoxelBox keep = settings.base.clip.value_or(VoxelBox{glm::ivec3(0), grid.dims});
        uniforms_ = SamplingUniforms{float(plan.options.radius / grid.voxelSize), settings.base.supersample,
                                     float(support), keep.min, keep.max};
        const TraceSpan span("choose the budgets");
        drawing_ = chooseSliceDrawing(settings, plan, grid, support, info);
        counters_.slicePrimitive = drawing_.name();
        budget_ = chooseBudget(settings, plan, grid, context_, drawing_, wordsPerVoxel(reduce_, albedo_), albedo_);
    }

    ~Impl() {
        // Where releaseThread() let another thread destroy the backend. A
        // context that cannot be made current is past saving; the process
        // goes on without freeing it here.
        try {
            context_.makeCurrent();
        } catch (const Error&) {
        }
    }

    void prepare();
    void run(const std::vector<ZoomRegion>& regions, RegionSink& sink);
    void releaseThread() const { context_.releaseCurrent(); }
    std::uint64_t fragmentBudget() const { return budget_.capacity; }
    int maxRegionSize() const { return budget_.regionCap; }
    const GlVoxelizeCounters& counters() const { return counters_; }

  private:
    void sizeListsFor(const std::vector<ZoomRegion>& regions);
    bool rasterAndSample(const WorkItem& item);
    PassResult buildBricks(const WorkItem& item, RegionInFlight& region);
    void handOver(std::unique_ptr<RegionInFlight>& previous, RegionSink& sink);
    void split(const WorkItem& item, std::vector<WorkItem>& stack) const;
    void noteTotals();
    void notePeak() { counters_.peakGpuBytes = std::max(counters_.peakGpuBytes, gpuBytes_); }

    std::unique_ptr<GlContext> owned_; ///< the context, where the backend owns it (destroyed last)
    const GlContext& context_;
    const SlicePlan& plan_;
    const CrossSection& xs_;
    const VoxelGrid& grid_;
    const GlVoxelizeSettings settings_;
    GlVoxelizeCounters counters_;
    Reduce reduce_;
    bool albedo_; ///< --albedo: the ALBEDO program variants, a colour list and three more words a voxel
    bool hostResolve_ = false; ///< BrickResolve::Host (settled from Auto by the platform)
    bool prepared_ = false;    ///< prepare() done
    SamplingUniforms uniforms_;
    SliceDrawing drawing_;
    GlBudget budget_;
    std::uint64_t gpuBytes_ = 0;          ///< the sum of yarnvox's GPU buffers now
    std::uint64_t instances_ = 0;         ///< slices the work item's raster drew
    GlBuffer segments_;                   ///< the plan's segments (GpuSegment)
    ReadbackBuffer small_;                ///< every read of a few bytes: counts, the touched bricks' slots
    std::unique_ptr<SampleLists> lists_;  ///< sample items and fragments
    std::unique_ptr<RasterPass> raster_;  ///< slices placed and drawn: sample items
    std::unique_ptr<SamplePass> sample_;  ///< items sampled: fragments
    std::unique_ptr<BrickPass> bricks_;   ///< fragments into bricks
    std::unique_ptr<BrickReadback> readback_; ///< bricks to the host, resolved or raw
};

/// The work before the first region that the zoom plan does not need: the
/// slices' upload, the cross-section, the programs and the lists.
void GlBackend::Impl::prepare() {
    if (prepared_) return;
    prepared_ = true;
    {
        const TraceSpan span("upload the slices");
        uploadSegments(plan_, grid_, segments_, &gpuBytes_);
        counters_.sliceDataBytes = segments_.size();
    }
    const TexelReads reads = texelReadsFor(settings_.texelReads);
    SampleTextures textures = uploadSampleTextures(xs_, reads, albedo_, &gpuBytes_);
    const auto compileStart = std::chrono::steady_clock::now();
    const bool timerQueries = context_.info().hardware();
    raster_ = std::make_unique<RasterPass>(plan_, segments_, drawing_, budget_, crossSectionDefines(xs_, reads),
                                           timerQueries, &gpuBytes_);
    sample_ = std::make_unique<SamplePass>(xs_, reads, std::move(textures), albedo_, budget_.maxGroups, timerQueries);
    bricks_ = std::make_unique<BrickPass>(reduce_, albedo_, budget_.maxGroups, timerQueries, &gpuBytes_);
    readback_ = std::make_unique<BrickReadback>(reduce_, settings_.base.overlap, albedo_, small_, &gpuBytes_);
    counters_.programSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - compileStart).count();
    traceSpanSince("compile the programs", compileStart);
    // The lists start small; run() sizes them from the zoom plan, and a
    // pass that finds them short grows them, up to the budget.
    lists_ = std::make_unique<SampleLists>(budget_.capacity, settings_.initialListSlots, albedo_,
                                           settings_.firstCounterStart, settings_.firstItemCounterStart, &gpuBytes_);
    notePeak();
}

/// The lists at what the largest region is expected to need: a list that
/// grows during the run redoes the pass (or the sampling) that found it
/// short. The zoom plan estimates the pixels that hold fibre; the items are
/// every pixel the footprints' reach covers, the fragments every voxel layer
/// a sample crosses: 4 to 7 times the estimate, measured.
void GlBackend::Impl::sizeListsFor(const std::vector<ZoomRegion>& regions) {
    if (settings_.initialListSlots) return;
    double most = 0.0;
    for (const ZoomRegion& r : regions) most = std::max(most, r.estimatedFragments);
    lists_->reserveAtLeast(static_cast<std::uint64_t>(kListsPerEstimate * most));
    notePeak();
}

/// The regions in order, each in work items that fit (an item that does not
/// is split and its pieces done in its place). Region N goes to the sink
/// once its last packed bricks are in: while region N + 1's first raster
/// runs on the GPU, or at the end.
void GlBackend::Impl::run(const std::vector<ZoomRegion>& regions, RegionSink& sink) {
    prepare();
    sizeListsFor(regions);
    counters_.plannedRegions = regions.size();
    std::unique_ptr<RegionInFlight> previous; // done, its last packed bricks maybe still on their way
    forEachRegionToDo(regions, sink, settings_.base.quiet, counters_.resumedRegions, [&](const ZoomRegion& region) {
        auto current = std::make_unique<RegionInFlight>(
            RegionInFlight{region, hostResolve_ ? PackedBricks{} : sink.emptyPackedBricks()});
        // Pieces of one region are finished before the next region starts,
        // so the sink gets each region whole, once.
        std::vector<WorkItem> stack{WorkItem{region.min, region.max, region.segments}};
        while (!stack.empty()) {
            const WorkItem item = std::move(stack.back());
            stack.pop_back();
            PassResult result = PassResult::Redo;
            while (result == PassResult::Redo) {
                const TraceSpan span("raster pass");
                if (!rasterAndSample(item)) { // queued on the GPU
                    result = PassResult::Overflow;
                    break;
                }
                handOver(previous, sink); // meanwhile, on the host
                result = buildBricks(item, *current);
            }
            if (result == PassResult::Overflow) {
                ++counters_.overflows;
                split(item, stack);
            }
        }
        ++counters_.regions;
        if (hostResolve_) {
            // The raw accumulators go to the sink, which resolves them on its threads.
            sink.consumeAccumulators(region, readback_->takeAccumulators());
            return;
        }
        // The region before, if no pass of this one handed it over; and the
        // packed bricks on their way ahead of this region's summed ones.
        if (previous || readback_->hasAccumulators()) handOver(previous, sink);
        readback_->resolveAccumulators(current->packed);
        previous = std::move(current);
    });
    handOver(previous, sink);
    noteTotals();
}

/// Queues the raster of `item` and the sampling of its items on the GPU;
/// false when its slices exceed one draw.
bool GlBackend::Impl::rasterAndSample(const WorkItem& item) {
    const std::optional<std::uint64_t> instances = raster_->run(item, uniforms_, *lists_);
    if (!instances) return false;
    instances_ = *instances;
    sample_->run(item, uniforms_, *lists_, raster_->slices());
    glFlush();
    return true;
}

/// Takes in the packed bricks still on their way (into the region they
/// belong to), then hands `previous`, which waited for them, to the sink.
void GlBackend::Impl::handOver(std::unique_ptr<RegionInFlight>& previous, RegionSink& sink) {
    const TraceSpan span("take in the pass before");
    readback_->takeInPassBefore();
    if (!previous) return;
    const TraceSpan handing("hand the region to the writer");
    sink.consume(previous->region, std::move(previous->packed));
    previous.reset();
}

/// Once the raster and the sampling of `item` are done: their counts (a list
/// found short is grown: the passes, or the sampling alone, again), the
/// bricks, and their way to the host started (into `region`'s packed bricks,
/// or its accumulators).
PassResult GlBackend::Impl::buildBricks(const WorkItem& item, RegionInFlight& region) {
    PassCounts counts = lists_->read(small_, raster_->runDraw());
    const std::uint64_t capacity = lists_->capacity();
    if (counts.wrapped || counts.fragments > capacity || counts.items > capacity) return PassResult::Overflow;
    if (counts.items > lists_->itemSlots()) {
        // Within the budget but beyond the item list as allocated: grow it
        // (the counter told us how much is needed) and redo the pass.
        lists_->growItems(counts.items);
        ++counters_.listGrowths;
        return PassResult::Redo;
    }
    if (counts.fragments > lists_->fragmentSlots()) {
        // Likewise for the fragment list; the items are whole, so only the
        // sampling is redone.
        lists_->growFragments(counts.fragments);
        ++counters_.listGrowths;
        lists_->resetFragmentCounter();
        sample_->run(item, uniforms_, *lists_, raster_->slices());
        counts = lists_->read(small_, raster_->runDraw());
        YV_CHECK(!counts.wrapped && counts.fragments <= lists_->fragmentSlots()); // the same items give the same fragments
    }
    counters_.sampleItems += counts.items;
    counters_.slicesDrawn += instances_;
    counters_.primitivesDrawn += drawing_.compute ? 0 : (drawing_.runSlices > 1 ? counts.runs : instances_);
    if (counts.fragments == 0) return PassResult::Done;

    const std::optional<GLuint> active = bricks_->build(item, counts.fragments, *lists_, small_, budget_.brickBudget);
    if (!active) return PassResult::Overflow;
    // Per pass the host waits for the fragment count, the touched bricks'
    // count and (in the resolver) the resolved totals, each a few bytes;
    // the packed bricks' copy is taken in during the next pass's raster.
    if (item.partial || hostResolve_)
        counters_.hostSummedBricks += readback_->readRaw(item, *bricks_, *active);
    else
        readback_->startPacked(item, *bricks_, *active, counts.fragments, region.packed);
    notePeak();
    counters_.fragments += counts.fragments;
    ++counters_.passes;
    return PassResult::Done;
}

/// Splits an item that did not fit: in two along its longest axis at a brick
/// boundary, or, one brick already, its segments in halves.
void GlBackend::Impl::split(const WorkItem& item, std::vector<WorkItem>& stack) const {
    const glm::ivec3 size = item.max - item.min;
    const int axis = size.x >= size.y && size.x >= size.z ? 0 : (size.y >= size.z ? 1 : 2);
    if (size[axis] > 8) {
        const int mid = item.min[axis] + (size[axis] / 16) * 8;
        WorkItem lo{item.min, item.max, {}}, hi{item.min, item.max, {}};
        lo.max[axis] = mid;
        hi.min[axis] = mid;
        lo.segments = segmentsReaching(plan_, grid_, item.segments, lo.min, lo.max);
        hi.segments = segmentsReaching(plan_, grid_, item.segments, hi.min, hi.max);
        if (!hi.segments.empty()) stack.push_back(std::move(hi));
        if (!lo.segments.empty()) stack.push_back(std::move(lo));
        return;
    }
    // One brick that still overflows: halve its segments instead; the two
    // halves' bricks add up on the host.
    YV_CHECK(item.segments.size() > 1);
    const std::size_t half = item.segments.size() / 2;
    WorkItem a{item.min, item.max, {item.segments.begin(), item.segments.begin() + half}, true};
    WorkItem b{item.min, item.max, {item.segments.begin() + half, item.segments.end()}, true};
    stack.push_back(std::move(b));
    stack.push_back(std::move(a));
}

/// The passes' times and the readbacks' totals, into the counters.
void GlBackend::Impl::noteTotals() {
    counters_.placeSeconds = raster_->placeSeconds();
    counters_.rasterSeconds = counters_.placeSeconds + raster_->drawSeconds();
    counters_.sampleSeconds = sample_->seconds();
    counters_.brickSeconds = bricks_->seconds();
    counters_.resolveSeconds = readback_->resolveSeconds();
    counters_.readbackSeconds = readback_->readbackSeconds();
    counters_.readbackBytes = small_.bytesRead() + readback_->bytesRead();
    counters_.fragmentCapacity = budget_.capacity;
}

void compileInvariantPrograms() {
    const TraceSpan span("compile the programs without variants");
    std::vector<GlProgram> programs;
    for (const char* name : {"buffer_clear.comp", "brick_flag.comp", "brick_scan.comp", "brick_resolve_scan.comp",
                             "sample_dispatch.comp", "slice_setup.comp"})
        programs.push_back(GlProgram::compute(name));
    for (const GlProgram& p : programs) p.waitLinked();
}

GlBackend::GlBackend(const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid,
                     const GlVoxelizeSettings& settings, std::unique_ptr<GlContext> context) {
    YV_CHECK(context);
    const GlContext& current = *context;
    impl_ = std::make_unique<Impl>(plan, xs, grid, settings, std::move(context), current);
}
GlBackend::GlBackend(const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid,
                     const GlVoxelizeSettings& settings, const GlContext& context)
    : impl_(std::make_unique<Impl>(plan, xs, grid, settings, nullptr, context)) {}
GlBackend::~GlBackend() = default;
std::uint64_t GlBackend::fragmentBudget() const { return impl_->fragmentBudget(); }
int GlBackend::maxRegionSize() const { return impl_->maxRegionSize(); }
void GlBackend::prepare() { impl_->prepare(); }
void GlBackend::run(const std::vector<ZoomRegion>& regions, RegionSink& sink) { impl_->run(regions, sink); }
void GlBackend::releaseThread() { impl_->releaseThread(); }
const GlVoxelizeCounters& GlBackend::counters() const { return impl_->counters(); }

JsonObject GlBackend::stats() const {
    const GlVoxelizeCounters& c = counters();
    JsonObject out;
    out.set("renderer", c.renderer)
        .set("platform", c.platform)
        .set("slice_primitive", c.slicePrimitive)
        .set("fragments", c.fragments)
        .set("raster_passes", c.passes)
        .set("overflow_retries", c.overflows)
        .set("fragment_list_growths", c.listGrowths)
        .set("bricks_summed_on_host", c.hostSummedBricks)
        .set("zoom_regions", c.plannedRegions)
        .set("regions_computed", c.regions)
        .set("regions_resumed", c.resumedRegions)
        .set("fragment_budget", c.fragmentCapacity)
        .set("gpu_slice_data_bytes", c.sliceDataBytes)
        .set("gpu_peak_bytes", c.peakGpuBytes)
        .set("gl_context_seconds", c.contextSeconds)
        .set("gl_program_seconds", c.programSeconds)
        .set("gpu_raster_seconds", c.rasterSeconds)
        .set("gpu_place_seconds", c.placeSeconds)
        .set("sample_items", c.sampleItems)
        .set("slices_drawn", c.slicesDrawn)
        .set("primitives_drawn", c.primitivesDrawn)
        .set("gpu_sample_seconds", c.sampleSeconds)
        .set("gpu_brick_seconds", c.brickSeconds)
        .set("gpu_resolve_seconds", c.resolveSeconds)
        .set("readback_seconds", c.readbackSeconds)
        .set("readback_bytes", c.readbackBytes);
    return out;
}

std::string GlBackend::describe() const {
    const GlVoxelizeCounters& c = counters();
    return "renderer: " + c.renderer + " (" + c.platform + "); " + std::to_string(c.overflows) + " overflow retries, " +
           std::to_string(c.resumedRegions) + " regions resumed";
}

StageSeconds GlBackend::voxelizeParts() const {
    const GlVoxelizeCounters& c = counters();
    return {{"voxelize.gpu_raster", c.rasterSeconds},
            {"voxelize.gpu_sample", c.sampleSeconds},
            {"voxelize.gpu_bricks", c.brickSeconds},
            {"voxelize.gpu_resolve", c.resolveSeconds},
            {"voxelize.readback", c.readbackSeconds}};
}

namespace {

/// Keeps every region's bricks in memory (no work directory).
class CollectingSink : public RegionSink {
  public:
    void consume(const ZoomRegion&, PackedBricks&& bricks) override { regions.push_back(std::move(bricks)); }
    void consumeAccumulators(const ZoomRegion&, std::vector<BrickAccumulator>&& bricks) override {
        std::move(bricks.begin(), bricks.end(), std::back_inserter(accumulators));
    }
    std::vector<PackedBricks> regions;
    std::vector<BrickAccumulator> accumulators; ///< with the host resolve
};

} // namespace

BrickVolume voxelizeGl(const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid,
                       const GlVoxelizeSettings& settings, const GlContext& context, GlVoxelizeCounters* counters) {
    GlBackend backend(plan, xs, grid, settings, context);
    const ZoomPlan zoom = planZoomRegions(plan, grid, xs, {backend.fragmentBudget(), backend.maxRegionSize(),
                                                           settings.base.supersample}, settings.base.clip);
    CollectingSink sink;
    backend.run(zoom.regions, sink);
    if (counters) *counters = backend.counters();
    if (!sink.accumulators.empty())
        return resolveVolume(grid, settings.base.reduce, settings.base.overlap, sink.accumulators);
    return unpackVolume(grid, settings.base.reduce, sink.regions);
}

} // namespace yv
