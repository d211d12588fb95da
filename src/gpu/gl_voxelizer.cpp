#include "gpu/gl_voxelizer.h"

#include "core/error.h"
#include "core/trace.h"
#include "gpu/brick_resolver.h"
#include "gpu/cross_section_texture.h"
#include "gpu/egl_context.h"
#include "gpu/gl_buffer.h"
#include "gpu/gl_program.h"
#include "gpu/gpu_layout.h"
#include "gpu/slice_placer.h"

#include <epoxy/gl.h>
#include <glm/common.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <unordered_map>
#include <utility>

namespace yv {
namespace {

constexpr GLuint kWorkGroup = 256;
constexpr GLuint kSampleGroup = 128; // sample.comp's local_size_x
constexpr std::uint64_t kInitialFragmentSlots = 1 << 20; // 16 MiB of fragments, 8 MiB of sample items
constexpr double kListsPerEstimate = 8.0; // list slots per fragment the zoom plan expects (sizeListsFor)

/// Time of the GL commands between begin() and end(), summed. On a GPU
/// (EGL's device platform) by timer queries, read at the end of the run, so
/// that timing never stalls the pipeline; on llvmpipe, whose timer queries
/// answer garbage, both ends wait for the GPU to drain (glFinish), so there
/// it is what the pass costs the pipeline.
class GpuTimer {
  public:
    explicit GpuTimer(bool useQueries) : useQueries_(useQueries) {}
    ~GpuTimer() {
        if (!queries_.empty()) glDeleteQueries(GLsizei(queries_.size()), queries_.data());
    }
    GpuTimer(const GpuTimer&) = delete;
    GpuTimer& operator=(const GpuTimer&) = delete;

    void begin() {
        if (useQueries_) {
            GLuint query = 0;
            glGenQueries(1, &query);
            queries_.push_back(query);
            glBeginQuery(GL_TIME_ELAPSED, query);
            return;
        }
        glFinish();
        start_ = std::chrono::steady_clock::now();
    }
    void end() {
        if (useQueries_) {
            glEndQuery(GL_TIME_ELAPSED);
            return;
        }
        glFinish();
        seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }
    /// Seconds so far (waits for the queries still running).
    double seconds() {
        for (GLuint query : queries_) {
            GLuint64 ns = 0;
            glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
            seconds_ += double(ns) * 1e-9;
        }
        if (!queries_.empty()) glDeleteQueries(GLsizei(queries_.size()), queries_.data());
        queries_.clear();
        return seconds_;
    }

  private:
    bool useQueries_;
    std::vector<GLuint> queries_;
    std::chrono::steady_clock::time_point start_;
    double seconds_ = 0.0;
};

/// A box of voxels (a whole number of bricks) and the segments that may touch it.
struct WorkItem {
    glm::ivec3 min, max;
    std::vector<std::uint32_t> segments;
    /// One brick drawn in several passes, each with part of its segments: its
    /// accumulators add up on the host before the brick is resolved.
    bool partial = false;
};

/// A context, and the seconds it took to create (into `seconds`).
std::unique_ptr<GlContext> timedContext(const GlContextOptions& options, double& seconds) {
    const auto start = std::chrono::steady_clock::now();
    auto context = std::make_unique<GlContext>(options);
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return context;
}

/// A context made elsewhere, current on this thread.
std::unique_ptr<GlContext> currentContext(std::unique_ptr<GlContext> context) {
    context->makeCurrent();
    return context;
}

GLuint groupsFor(std::uint64_t items, GLuint maxGroups) {
    const std::uint64_t groups = (items + kWorkGroup - 1) / kWorkGroup;
    return static_cast<GLuint>(std::clamp<std::uint64_t>(groups, 1, maxGroups));
}

} // namespace

class GlBackend::Impl {
  public:
    Impl(const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid,
                const GlVoxelizeSettings& settings, GlVoxelizeCounters& counters, std::unique_ptr<GlContext> context)
        : plan_(plan), xs_(xs), grid_(grid), settings_(settings), counters_(counters),
          context_(context ? currentContext(std::move(context))
                           : timedContext(GlContextOptions{settings.device, std::getenv("YV_GL_DEBUG") != nullptr,
                                                           settings.spreadIndex},
                                          counters.contextSeconds)),
          reduce_(settings.base.reduce), albedo_(xs.hasAlbedo()), words_(wordsPerVoxel(reduce_, albedo_)) {
        if (albedo_ && reduce_ != Reduce::Mean)
            throw Error("--albedo needs --reduce mean (a colour is averaged like the density, not maxed)");
        const GlInfo& info = context_->info();
        hostResolve_ = settings.brickResolve == BrickResolve::Host ||
                       (settings.brickResolve == BrickResolve::Auto && !info.hardware());
        counters_.renderer = info.renderer;
        counters_.platform = platformName(info.platform);
        support_ = textureSupport(xs);
        const TraceSpan span("choose the budgets");
        chooseSlicePrimitive(info);
        chooseBudgets(info);
    }

