#include "pipeline/voxelize_run.h"

#include "bcc.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/output_path.h"
#include "core/process_memory.h"
#include "core/trace.h"
#include "core/world_units.h"
#include "cpu/cpu_region_backend.h"
#include "garment/cross_section.h"
#include "garment/curve_check.h"
#include "garment/slices.h"
#include "gpu/dense_voxelizer.h"
#include "gpu/egl_context.h"
#include "gpu/gl_voxelizer.h"
#include "pipeline/cluster.h"
#include "pipeline/run_fingerprint.h"
#include "pipeline/yarn_radius.h"
#include "plan/feasibility.h"
#include "plan/grid.h"
#include "plan/resource_estimate.h"
#include "plan/zoom_plan.h"
#include "store/brick_store.h"
#include "store/region_writer.h"
#include "vdb/lod_pyramid.h"
#include "vdb/merge.h"
#include "vdb/vdb_writer.h"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <future>
#include <memory>
#include <optional>
#include <thread>
#include <unordered_map>

namespace yv {
namespace {

/// Hands finished regions to the RegionWriter, which resolves or unpacks them
/// on its threads and puts them into the .vdb's leaves or a work directory.
class QueueSink : public RegionSink {
  public:
    explicit QueueSink(RegionWriter& writer) : writer_(writer) {}
    void consume(const ZoomRegion& r, PackedBricks&& bricks) override {
        writer_.submitResolved(r.id, r.min, r.max, std::move(bricks));
        ++consumed;
    }
    void consumeAccumulators(const ZoomRegion& r, std::vector<BrickAccumulator>&& accumulators) override {
        writer_.submit(r.id, r.min, r.max, std::move(accumulators));
        ++consumed;
    }
    PackedBricks emptyPackedBricks() override { return writer_.recycledPackedBricks(); }
    /// SIGINT or SIGTERM: stop at this region boundary.
    bool stopRequested() override { return interruptSignal() != 0; }
    std::uint64_t consumed = 0; ///< regions handed to the writer

  private:
    RegionWriter& writer_;
};

/// Feeds the disk pipeline; on --resume, skips regions whose files are
/// complete and verified.
class StoreSink : public QueueSink {
  public:
    StoreSink(BrickStore& store, RegionWriter& writer, bool resume) : QueueSink(writer), store_(store), resume_(resume) {}
    bool alreadyDone(const ZoomRegion& r) override {
        if (!resume_) return false;
        std::string why;
        if (store_.hasVerifiedRegion(r.id, r.min, r.max, &why)) return true;
        if (!why.empty()) ++recomputed;
        return false;
    }
    std::uint64_t recomputed = 0; ///< damaged region files found on resume

  private:
    BrickStore& store_;
    bool resume_;
};

/// Test hook, never set in real runs: YARNVOX_TEST_KILL_RANK=R:K makes rank R
/// kill itself (SIGKILL, as a crashed node would end) once it has rasterized K
/// regions, so tests can check what the other ranks and --resume make of it.
struct KillHook {
    int rank = -1;
    std::uint64_t after = 0;
    static KillHook fromEnvironment() {
        KillHook hook;
        if (const char* text = std::getenv("YARNVOX_TEST_KILL_RANK")) {
            unsigned long long after = 0;
            if (std::sscanf(text, "%d:%llu", &hook.rank, &after) != 2) hook.rank = -1;
            hook.after = after;
        }
        return hook;
    }
};

/// One rank's part of an MPI run: all ranks walk the regions in the same
/// order (largest first) and each takes a region only when the hand-out gives
/// it to this rank; the others' regions count as done here.
class ClaimSink : public StoreSink {
  public:
    ClaimSink(BrickStore& store, RegionWriter& writer, bool resume, Cluster& cluster, const std::vector<ZoomRegion>& order)
        : StoreSink(store, writer, resume), cluster_(cluster), hook_(KillHook::fromEnvironment()) {
        for (std::size_t i = 0; i < order.size(); ++i) positionOf_.emplace(order[i].id, i);
        cluster_.beginHandout(order.size());
    }
    bool alreadyDone(const ZoomRegion& r) override {
        const std::uint64_t position = positionOf_.at(r.id);
        // Hand-out positions only grow, for every rank: skip ahead to this one.
        while (!exhausted_ && (!claim_ || *claim_ < position)) {
            claim_ = cluster_.claim();
            exhausted_ = !claim_;
        }
        if (exhausted_ || *claim_ != position) {
            ++elsewhere;
            return true;
        }
        // Dies holding a region it was given: the run can never finish without it.
        if (hook_.rank == cluster_.rank() && consumed == hook_.after) std::raise(SIGKILL);
        if (StoreSink::alreadyDone(r)) {
            ++resumed;
            return true;
        }
        return false;
    }
    std::uint64_t elsewhere = 0; ///< regions other ranks were given
    std::uint64_t resumed = 0;   ///< regions of this rank found complete on disk