    /// The work before the first region that the zoom plan does not need:
    /// the slices' upload, the cross-section, the programs and the lists.
    void prepare() {
        if (prepared_) return;
        prepared_ = true;
        const GlVoxelizeSettings& settings = settings_;
        const CrossSection& xs = xs_;
        {
            const TraceSpan span("upload the slices");
            uploadSegments();
        }
        const TexelReads reads = texelReadsFor(settings.texelReads);
        uploadCrossSection(xs, reads);
        // --albedo compiles variants of their own (ALBEDO), so runs without it
        // keep the programs, fragments and brick words they always had.
        const auto compileStart = std::chrono::steady_clock::now();
        std::vector<std::string> sampleDefines = crossSectionDefines(xs, reads);
        if (albedo_) sampleDefines.push_back("ALBEDO 1");
        // The raster bounds a footprint by what the sampling reads of it (the
        // disk's whole footprint, or a texture's cell centres: slice.vert).
        std::vector<std::string> rasterDefines = crossSectionDefines(xs, reads);
        if (pointMargin_ > 0) {
            rasterDefines.push_back("SLICE_POINTS 1");
            rasterDefines.push_back("SLICE_RUN " + std::to_string(runSlices_));
        }
        placer_ = std::make_unique<SlicePlacer>(runSlices_, rasterDefines);
        raster_ = GlProgram::graphics("slice.vert", "append.frag", rasterDefines);
        sample_ = GlProgram::compute("sample.comp", sampleDefines);
        sampleDispatch_ = GlProgram::compute("sample_dispatch.comp");
        flag_ = GlProgram::compute("brick_flag.comp");
        clear_ = GlProgram::compute("buffer_clear.comp");
        scan_ = GlProgram::compute("brick_scan.comp");
        std::vector<std::string> defines;
        if (reduce_ == Reduce::Max) defines.push_back("REDUCE_MAX 1");
        if (albedo_) defines.push_back("ALBEDO 1");
        scatter_ = GlProgram::compute("brick_scatter.comp", defines);
        if (reduce_ == Reduce::Max) maxOrient_ = GlProgram::compute("brick_max_orient.comp");
        resolver_ = std::make_unique<GlBrickResolver>(reduce_, settings.base.overlap, &gpuBytes_, albedo_);
        counters_.programSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - compileStart).count();
        traceSpanSince("compile the programs", compileStart);
        glCreateVertexArrays(1, &vao_);
        glCreateFramebuffers(1, &fbo_);
        // The lists start small; run() sizes them from the zoom plan, and a
        // pass that finds them short grows them, up to the budget, so a small
        // garment does not hold the whole budget on the GPU.
        const std::uint64_t initialSlots = settings.initialListSlots ? settings.initialListSlots : kInitialFragmentSlots;
        fragmentSlots_ = std::min<std::uint64_t>(capacity_, initialSlots);
        itemSlots_ = std::min<std::uint64_t>(capacity_, initialSlots);
        reserveLists();
        counter_.reserve(8, &gpuBytes_); // the append counter, then the flag of a counter that wrapped
        runDraw_.reserve(16, &gpuBytes_); // with point sprites, the draw's command (its first word: the runs)
        runDraw_.clear(16);
        itemCounter_.reserve(32, &gpuBytes_); // likewise for the items, then the sampling pass's dispatch size
        counts_.reserve(16, &gpuBytes_);
        notePeak();
    }

    ~Impl() {
        // Where releaseThread() let another thread destroy the backend. A
        // context that cannot be made current is past saving; the process
        // goes on without freeing it here.
        try {
            context_->makeCurrent();
        } catch (const Error&) {
        }
        glDeleteTextures(1, &texture_);
        if (albedoTexture_) glDeleteTextures(1, &albedoTexture_);
        glDeleteVertexArrays(1, &vao_);
        glDeleteFramebuffers(1, &fbo_);
    }

    void run(const std::vector<ZoomRegion>& regions, RegionSink& sink) {
        prepare();
        sizeListsFor(regions);
        sink_ = &sink;
        forEachRegionToDo(regions, sink, settings_.base.quiet, counters_.resumedRegions, [&](const ZoomRegion& region) {
            // With the host resolve the region's bricks stay raw (partials_).
            if (!hostResolve_) current_ = std::make_unique<RegionInFlight>(RegionInFlight{region, sink.emptyPackedBricks()});
            // Pieces of one region are finished before the next region starts,
            // so the sink gets each region whole, once.
            std::vector<WorkItem> stack{WorkItem{region.min, region.max, region.segments}};
            while (!stack.empty()) {
                WorkItem item = std::move(stack.back());
                stack.pop_back();
                if (!process(item)) {
                    ++counters_.overflows;
                    split(item, stack);
                }
            }
            ++counters_.regions;
            if (hostResolve_) {
                // The raw accumulators go to the sink, which resolves them on its threads.
                std::sort(partials_.begin(), partials_.end(),
                          [](const BrickAccumulator& a, const BrickAccumulator& b) { return a.key < b.key; });
                sink.consumeAccumulators(region, std::move(partials_));
                partials_.clear();
                slotOfKey_.clear();
                return;
            }
            if (!partials_.empty()) {
                // After the region's packed bricks still on their way, so they keep their order.
                finishReadbacks();
                resolver_->resolve(partials_, current_->packed);
                partials_.clear();
                slotOfKey_.clear();
            }
            // The region's last packed bricks may still be on their way: it
            // goes to the sink once they are in, while the next region's
            // raster runs (process), or at the end.
            if (awaiting_) finishReadbacks(); // the region before, if no pass of this one handed it over
            awaiting_ = std::move(current_);
        });
        finishReadbacks();
        counters_.placeSeconds = placeTimer_.seconds();
        counters_.rasterSeconds = counters_.placeSeconds + rasterTimer_.seconds();
        counters_.sampleSeconds = sampleTimer_.seconds();
        counters_.brickSeconds = brickTimer_.seconds();
        noteResolver();
        counters_.fragmentCapacity = capacity_;
        sink_ = nullptr;
    }

    /// The lists at what the largest region is expected to need: a list that
    /// grows during the run redoes the pass (or the sampling) that found it
    /// short. The zoom plan estimates the pixels that hold fibre; the items
    /// are every pixel the footprints' reach covers, the fragments every
    /// voxel layer a sample crosses: 4 to 7 times the estimate, measured.
    void sizeListsFor(const std::vector<ZoomRegion>& regions) {
        if (settings_.initialListSlots) return;
        double most = 0.0;
        for (const ZoomRegion& r : regions) most = std::max(most, r.estimatedFragments);
        const std::uint64_t slots = std::min<std::uint64_t>(capacity_, static_cast<std::uint64_t>(kListsPerEstimate * most));
        fragmentSlots_ = std::max(fragmentSlots_, slots);
        itemSlots_ = std::max(itemSlots_, slots);
        reserveLists();
        notePeak();
    }

    void releaseThread() const { context_->releaseCurrent(); }

    std::uint64_t fragmentBudget() const { return capacity_; }
    int maxRegionSize() const { return regionCap_; }

  private:
    void chooseBudgets(const GlInfo& info) {
        // Every buffer is bound whole as one shader storage block, so none may
        // exceed GL_MAX_SHADER_STORAGE_BLOCK_SIZE; together they stay within
        // half of the free GPU memory where the driver reports it.
        const std::uint64_t block = static_cast<std::uint64_t>(std::max<long long>(info.maxSsboBlockSize, 1 << 20));
        const long long freeBytes = context_->queryFreeMemoryBytes();
        const std::uint64_t memory = freeBytes > 0 ? static_cast<std::uint64_t>(freeBytes) / 2 : (std::uint64_t(1) << 30);
        // A unit of the budget is a fragment (with albedo a second record as
        // large, GpuAlbedoFragment) and a sample item: the item list holds
        // as many items as the fragment list holds fragments.
        const std::uint64_t unitBytes = sizeof(GpuFragment) * (albedo_ ? 2 : 1) + sizeof(GpuSampleItem);
        capacity_ = settings_.fragmentCapacity ? settings_.fragmentCapacity : memory / 2 / unitBytes;
        capacity_ = std::min<std::uint64_t>(capacity_, block / sizeof(GpuFragment));
        maxBlock_ = block;
        // Slots at 2^31 and beyond flag the pass as overflowed (append.frag).
        capacity_ = std::min<std::uint64_t>(capacity_, 0x7fffffffu);
        // A brick slot holds its words, and the resolve's output for it in the worst case.
        const std::uint64_t wordBytes = std::uint64_t(words_) * kBrickVoxels * 4;
        const std::uint64_t resolveBytes = resolveBytesPerBrick(albedo_);
        brickBudget_ = std::min(block / std::max(wordBytes, resolveBytes), memory / 3 / (wordBytes + resolveBytes));
        if (settings_.fragmentCapacity) brickBudget_ = std::min<std::uint64_t>(brickBudget_, std::max<std::uint64_t>(capacity_ / 8, 1));

        GLint fbMax[2] = {0, 0}, viewportMax[2] = {0, 0};
        glGetIntegerv(GL_MAX_FRAMEBUFFER_WIDTH, &fbMax[0]);
        glGetIntegerv(GL_MAX_FRAMEBUFFER_HEIGHT, &fbMax[1]);
        glGetIntegerv(GL_MAX_VIEWPORT_DIMS, viewportMax);
        // Point sprites take a margin around the region's face (chooseSlicePrimitive).
        const int pixels = std::min({fbMax[0], fbMax[1], viewportMax[0], viewportMax[1]}) - 2 * pointMargin_;
        // Region keys hold a brick index in 23 bits: at most 2^23 bricks a region.
        regionCap_ = std::min(1024, (pixels / settings_.base.supersample) / 8 * 8);
        maxGroups_ = static_cast<GLuint>(std::min(info.maxComputeWorkGroupCountX, 65535));

        // The smallest piece of work is one segment over one brick.
        std::uint32_t maxSlices = 0, minSlices = ~0u;
        for (const SegmentRecord& s : plan_.segments) {
            maxSlices = std::max(maxSlices, s.sliceCount);
            minSlices = std::min(minSlices, s.sliceCount);
        }
        uniformSlices_ = minSlices == maxSlices ? maxSlices : 0;
        // Each sample's slab column is split over at most this many voxels
        // (and over at most 8 of one brick).
        const double slabDepth = 2.0 * std::max(0.0, plan_.maxReach - plan_.options.radius * std::sqrt(2.0)) / grid_.voxelSize;
        const std::uint64_t pieces = std::min<std::uint64_t>(8, 2 + static_cast<std::uint64_t>(slabDepth));
        const std::uint64_t worst =
            std::uint64_t(maxSlices) * 64 * settings_.base.supersample * settings_.base.supersample * pieces;
        if (capacity_ < worst)
            throw Error("fragment budget " + std::to_string(capacity_) + " is below the " + std::to_string(worst) +
                        " fragments one segment can put into one brick; raise --fragment-budget");
        if (settings_.verbose)
            std::fprintf(stderr, "gl: %s, %s; ssbo block %lld MiB, free %lld MiB; capacity %llu fragments, %llu bricks, regions <= %d\n",
                         info.renderer.c_str(), info.version.c_str(), info.maxSsboBlockSize >> 20,
                         freeBytes > 0 ? freeBytes >> 20 : -1LL, static_cast<unsigned long long>(capacity_),
                         static_cast<unsigned long long>(brickBudget_), regionCap_);
    }