  private:
    Cluster& cluster_;
    KillHook hook_;
    std::unordered_map<std::uint64_t, std::uint64_t> positionOf_;
    std::optional<std::uint64_t> claim_;
    bool exhausted_ = false;
};

/// The regions in the order they are handed out: largest first (by the
/// planner's fragment estimate), so no rank starts a big one last while the
/// others sit idle; ties in plan order.
std::vector<ZoomRegion> largestFirst(const std::vector<ZoomRegion>& regions) {
    std::vector<ZoomRegion> order = regions;
    std::stable_sort(order.begin(), order.end(), [](const ZoomRegion& a, const ZoomRegion& b) {
        return a.estimatedFragments > b.estimatedFragments;
    });
    return order;
}

/// Host memory the writer queue may hold: an eighth of physical memory, at most 4 GiB.
std::size_t writerQueueBytes() {
    return static_cast<std::size_t>(std::min<std::uint64_t>(physicalMemoryBytes() / 8, std::uint64_t(4) << 30));
}

/// Times the run's stages one after another; they go to --stats and the work
/// dir's manifest (not into the .vdb: its bytes are the same run after run).
class StageTimer {
  public:
    double lap(const std::string& stage) {
        traceSpanSince(stage, last_);
        const auto now = std::chrono::steady_clock::now();
        const double s = std::chrono::duration<double>(now - last_).count();
        last_ = now;
        laps_.emplace_back(stage, s);
        return s;
    }
    const StageSeconds& laps() const { return laps_; }
    JsonObject json() const {
        JsonObject out;
        for (const auto& [stage, seconds] : laps_) out.set(stage, seconds);
        return out;
    }

  private:
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
    StageSeconds laps_;
};

/// The stages so far and the parts of the voxelize stage that the writer
/// threads and the GL backend time, for the work dir's manifest.
StageSeconds workDirStages(const StageTimer& timer, const RegionWriterStats& writer, const GlVoxelizeCounters* gl) {
    StageSeconds out = timer.laps();
    if (gl)
        out.insert(out.end(), {{"voxelize.gpu_raster", gl->rasterSeconds},
                               {"voxelize.gpu_sample", gl->sampleSeconds},
                               {"voxelize.gpu_bricks", gl->brickSeconds},
                               {"voxelize.gpu_resolve", gl->resolveSeconds},
                               {"voxelize.readback", gl->readbackSeconds}});
    out.insert(out.end(), {{"voxelize.store_resolve", writer.resolveSeconds},
                           {"voxelize.store_encode", writer.encodeSeconds},
                           {"voxelize.store_write", writer.writeSeconds},
                           {"voxelize.store_wait", writer.submitWaitSeconds}});
    return out;
}

/// The backend "auto" stands for: the GL backend on a GPU (or for the dense
/// method, which only it has); else the CPU reference, which on a machine
/// without a GPU is far faster than GL through a software rasteriser. The GL
/// context made with the run (`pending`, or the error making it threw; none
/// for --backend cpu or the dense method) tells whether there is a GPU; where
/// the GL backend runs, `context` gets it.
std::string resolveBackend(const VoxelizeRequest& a, std::future<std::unique_ptr<GlContext>>& pending,
                           std::unique_ptr<GlContext>& context, const std::function<void(const std::string&)>& note) {
    if (a.method == "dense") return "gl";
    if (a.backend == "gl" && pending.valid()) context = pending.get(); // no GL 4.5 context: its error, here
    if (a.backend != "auto") return a.backend;
    try {
        if (std::unique_ptr<GlContext> probe = pending.get(); probe->info().hardware()) {
            context = std::move(probe);
            return "gl";
        }
    } catch (const Error&) {
    }
    if (a.verbose && !a.quiet) note("backend: no GPU found, using the CPU backend (--backend gl forces the software GL path)");
    return "cpu";
}

/// --albedo's limits, said before any work: the sparse method with the mean
/// reduction carries the colour (on either backend).
void checkAlbedoRequest(const VoxelizeRequest& a) {
    if (!a.albedo) return;
    if (a.method == "dense") throw Error("--albedo: the dense method has no albedo; use --method sparse");
    if (a.reduce != "mean") throw Error("--albedo needs --reduce mean (a colour is averaged like the density, not maxed)");
}

/// Three significant digits, for messages.
std::string shortNumber(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", v);
    return text;
}

/// Destroys the GL backend on a thread of its own (its GPU buffers and context
/// take tens of ms to free) while the caller goes on to write the output; the
/// thread is joined where the returned handle goes.
std::jthread freeInBackground(std::unique_ptr<RegionRasterizer> rasterizer) {
    rasterizer->releaseThread();
    return std::jthread([r = std::move(rasterizer)]() mutable {
        const TraceSpan span("free the GPU's buffers and context");
        r.reset();
    });
}

/// The zoom regions' rasterizer, whichever backend, and what it counted.
struct Backend {
    GlVoxelizeSettings glSettings; ///< the GL backend keeps a reference to it
    GlVoxelizeCounters gl;
    CpuRegionCounters cpu;
    std::unique_ptr<RegionRasterizer> rasterizer;
    bool isGl = false;

    std::uint64_t resumedRegions() const { return isGl ? gl.resumedRegions : cpu.resumedRegions; }
    /// The counts of a whole MPI run, on rank 0.
    void setRegionTotals(std::uint64_t computed, std::uint64_t resumed) {
        (isGl ? gl.regions : cpu.regions) = computed;
        (isGl ? gl.resumedRegions : cpu.resumedRegions) = resumed;
    }
    std::uint64_t samples() const { return isGl ? gl.fragments : cpu.sampling.samples; }
};

} // namespace

/// What reading and slicing the garment gives the rest of the run.
struct Sliced {
    Garment garment;
    CrossSection xs;
    YarnRadiusChoice radius;
    SliceOptions sliceOptions;
    bool explicitSpacing = false;
    SlicePlan plan;
};

/// A GL context made on this thread (and current on it), or the error that
/// making it threw, as resolveBackend takes it; `seconds`: how long it took.
std::future<std::unique_ptr<GlContext>> makeGlContextHere(const GlContextOptions& options, double& seconds) {
    const auto start = std::chrono::steady_clock::now();
    std::promise<std::unique_ptr<GlContext>> made;
    try {
        const TraceSpan span("make the GL context");
        made.set_value(std::make_unique<GlContext>(options));
    } catch (...) {
        made.set_exception(std::current_exception());
    }
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return made.get_future();
}

VoxelizeReport runVoxelize(const VoxelizeRequest& args, const std::function<void(const std::string&)>& note) {
    // Where the results go is checked before minutes of work, not after.
    checkOutputPath(args.output, "-o", {args.input});
    if (!args.statsPath.empty()) checkOutputPath(args.statsPath, "--stats", {args.input, args.output});
    if (!args.statsPath.empty() && args.statsPath == args.output)
        throw Error("--stats " + args.statsPath + ": is the same file as -o: refusing to overwrite it");
    // Several processes under mpirun share the regions of one run; one (or
    // mpirun -np 1) runs as a plain process.
    Cluster* const group = !args.alone && cluster() && cluster()->size() > 1 ? cluster() : nullptr;
    if (group && args.method == "dense") throw Error("--method dense runs in one process, not under mpirun -np 2 or more");
    VoxelizeRequest a = args;
    if (a.method == "dense" && a.backend == "cpu") throw Error("--method dense needs --backend gl");
    if (a.method == "dense" && (!a.workDir.empty() || a.resume)) throw Error("--work-dir and --resume need the sparse method");
    checkAlbedoRequest(a);
    // Under mpirun rank 0 speaks for the run: the others see the same things.
    const auto tell = [&](const std::string& line) {
        if (!a.quiet && (!group || group->rank() == 0)) note(line);
    };
    // The garment is read and sliced on a thread of its own while this thread
    // makes the GL context: the driver's start-up overlaps the slicing, and
    // the context is current where the GL backend runs (binding a context
    // made on another thread took about 0.03 s on the H100).
    StageTimer timer;
    std::future<Sliced> pendingSlices = std::async(std::launch::async, [&] {
        Sliced s;
        Garment& garment = s.garment;
        garment = readBcc(a.input);
        // Real files repeat points and mislabel loops: tidied here, said once.
        const CurveCheckReport curveReport = checkCurves(garment, a.input);
        if (const std::string dropped = curveReport.droppedText(a.input); !dropped.empty()) tell(dropped);
        for (const std::string& w : curveReport.warnings) tell("warning: " + w);
        timer.lap("read");

        s.xs = makeCrossSection(a.crossSection, a.albedo);
        const CrossSection& xs = s.xs;
        SliceOptions& sliceOptions = s.sliceOptions;
        sliceOptions.twist = a.twist;
        s.radius = chooseYarnRadius(a.yarnRadius, xs, garment, a.input);
        const YarnRadiusChoice& radius = s.radius;
        if (!radius.note.empty()) tell(radius.note);
        sliceOptions.radius = radius.radius;
        if (a.resolution == 0 && a.voxelSize == 0.0)
            throw Error("give --resolution N (voxels on the longest axis) or --voxel-size H");
        // Slices follow the voxel size, not the garment's control points: one
        // slice per (supersampled) voxel along the yarn, unless asked otherwise.
        const double voxelSize = voxelSizeFor(garment, sliceOptions.radius, a.resolution, a.voxelSize);
        // A run that would leave no voxels is refused before any slicing.
        const RunScale scale{radius.radius, radius.description, voxelSize,
                             a.resolution > 0 ? "--resolution " + std::to_string(a.resolution)
                                              : "--voxel-size " + numberText(a.voxelSize),
                             a.supersample, a.spacing};
        for (const std::string& w : checkRunScale(scale, xs)) tell("warning: " + w);
        // Disk the run needs at least, before minutes of work.
        {
            const std::string outputDir = std::filesystem::path(a.output).parent_path().string();
            const bool store = !a.workDir.empty() || a.keepWorkDir || a.resume || group;
            const RunPlace place{outputDir, store ? (a.workDir.empty() ? outputDir : a.workDir) : ""};
            const TraceSpan span("estimate what the run needs");
            const std::string problem = checkNeeds(estimateNeeds(garment, radius.radius, voxelSize, a.precision == "half"),
                                                   place, scale.voxelSource);
            if (!problem.empty()) throw Error(a.input + ": " + problem);
        }
        s.explicitSpacing = a.slicesPerSegment > 0 || a.spacing > 0.0;
        const bool explicitSpacing = s.explicitSpacing;
        sliceOptions.slicesPerSegment = a.slicesPerSegment;
        sliceOptions.spacing = explicitSpacing ? a.spacing : defaultSliceSpacing(voxelSize, a.supersample);
        s.plan = [&] {
            const TraceSpan span("plan the slices");
            try {
                return planSlices(garment, sliceOptions);
            } catch (const Error& e) {
                throw Error(a.input + ": " + e.what());
            }
        }();
        timer.lap("slices");
        return s;
    });
    std::future<std::unique_ptr<GlContext>> pendingContext;
    double glContextSeconds = 0.0;
    if (a.backend != "cpu" && a.method != "dense")
        pendingContext = makeGlContextHere(GlContextOptions{a.device, std::getenv("YV_GL_DEBUG") != nullptr,
                                                            cluster() ? cluster()->localRank() : 0},
                                           glContextSeconds);
    Sliced sliced = pendingSlices.get();
    const Garment& garment = sliced.garment;
    const CrossSection& xs = sliced.xs;
    const YarnRadiusChoice& radius = sliced.radius;
    const SliceOptions& sliceOptions = sliced.sliceOptions;
    const bool explicitSpacing = sliced.explicitSpacing;
    const SlicePlan& plan = sliced.plan;
    std::unique_ptr<GlContext> glContext;
    a.backend = resolveBackend(args, pendingContext, glContext, note);
    // Every rank must write regions of the same run: rank 0's choice holds.
    if (group) a.backend = group->broadcast(a.backend == "gl") ? "gl" : "cpu";
    const VoxelGrid grid = makeGrid(plan, a.resolution, a.voxelSize);
    if (explicitSpacing && plan.maxSpacing > 1.05 * grid.voxelSize)
        tell("warning: " +
             (a.slicesPerSegment > 0 ? "--slices-per-segment " + std::to_string(a.slicesPerSegment)
                                     : std::string("--slice-spacing")) +
             " places slices up to " + shortNumber(plan.maxSpacing / grid.voxelSize) +
             " voxels apart: each slab is split over the voxels it spans and treated as flat across them, so "
             "bends are coarsened (leave it out for one slice per voxel)");
    VoxelizeSettings settings;
    settings.reduce = a.reduce == "max" ? Reduce::Max : Reduce::Mean;
    settings.overlap = a.overlap == "sum" ? Overlap::Sum : Overlap::Clamp;
    settings.supersample = a.supersample;
    settings.quiet = a.quiet;

    VolumeMetadata meta;
    meta.input = a.input;
    meta.backend = a.backend;
    meta.crossSection = xs.name;
    meta.resolution = a.resolution;
    meta.sliceCount = plan.sliceCount;
    meta.yarnRadius = sliceOptions.radius;
    meta.yarnRadiusSource = radius.source;
    meta.twist = a.twist;
    meta.supersample = a.supersample;
    meta.overlap = toString(settings.overlap);
    meta.sliceSpacing = plan.maxSpacing;
    meta.slicesPerSegment = a.slicesPerSegment;
    meta.sliceSpacingOption = a.spacing;
    meta.albedo = xs.hasAlbedo();

    VdbWriteTimings writeTimings;
    VdbWriteOptions writeOptions;
    writeOptions.compression = parseVdbCompression(a.compression);
    writeOptions.precision = parseVdbPrecision(a.precision);
    writeOptions.lodLevels = checkedLodLevels(a.lod, grid);
    writeOptions.albedo = xs.hasAlbedo();
    writeOptions.timings = &writeTimings;

    // The checks before slicing refuse what cannot leave a voxel; a yarn that
    // falls between sample pixels can still miss them all. An empty volume is
    // never a result: the run fails before anything is written.
    const auto refuseEmpty = [&](std::uint64_t activeVoxels) {
        if (activeVoxels == 0)
            throw Error(a.input + ": no yarn reached a voxel's samples (" + radius.description + ", voxel size " +
                        numberText(grid.voxelSize) + "): the volume would be empty, " + a.output +
                        " was not written (a finer --resolution, a higher --supersample, or --cross-section disk)");
    };

    VoxelizeReport report;
    report.backend = a.backend;
    report.reduce = settings.reduce;
    report.overlap = settings.overlap;
    report.slices = plan.sliceCount;
    report.dims = grid.dims;
    report.voxelSize = grid.voxelSize;
    JsonObject backendStats;
    std::uint64_t samples = 0;
    if (a.method == "dense") {
        // The paper's method, kept as a benchmark baseline: one dense 3D texture set.
        GlVoxelizeSettings gl;
        gl.base = settings;
        gl.device = a.device;
        DenseVoxelizeCounters counters;
        const BrickVolume volume = voxelizeDense(plan, xs, grid, gl, &counters);
        report.voxelizeSeconds = timer.lap("voxelize");
        meta.backend = "gl-dense";
        report.activeVoxels = volume.activeVoxelCount();
        refuseEmpty(report.activeVoxels);
        writeVdb(a.output, volume, meta, writeOptions);
        timer.lap("write");
        report.bricks = volume.bricks.size();
        report.tally = volume.tally;
        backendStats.set("renderer", counters.renderer)
            .set("platform", counters.platform)
            .set("method", "dense")
            .set("gpu_peak_bytes", counters.textureBytes)
            .set("slices_drawn", counters.instances)
            .set("gpu_clear_seconds", counters.clearSeconds)
            .set("gpu_raster_seconds", counters.rasterSeconds)
            .set("readback_seconds", counters.readbackSeconds);
    } else {
        // Either backend rasterizes zoom regions one after another into the same writer.
        Backend backend;
        backend.isGl = a.backend == "gl";
        if (backend.isGl) {
            GlVoxelizeSettings& gl = backend.glSettings;
            gl.base = settings;
            gl.device = a.device;
            gl.spreadIndex = cluster() ? cluster()->localRank() : 0; // each rank its own GPU, alone or not
            gl.fragmentCapacity = a.fragmentCapacity;
            gl.verbose = a.verbose && !a.quiet;
            backend.gl.contextSeconds = glContextSeconds;
            const TraceSpan span("set up the GL backend");
            backend.rasterizer = std::make_unique<GlBackend>(plan, xs, grid, gl, backend.gl, std::move(glContext));
        } else {
            backend.rasterizer = std::make_unique<CpuRegionBackend>(plan, xs, grid, settings, backend.cpu, a.fragmentCapacity);
        }
        RegionRasterizer& rasterizer = *backend.rasterizer;
        // The ranks' budgets differ (each sees what the others left free):
        // all plan with rank 0's, so they plan the same regions.
        const std::uint64_t budget = group ? group->broadcast(rasterizer.fragmentBudget()) : rasterizer.fragmentBudget();
        // The zoom plan (on the host's cores) while the backend uploads the
        // slices and builds its programs (the driver, on this thread).
        double zoomPlanSeconds = 0.0;
        std::future<ZoomPlan> pendingZoom = std::async(std::launch::async, [&] {
            const auto zoomStart = std::chrono::steady_clock::now();
            ZoomPlan planned = planZoomRegions(plan, grid, xs, {budget, rasterizer.maxRegionSize(), a.supersample});
            traceSpanSince("plan the zoom regions", zoomStart);
            zoomPlanSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - zoomStart).count();
            return planned;
        });
        rasterizer.prepare();
        const ZoomPlan zoom = pendingZoom.get();
        backend.gl.plannedRegions = zoom.regions.size();
        timer.lap("plan");
        if (a.verbose)
            tell("plan: " + std::to_string(zoom.regions.size()) + " zoom regions, " + numberText(zoom.estimatedFragments) +
                 " fragments expected, budget " + std::to_string(rasterizer.fragmentBudget()) + " per pass");

        // Without a work dir, regions go straight into the .vdb's leaves.
        // With one, they stream through a bounded queue to it while the
        // backend moves on, and the merge then writes the .vdb from the files.
        const bool ownWorkDir = a.workDir.empty();
        const bool inMemory = ownWorkDir && !a.keepWorkDir && !group;
        std::jthread freeing; // the GL backend, freed while the output is written
        const std::string workDir = ownWorkDir ? a.output + ".work" : a.workDir;
        RegionWriterStats writerStats;
        std::uint64_t recomputed = 0, storeBytes = 0;
        // Unpacking or resolving regions and compressing them keep several cores busy.
        const unsigned workers = std::max(2u, std::thread::hardware_concurrency() / 2);
        if (inMemory) {
            VdbAssembler assembler(a.output, grid, settings.reduce, writeOptions);
            RegionWriter writer(
                [&](std::uint64_t id, std::vector<VoxelBrick>&& resolved) {
                    assembler.add(resolved, "region " + std::to_string(id));
                },
                [&](std::uint64_t id, const PackedBricks& packed) { assembler.add(packed, "region " + std::to_string(id)); },
                settings.reduce, settings.overlap, writerQueueBytes(), workers);
            QueueSink sink(writer);
            {
                const InterruptScope interruptible;
                rasterizer.run(zoom.regions, sink);
            }
            backendStats = rasterizer.stats();
            if (backend.isGl) freeing = freeInBackground(std::move(backend.rasterizer));
            const std::vector<RegionInfo> regions = writer.finish();
            for (const RegionInfo& r : regions) {
                report.activeVoxels += r.activeVoxels;
                report.bricks += r.brickCount;
            }
            meta.regions = recordedRegions(regions); // as a merge of the same regions records them
            if (interruptSignal())
                throw Error("interrupted by " + interruptSignalName() + " after " + std::to_string(sink.consumed) +
                            " of " + std::to_string(zoom.regions.size()) + " regions: nothing was written (" +
                            a.output + " is untouched; a run with --work-dir DIR can be resumed)");
            writerStats = writer.stats();
            report.tally = writerStats.tally;
            report.voxelizeSeconds = timer.lap("voxelize");
            refuseEmpty(report.activeVoxels);
            assembler.write(meta);
            timer.lap("write");
        } else {
            // The run's fingerprint reads the whole garment file: only a work
            // dir's manifest needs it (90 ms of a 1.2 s run in memory).
            StoreManifest manifest;
            manifest.fingerprint = runFingerprint(a.input, sliceOptions, xs, grid, settings.reduce, settings.overlap,
                                                  a.supersample, zoom, a.backend);
            manifest.samplingCode = samplingCodeHash();
            manifest.grid = grid;
            manifest.reduce = settings.reduce;
            manifest.run = meta;
            // Rank 0 opens (or clears, or resumes) the work dir; the others join it after.
            std::optional<BrickStore> opened;
            if (!group || group->rank() == 0) opened.emplace(workDir, manifest, a.resume);
            if (group) {
                group->broadcast(0);
                if (group->rank() != 0) opened.emplace(workDir, manifest, JoinStore{});
            }
            BrickStore& store = *opened;
            RegionWriter writer(store, settings.reduce, settings.overlap, writerQueueBytes(), workers);
            const std::vector<ZoomRegion> order = group ? largestFirst(zoom.regions) : std::vector<ZoomRegion>{};
            std::optional<StoreSink> ownSink;
            std::optional<ClaimSink> claimSink;
            if (group)
                claimSink.emplace(store, writer, a.resume, *group, order);
            else
                ownSink.emplace(store, writer, a.resume);
            StoreSink& sink = group ? *claimSink : *ownSink;
            {
                const InterruptScope interruptible;
                rasterizer.run(group ? order : zoom.regions, sink);
            }
            backendStats = rasterizer.stats();
            if (backend.isGl) freeing = freeInBackground(std::move(backend.rasterizer));
            writer.finish(); // every region handed over is on disk before the run stops
            writerStats = writer.stats();
            recomputed = sink.recomputed;
            std::uint64_t consumed = sink.consumed, resumed = backend.resumedRegions();
            bool interrupted = interruptSignal() != 0;
            if (group) {
                // Rank 0 sums what every rank did; the others are done here.
                const ResolveTally& t = writerStats.tally;
                const std::vector<double> sums = group->endHandout(
                    {interrupted ? 1.0 : 0.0, double(consumed), double(claimSink->resumed), double(recomputed),
                     double(t.activeVoxels), double(t.voxelsOverOne), t.densitySum, t.rawDensitySum, t.excessOverOne});
                if (a.verbose && !a.quiet)
                    note("rank " + std::to_string(group->rank()) + ": " + std::to_string(sink.consumed) +
                         " regions rasterized, " + std::to_string(claimSink->resumed) + " found done on disk");
                if (group->rank() != 0) {
                    report.rankOnly = true;
                    return report;
                }
                interrupted = sums[0] > 0.0;
                consumed = static_cast<std::uint64_t>(sums[1]);
                resumed = static_cast<std::uint64_t>(sums[2]);
                recomputed = static_cast<std::uint64_t>(sums[3]);
                writerStats.tally = ResolveTally{static_cast<std::uint64_t>(sums[4]), static_cast<std::uint64_t>(sums[5]),
                                                 sums[6], sums[7], sums[8]};
                backend.setRegionTotals(consumed, resumed);
            }
            if (interrupted) {
                const std::string& line = commandLine();
                const bool resuming = line.find(" --resume") != std::string::npos;
                throw Error("interrupted by " + (group ? std::string("a signal") : interruptSignalName()) + " after " +
                            std::to_string(consumed + resumed) + " of " + std::to_string(zoom.regions.size()) +
                            " regions, all of them kept in " + workDir + "; go on with: " + line +
                            (resuming ? "" : " --resume"));
            }
            report.voxelizeSeconds = timer.lap("voxelize");
            store.markComplete(zoom.regions.size(), workDirStages(timer, writerStats, backend.isGl ? &backend.gl : nullptr));
            for (const RegionInfo& r : store.listRegions()) {
                report.activeVoxels += r.activeVoxels;
                report.bricks += r.brickCount;
            }
            refuseEmpty(report.activeVoxels);
            mergeStoreToVdb(store, a.output, meta, writeOptions);
            timer.lap("merge");
            storeBytes = store.bytesOnDisk();
            // Regions taken from a resumed run were not resolved here.
            report.tally = writerStats.tally;
            report.tallyComplete = backend.resumedRegions() == 0;
            if (group && ownWorkDir && !a.keepWorkDir) {
                // A default work dir served only to share the regions between the ranks.
                opened.reset();
                std::error_code ec;
                std::filesystem::remove_all(workDir, ec);
            }
        }

        samples = backend.samples();
        if (a.verbose && backend.isGl) {
            const GlVoxelizeCounters& counters = backend.gl;
            tell("renderer: " + counters.renderer + " (" + counters.platform + "); " +
                 std::to_string(counters.plannedRegions) + " regions (" + std::to_string(counters.resumedRegions) +
                 " resumed), " + std::to_string(counters.overflows) + " overflow retries");
        }
        backendStats.set("zoom_plan_seconds", zoomPlanSeconds).set("regions_damaged_recomputed", recomputed)
            .set("store_bytes_on_disk", storeBytes)
            .set("store_resolve_seconds", writerStats.resolveSeconds)
            .set("store_encode_seconds", writerStats.encodeSeconds)
            .set("store_write_seconds", writerStats.writeSeconds)
            .set("store_wait_seconds", writerStats.submitWaitSeconds)
            .set("store_peak_queued_bytes", writerStats.peakQueuedBytes)
            .set("regions_to", inMemory ? "memory" : "work dir")
            .set("ranks", static_cast<std::uint64_t>(group ? group->size() : 1));
    }