    /// Point sprites where asked for (Auto: on a GPU) and where the driver's
    /// point sizes hold the largest sprite the vertex shader can ask for; a
    /// margin of pixels around the region's face keeps every sprite's centre
    /// in the viewport, since a point whose centre is clipped is dropped whole.
    void chooseSlicePrimitive(const GlInfo& info) {
        const SlicePrimitive asked = settings_.slicePrimitive;
        counters_.slicePrimitive = "triangle";
        if (asked == SlicePrimitive::Triangle || (asked == SlicePrimitive::Auto && !info.hardware())) return;
        const double S = settings_.base.supersample, r = plan_.options.radius / grid_.voxelSize;
        // Runs of slices, one sprite each, where the yarn is thin on the face:
        // there a point's fixed cost is most of its time, and two slices'
        // sprites cover nearly the same few pixels (slice_runs.comp).
        if (settings_.sliceRun < 0 || settings_.sliceRun > kSliceRunLimit)
            throw Error("a point sprite draws 1 to " + std::to_string(kSliceRunLimit) + " slices (asked for " +
                        std::to_string(settings_.sliceRun) + ")");
        if (settings_.sliceRun > 0)
            runSlices_ = settings_.sliceRun;
        else
            runSlices_ = support_ * r * S < kSliceRunSupportPixels ? kSliceRunMax : 1;
        GLfloat sizes[2] = {0, 0};
        glGetFloatv(GL_POINT_SIZE_RANGE, sizes);
        // A bound on slice.vert's reach: its footprint term (a share of the
        // footprint's longer diagonal) is at most half the edges' sum, at most
        // sqrt(3)/S since 1/|tangent[a]| <= sqrt(3); and the square's corners.
        // A run's sprite is at most half the spread of its slices' centres
        // wider than its widest slice's; where runs' sprites would not fit the
        // driver's point sizes, a slice's may.
        const double reach = (support_ * r + 1.75 / S) * 1.001 + 0.05 / S, extent = r + 2.0 / S;
        const auto halfPixelsWith = [&](int runSlices) {
            return std::max(reach, extent * std::sqrt(2.0)) * S + 0.05 + (runSlices > 1 ? 0.5 * kSliceRunSpread : 0.0);
        };
        if (runSlices_ > 1 && !(2.0 * halfPixelsWith(runSlices_) + 1.0 <= sizes[1])) runSlices_ = 1;
        const double halfPixels = halfPixelsWith(runSlices_);
        if (!(2.0 * halfPixels + 1.0 <= sizes[1])) return;
        pointMargin_ = static_cast<int>(std::ceil(halfPixels)) + 2; // chooseBudgets keeps regions within the rest
        counters_.slicePrimitive = "point";
    }

    void uploadSegments() {
        // Packed on every core straight into a mapped staging buffer, then
        // copied into the GPU's memory by the GPU: handing a packed copy to
        // glNamedBufferSubData took 0.09 s for the draped garment's 78 MB on
        // the H100. (When the raster's vertex shader read the segments, it
        // ran 3 % slower from a buffer filled this way; only the slices'
        // placement pass reads them now.)
        const std::uint64_t bytes = plan_.segments.size() * sizeof(GpuSegment);
        segments_.reserve(bytes, &gpuBytes_);
        counters_.sliceDataBytes = segments_.size();
        if (bytes == 0) return;
        GlBuffer staging;
        staging.reserveMappable(bytes);
        void* mapped = glMapNamedBufferRange(staging.id(), 0, static_cast<GLsizeiptr>(bytes),
                                             GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT);
        if (!mapped) throw Error("cannot map a GPU staging buffer of " + std::to_string(bytes >> 20) + " MiB for the slices");
        packSegments(plan_, grid_, static_cast<GpuSegment*>(mapped));
        glUnmapNamedBuffer(staging.id());
        glCopyNamedBufferSubData(staging.id(), segments_.id(), 0, 0, static_cast<GLsizeiptr>(bytes));
        checkGlError("uploading the slices");
    }

    void uploadCrossSection(const CrossSection& xs, TexelReads reads) {
        texture_ = uploadCrossSectionTexture(xs, reads);
        gpuBytes_ += reads == TexelReads::Quad ? std::uint64_t(xs.size + 1) * (xs.size + 1) * 4 : std::uint64_t(xs.size) * xs.size;
        if (albedo_) {
            albedoTexture_ = uploadAlbedoTexture(xs);
            gpuBytes_ += std::uint64_t(xs.size) * xs.size * 12;
        }
        checkGlError("uploading the cross-section");
    }