    // Releasing the GPU's buffers and context, the writer's threads and the
    // scratch file, once the output is in place.
    timer.lap("finish");
    const double h3 = grid.voxelSize * grid.voxelSize * grid.voxelSize;
    const ResolveTally& tally = report.tally;
    const bool complete = report.tallyComplete;
    report.stats.set("yarnvox_version", YV_VERSION)
        .set("input", a.input)
        .set("output", a.output)
        .set("backend", a.backend)
        .set("reduce", toString(settings.reduce))
        .set("yarns", static_cast<std::uint64_t>(garment.yarns.size()))
        .set("segments", static_cast<std::uint64_t>(plan.segments.size()))
        .set("slices", plan.sliceCount)
        .set("samples", samples)
        .set("voxel_size", grid.voxelSize)
        .set("grid_dims", std::to_string(grid.dims.x) + "x" + std::to_string(grid.dims.y) + "x" +
                              std::to_string(grid.dims.z))
        .set("active_voxels", report.activeVoxels)
        .set("bricks", report.bricks)
        .set("slice_spacing", plan.maxSpacing)
        .set("overlap", toString(settings.overlap))
        .set("fiber_volume", complete ? tally.densitySum * h3 : -1.0)
        .set("voxels_over_one", complete ? static_cast<std::int64_t>(tally.voxelsOverOne) : std::int64_t(-1))
        .set("mass_share_over_one", complete ? tally.excessShare() : -1.0)
        .set("slices_per_second", plan.sliceCount / report.voxelizeSeconds)
        .set("active_voxels_per_second", report.activeVoxels / report.voxelizeSeconds)
        .set("peak_host_bytes", peakResidentBytes())
        .set("vdb_compression", toString(writeOptions.compression))
        .set("vdb_precision", toString(writeOptions.precision))
        .set("vdb_seconds", JsonObject()
                                .set("read_regions", writeTimings.readSeconds)
                                .set("encode_leaves", writeTimings.encodeSeconds)
                                .set("topology", writeTimings.topologySeconds)
                                .set("write", writeTimings.writeSeconds))
        .set("seconds", timer.json())
        .set("backend_stats", backendStats);
    if (!a.statsPath.empty()) {
        const TraceSpan span("write the stats");
        writeTextFileAtomically(a.statsPath, report.stats.dump() + "\n");
    }
    return report;
}

} // namespace yv