    void split(WorkItem& item, std::vector<WorkItem>& stack) const {
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

    /// Rasterises and bricks one work item; false when it did not fit.
    bool process(const WorkItem& item) {
        const TraceSpan span("raster pass");
        const glm::ivec3 size = item.max - item.min;
        const glm::ivec3 bricks = size / 8;
        const std::uint64_t regionBricks = std::uint64_t(bricks.x) * bricks.y * bricks.z;
        const int S = settings_.base.supersample;

        // Draw list: segment index and the first instance of each.
        std::vector<std::uint32_t> draw(item.segments.size() * 2);
        std::uint64_t instances = 0;
        for (std::size_t i = 0; i < item.segments.size(); ++i) {
            draw[2 * i] = item.segments[i];
            draw[2 * i + 1] = static_cast<std::uint32_t>(instances);
            instances += plan_.segments[item.segments[i]].sliceCount;
        }
        if (instances > 0x7fffffff || instances * sizeof(GpuSliceRecord) > maxBlock_) return false;
        drawList_.upload(draw.data(), draw.size() * 4, &gpuBytes_);
        counter_.clear(8);
        itemCounter_.clear(32);
        if (const std::uint32_t start = std::exchange(counterStart_, 0); start != 0)
            glNamedBufferSubData(counter_.id(), 0, 4, &start);
        if (const std::uint32_t start = std::exchange(itemCounterStart_, 0); start != 0)
            glNamedBufferSubData(itemCounter_.id(), 0, 4, &start);

        // The raster: the slices placed on every compute unit, then drawn, one
        // sample item appended per pixel that can hold fibre.
        placeTimer_.begin();
        {
            const TraceSpan placing("place the slices");
            placer_->place(SliceDraw{segments_.id(), drawList_.id(), static_cast<int>(item.segments.size()), uniformSlices_, instances},
                           slices_, &gpuBytes_);
            if (runSlices_ > 1)
                placer_->joinRuns(instances, S, kSliceRunSpread, slices_, runs_, runDraw_, &gpuBytes_);
        }
        placeTimer_.end();
        rasterTimer_.begin();
        {
            // Submitting the draw and the sampling (the driver may wait here on first use).
            const TraceSpan drawing("draw the slices");
            const int viewport = std::max({size.x, size.y, size.z}) * S + 2 * pointMargin_;
            glNamedFramebufferParameteri(fbo_, GL_FRAMEBUFFER_DEFAULT_WIDTH, viewport);
            glNamedFramebufferParameteri(fbo_, GL_FRAMEBUFFER_DEFAULT_HEIGHT, viewport);
            glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
            glViewport(0, 0, viewport, viewport);
            glDisable(GL_DEPTH_TEST);
            glDisable(GL_CULL_FACE);
            glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);

            raster_.use();
            setRegionUniforms(raster_, item.min, bricks);
            glUniform2f(raster_.uniform("uViewport"), float(viewport), float(viewport));
            glUniform1i(raster_.uniform("uMargin"), pointMargin_);
            glUniform1ui(raster_.uniform("uItemCapacity"), static_cast<GLuint>(itemSlots_));
            slices_.bindStorage(5);
            items_.bindStorage(6);
            itemCounter_.bindStorage(7); // the wrap flag
            glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, itemCounter_.id());
            glBindVertexArray(vao_);
            if (runSlices_ > 1) {
                // Vertex i is run i; their count is on the GPU (slice_runs.comp).
                glEnable(GL_PROGRAM_POINT_SIZE);
                runs_.bindStorage(4); // (the sampling binds its own buffers at 3 and 4)
                glBindBuffer(GL_DRAW_INDIRECT_BUFFER, runDraw_.id());
                glDrawArraysIndirect(GL_POINTS, nullptr);
                glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
            } else if (pointMargin_ > 0) {
                glEnable(GL_PROGRAM_POINT_SIZE);
                glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(instances)); // vertex i is slice i
            } else {
                glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, kSliceVertices, static_cast<GLsizei>(instances));
            }
            rasterTimer_.end();
            checkGlError("raster pass");
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_ATOMIC_COUNTER_BARRIER_BIT);

            runSampling(item, bricks);
            glFlush();
        }
        // While the GPU rasterizes, the host takes in the pass before's bricks.
        finishReadbacks();

        // Each counter, then its wrap flag: the 32-bit counter went past 2^31
        // (and may have wrapped to a small count), far beyond any list, so the
        // pass is redone in pieces.
        GLuint count[5] = {0, 0, 0, 0, 0};
        readCounts(count);
        GLuint fragmentCount = count[0];
        const GLuint itemCount = count[2];
        if (count[1] != 0 || count[3] != 0 || fragmentCount > capacity_ || itemCount > capacity_) return false;
        if (itemCount > itemSlots_) {
            // Within the budget but beyond the item list as allocated: grow it
            // (the counter told us how much is needed) and redo the pass.
            itemSlots_ = std::min<std::uint64_t>(capacity_, std::uint64_t(itemCount) + itemCount / 4);
            reserveLists();
            ++counters_.listGrowths;
            return process(item);
        }
        if (fragmentCount > fragmentSlots_) {
            // Likewise for the fragment list; the items are whole, so only
            // the sampling is redone.
            fragmentSlots_ = std::min<std::uint64_t>(capacity_, std::uint64_t(fragmentCount) + fragmentCount / 4);
            reserveLists();
            ++counters_.listGrowths;
            counter_.clear(8);
            runSampling(item, bricks);
            readCounts(count);
            fragmentCount = count[0];
            YV_CHECK(count[1] == 0 && fragmentCount <= fragmentSlots_); // the same items give the same fragments
        }
        counters_.sampleItems += itemCount;
        counters_.slicesDrawn += instances;
        counters_.primitivesDrawn += runSlices_ > 1 ? count[4] : instances;
        if (fragmentCount == 0) return true;

        // Brick passes: flag, scan, then scatter into the touched bricks only.
        brickTimer_.begin();
        const std::uint64_t blocks = (regionBricks + 1023) / 1024;
        flags_.reserve(regionBricks * 4, &gpuBytes_);
        blockSums_.reserve(blocks * 4, &gpuBytes_);
        zero(flags_, regionBricks * 4);
        flags_.bindStorage(3);
        fragments_.bindStorage(2);
        flag_.use();
        glUniform1ui(flag_.uniform("uCount"), fragmentCount);
        glDispatchCompute(groupsFor(fragmentCount, maxGroups_), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

        slotBricks_.reserve(std::min<std::uint64_t>(regionBricks, fragmentCount) * 4, &gpuBytes_);
        blockSums_.bindStorage(4);
        counts_.bindStorage(5);
        slotBricks_.bindStorage(6);
        scan_.use();
        glUniform1ui(scan_.uniform("uBrickCount"), static_cast<GLuint>(regionBricks));
        glUniform1ui(scan_.uniform("uBlockCount"), static_cast<GLuint>(blocks));
        for (int phase = 0; phase < 3; ++phase) {
            glUniform1i(scan_.uniform("uPhase"), phase);
            glDispatchCompute(phase == 1 ? 1 : static_cast<GLuint>(blocks), 1, 1);
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        }
        GLuint activeBricks = 0;
        {
            const TraceSpan span("wait for the touched bricks");
            std::memcpy(&activeBricks, small_.read(counts_.id(), 4, &gpuBytes_), 4);
        }
        if (activeBricks > brickBudget_) {
            brickTimer_.end();
            return false;
        }

        const std::uint64_t brickWords = std::uint64_t(activeBricks) * words_ * kBrickVoxels;
        brickWords_.reserve(brickWords * 4, &gpuBytes_);
        zero(brickWords_, brickWords * 4);
        brickWords_.bindStorage(7);
        if (albedo_) albedoFragments_.bindStorage(4); // the scan's block sums were bound there
        scatter_.use();
        glUniform1ui(scatter_.uniform("uCount"), fragmentCount);
        glDispatchCompute(groupsFor(fragmentCount, maxGroups_), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        if (reduce_ == Reduce::Max) {
            maxOrient_.use();
            glUniform1ui(maxOrient_.uniform("uCount"), fragmentCount);
            glDispatchCompute(groupsFor(fragmentCount, maxGroups_), 1, 1);
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        }
        brickTimer_.end();
        checkGlError("brick passes");
        notePeak();

        // Per pass the host waits for the fragment count, the touched bricks'
        // count and (in the resolver) the resolved totals, each a few bytes;
        // the packed bricks' copy is taken in during the next pass's raster.
        if (item.partial || hostResolve_) {
            readPartial(item.min, bricks, activeBricks);
        } else {
            resolver_->startResolve(brickWords_.id(), activeBricks,
                                    BrickKeys{slotBricks_.id(), true, item.min / 8, bricks}, fragmentCount);
            pendingTarget_ = &current_->packed;
        }
        notePeak();
        counters_.fragments += fragmentCount;
        ++counters_.passes;
        return true;
    }

    /// The sampling pass over the items the raster appended: one thread per
    /// item, sized on the GPU from the item count.
    void runSampling(const WorkItem& item, glm::ivec3 bricks) {
        sampleTimer_.begin();
        sampleDispatch_.use();
        glUniform1ui(sampleDispatch_.uniform("uItemCapacity"), static_cast<GLuint>(itemSlots_));
        glUniform1ui(sampleDispatch_.uniform("uGroupSize"), kSampleGroup);
        glUniform1ui(sampleDispatch_.uniform("uMaxGroups"), maxGroups_);
        itemCounter_.bindStorage(7);
        glDispatchCompute(1, 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
        sample_.use();
        setRegionUniforms(sample_, item.min, bricks);
        glUniform1ui(sample_.uniform("uCapacity"), static_cast<GLuint>(fragmentSlots_));
        glUniform1ui(sample_.uniform("uItemCapacity"), static_cast<GLuint>(itemSlots_));
        fragments_.bindStorage(2);
        glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, counter_.id());
        counter_.bindStorage(3); // the wrap flag (the brick passes bind their own buffer there later)
        glBindTextureUnit(0, texture_);
        if (albedo_) {
            albedoFragments_.bindStorage(4);
            glBindTextureUnit(1, albedoTexture_);
        }
        slices_.bindStorage(5);
        items_.bindStorage(6);
        glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, itemCounter_.id());
        glDispatchComputeIndirect(16);
        sampleTimer_.end();
        checkGlError("sampling pass");
    }

    /// The fragment counter and its wrap flag, the item counter and its flag,
    /// and the point sprites drawn (0 with triangles), once the passes before
    /// are done.
    void readCounts(GLuint (&count)[5]) {
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_ATOMIC_COUNTER_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        const TraceSpan span("wait for the fragment count");
        std::memcpy(count, small_.read({{counter_.id(), 0, 8}, {itemCounter_.id(), 0, 8}, {runDraw_.id(), 0, 4}}, &gpuBytes_), 20);
    }

    /// The uniforms the raster and the sampling programs share: the yarn, the
    /// sampling and the region.
    void setRegionUniforms(const GlProgram& program, glm::ivec3 regionMin, glm::ivec3 bricks) const {
        glUniform1f(program.uniform("uRadius"), float(plan_.options.radius / grid_.voxelSize));
        glUniform1i(program.uniform("uSupersample"), settings_.base.supersample);
        glUniform1f(program.uniform("uSupport"), float(support_));
        glUniform3i(program.uniform("uRegionMin"), regionMin.x, regionMin.y, regionMin.z);
        glUniform3i(program.uniform("uRegionBricks"), bricks.x, bricks.y, bricks.z);
    }

    /// Sizes the fragment list (and with albedo its colour list) for
    /// fragmentSlots_ and the item list for itemSlots_ (a list already as
    /// large is kept as it is).
    void reserveLists() {
        fragments_.reserve(fragmentSlots_ * sizeof(GpuFragment), &gpuBytes_);
        if (albedo_) albedoFragments_.reserve(fragmentSlots_ * sizeof(GpuAlbedoFragment), &gpuBytes_);
        items_.reserve(itemSlots_ * sizeof(GpuSampleItem), &gpuBytes_);
    }

    /// Zeroes the first `bytes` (a multiple of 4) of `buffer` with a dispatch
    /// (see buffer_clear.comp for why not glClearNamedBufferSubData).
    void zero(GlBuffer& buffer, std::uint64_t bytes) {
        clear_.use();
        glUniform1ui(clear_.uniform("uWords"), static_cast<GLuint>(bytes / 4));
        buffer.bindStorage(0);
        glDispatchCompute(groupsFor(bytes / 4, maxGroups_), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }

    /// Reads back the raw words of a brick drawn in several passes and adds
    /// them to its accumulator; run() resolves it once all passes are in.
    void readPartial(glm::ivec3 min, glm::ivec3 bricks, GLuint activeBricks) {
        const auto readStart = std::chrono::steady_clock::now();
        const std::uint64_t brickWords = std::uint64_t(activeBricks) * words_ * kBrickVoxels;
        std::vector<std::uint32_t> slotBrick(activeBricks);
        std::memcpy(slotBrick.data(), small_.read(slotBricks_.id(), std::uint64_t(activeBricks) * 4, &gpuBytes_),
                    std::size_t(activeBricks) * 4);
        const auto* words = static_cast<const std::uint32_t*>(readback_.read(brickWords_.id(), brickWords * 4, &gpuBytes_));
        const std::size_t perBrick = std::size_t(words_) * kBrickVoxels;
        for (GLuint slot = 0; slot < activeBricks; ++slot) {
            const std::uint32_t b = slotBrick[slot];
            const glm::ivec3 local(b % bricks.x, (b / bricks.x) % bricks.y, b / (bricks.x * bricks.y));
            const std::uint64_t key = brickKey(min / 8 + local);
            const std::uint32_t* src = words + slot * perBrick;
            auto [it, inserted] = slotOfKey_.try_emplace(key, partials_.size());
            if (inserted) {
                partials_.push_back({key, std::vector<std::uint32_t>(src, src + perBrick)});
            } else {
                combineAccumulators(reduce_, partials_[it->second].words.data(), src, albedo_);
                ++counters_.hostSummedBricks;
            }
        }
        partialReadSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - readStart).count();
    }

    /// Takes in the packed bricks still on their way (into the region they
    /// belong to), then hands a finished region that waited for them to the sink.
    void finishReadbacks() {
        const TraceSpan span("take in the pass before");
        if (resolver_->resolvePending()) {
            resolver_->finishResolve(*pendingTarget_);
            pendingTarget_ = nullptr;
        }
        if (awaiting_) {
            const TraceSpan handOver("hand the region to the writer");
            sink_->consume(awaiting_->region, std::move(awaiting_->packed));
            awaiting_.reset();
        }
    }

    /// Copies the resolver's counters (totals so far) into the backend's.
    void noteResolver() {
        counters_.resolveSeconds = resolver_->gpuSeconds();
        counters_.readbackSeconds = partialReadSeconds_ + resolver_->readbackSeconds();
        counters_.readbackBytes = small_.bytesRead() + readback_.bytesRead() + resolver_->bytesRead();
    }

    void notePeak() { counters_.peakGpuBytes = std::max(counters_.peakGpuBytes, gpuBytes_); }

    const SlicePlan& plan_;
    const CrossSection& xs_;
    const VoxelGrid& grid_;
    const GlVoxelizeSettings& settings_;
    GlVoxelizeCounters& counters_;
    std::unique_ptr<GlContext> context_;
    Reduce reduce_;
    bool albedo_; ///< --albedo: the ALBEDO program variants, a colour list and three more words a voxel
    bool hostResolve_ = false; ///< BrickResolve::Host (settled from Auto by the platform)
    bool prepared_ = false;    ///< prepare() done
    int words_;
    std::uint64_t capacity_ = 0, brickBudget_ = 0, gpuBytes_ = 0;
    std::uint32_t counterStart_ = settings_.firstCounterStart;
    std::uint32_t itemCounterStart_ = settings_.firstItemCounterStart;
    std::uint64_t maxBlock_ = 0; ///< GL_MAX_SHADER_STORAGE_BLOCK_SIZE, bytes
    int regionCap_ = 1024;
    int pointMargin_ = 0; ///< pixels around a region's face with point sprites; 0: triangles
    int runSlices_ = 1; ///< slices a point sprite draws at most (chooseSlicePrimitive); 1 with triangles
    std::uint64_t fragmentSlots_ = 0; ///< fragments the list holds now (grows up to capacity_)
    std::uint64_t itemSlots_ = 0;     ///< sample items the item list holds now (likewise)
    std::uint32_t uniformSlices_ = 0; ///< slices per segment when all segments agree, else 0
    GLuint maxGroups_ = 65535;
    ReadbackBuffer small_, readback_;
    GlBuffer segments_, drawList_, fragments_, albedoFragments_, counter_, flags_, blockSums_, counts_, slotBricks_, brickWords_;
    GlBuffer slices_, items_, itemCounter_; ///< the placed slices, the sample items and their counter
    GlBuffer runs_, runDraw_; ///< point sprites: the runs of slices, and the draw's indirect command
    GLuint texture_ = 0, albedoTexture_ = 0, vao_ = 0, fbo_ = 0;
    double support_ = 0.0; ///< textureSupport() of the cross-section
    std::unique_ptr<SlicePlacer> placer_;
    GlProgram raster_, sample_, sampleDispatch_, clear_, flag_, scan_, scatter_, maxOrient_;
    std::unique_ptr<GlBrickResolver> resolver_;
    /// A region being rasterized, or done and waiting for its last packed bricks.
    struct RegionInFlight {
        ZoomRegion region;
        PackedBricks packed; ///< its resolved bricks so far
    };
    RegionSink* sink_ = nullptr;                ///< during run()
    std::unique_ptr<RegionInFlight> current_;  ///< the region being rasterized
    std::unique_ptr<RegionInFlight> awaiting_; ///< the region before, until its last bricks are in
    PackedBricks* pendingTarget_ = nullptr;    ///< where the resolve in flight appends
    GpuTimer placeTimer_{context_->info().hardware()}, rasterTimer_{context_->info().hardware()},
        sampleTimer_{context_->info().hardware()}, brickTimer_{context_->info().hardware()};
    /// The current region's raw bricks: those drawn in several passes (their
    /// words summed on the host), or all of them with the host resolve.
    std::vector<BrickAccumulator> partials_;
    std::unordered_map<std::uint64_t, std::size_t> slotOfKey_; ///< key -> index in partials_
    double partialReadSeconds_ = 0.0;
};

GlBackend::GlBackend(const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid,
                     const GlVoxelizeSettings& settings, GlVoxelizeCounters& counters,
                     std::unique_ptr<GlContext> context)
    : counters_(counters) {
    checkSupersample(settings.base.supersample);
    impl_ = std::make_unique<Impl>(plan, xs, grid, settings, counters, std::move(context));
}
GlBackend::~GlBackend() = default;
std::uint64_t GlBackend::fragmentBudget() const { return impl_->fragmentBudget(); }
int GlBackend::maxRegionSize() const { return impl_->maxRegionSize(); }
void GlBackend::prepare() { impl_->prepare(); }
void GlBackend::run(const std::vector<ZoomRegion>& regions, RegionSink& sink) { impl_->run(regions, sink); }
void GlBackend::releaseThread() { impl_->releaseThread(); }

JsonObject GlBackend::stats() const {
    const GlVoxelizeCounters& c = counters_;
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

StageSeconds GlBackend::voxelizeParts() const {
    const GlVoxelizeCounters& c = counters_;
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
                       const GlVoxelizeSettings& settings, GlVoxelizeCounters* counters) {
    GlVoxelizeCounters local;
    GlVoxelizeCounters& c = counters ? *counters : local;
    GlBackend backend(plan, xs, grid, settings, c);
    const ZoomPlan zoom = planZoomRegions(plan, grid, xs, {backend.fragmentBudget(), backend.maxRegionSize(), settings.base.supersample});
    c.plannedRegions = zoom.regions.size();
    CollectingSink sink;
    backend.run(zoom.regions, sink);
    if (!sink.accumulators.empty())
        return resolveVolume(grid, settings.base.reduce, settings.base.overlap, sink.accumulators);
    return unpackVolume(grid, settings.base.reduce, sink.regions);
}

} // namespace yv
