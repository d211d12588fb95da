// `yarnvox voxelize`: garment -> slices -> voxels -> .vdb, with --stats.
#include "bcc.h"
#include "cli/commands.h"
#include "cli/option_checks.h"
#include "cli/output_format.h"
#include "cli/run_fingerprint.h"
#include "cli/yarn_radius.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/output_path.h"
#include "core/process_memory.h"
#include "core/stats.h"
#include "cpu/cpu_voxelizer.h"
#include "garment/cross_section.h"
#include "garment/curve_check.h"
#include "garment/slices.h"
#include "gpu/dense_voxelizer.h"
#include "gpu/egl_context.h"
#include "gpu/gl_voxelizer.h"
#include "plan/feasibility.h"
#include "plan/grid.h"
#include "plan/resource_estimate.h"
#include "plan/zoom_plan.h"
#include "store/brick_store.h"
#include "store/region_writer.h"
#include "vdb/merge.h"
#include "vdb/vdb_writer.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <thread>
#include <unistd.h>

namespace yv {
namespace {

struct VoxelizeArgs {
    std::string input, output, backend = "auto", method = "sparse", crossSection = "fibers", reduce = "mean",
        overlap = "clamp", compression = "mask", precision = "float", statsPath, workDir, format;
    int resolution = 0, slicesPerSegment = 0, supersample = 1, device = -1;
    double voxelSize = 0.0, yarnRadius = 0.0, spacing = 0.0, twist = 0.0;
    std::uint64_t fragmentCapacity = 0;
    bool quiet = false, verbose = false, resume = false, keepWorkDir = false;
};

/// Hands finished regions (resolved on the GPU, packed) to the pipeline
/// (RegionWriter), which unpacks them and writes them to a work dir or puts
/// them straight into the .vdb's leaves.
class QueueSink : public RegionSink {
  public:
    explicit QueueSink(RegionWriter& writer) : writer_(writer) {}
    void consume(const ZoomRegion& r, PackedBricks&& bricks) override {
        writer_.submitResolved(r.id, r.min, r.max, std::move(bricks));
        ++consumed;
    }
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

/// Host memory the disk queue may hold: an eighth of physical memory, at most 4 GiB.
std::size_t writerQueueBytes() {
    const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGE_SIZE);
    const std::size_t physical = pages > 0 && pageSize > 0 ? std::size_t(pages) * std::size_t(pageSize) : (std::size_t(8) << 30);
    return std::min<std::size_t>(physical / 8, std::size_t(4) << 30);
}

class StageTimer {
  public:
    double lap() {
        const auto now = std::chrono::steady_clock::now();
        const double s = std::chrono::duration<double>(now - last_).count();
        last_ = now;
        return s;
    }

  private:
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

/// The backend "auto" stands for: the GL backend on a GPU, or wherever only it
/// can do what was asked (out of core, resume, the dense method); else the CPU
/// reference, which on a machine without a GPU is far faster than GL through
/// a software rasteriser.
std::string resolveBackend(const VoxelizeArgs& a) {
    if (a.backend != "auto") return a.backend;
    if (!a.workDir.empty() || a.resume || a.method == "dense") return "gl";
    try {
        const GlContext probe(GlContextOptions{a.device, false});
        if (probe.info().platform == "device") return "gl";
    } catch (const Error&) {
    }
    if (a.verbose && !a.quiet)
        std::fprintf(stderr, "backend: no GPU found, using the CPU backend (--backend gl forces the software GL path)\n");
    return "cpu";
}

void runVoxelize(const VoxelizeArgs& args) {
    // Where the results go is checked before minutes of work, not after.
    checkOutputPath(args.output, "-o", {args.input});
    if (!args.statsPath.empty()) checkOutputPath(args.statsPath, "--stats", {args.input, args.output});
    if (!args.statsPath.empty() && args.statsPath == args.output)
        throw Error("--stats " + args.statsPath + ": is the same file as -o: refusing to overwrite it");
    VoxelizeArgs a = args;
    a.backend = resolveBackend(args);
    StageTimer timer;
    JsonObject stages;
    Garment garment = readBcc(a.input);
    // Real files repeat points and mislabel loops: tidied here, said once.
    const CurveCheckReport curveReport = checkCurves(garment, a.input);
    if (!a.quiet) {
        if (const std::string dropped = curveReport.droppedText(a.input); !dropped.empty())
            std::fprintf(stderr, "%s\n", dropped.c_str());
        for (const std::string& w : curveReport.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    }
    stages.set("read", timer.lap());

    CrossSection xs = makeCrossSection(a.crossSection);
    SliceOptions sliceOptions;
    sliceOptions.twist = a.twist;
    const YarnRadiusChoice radius = chooseYarnRadius(a.yarnRadius, xs, garment, a.input);
    if (!a.quiet && !radius.note.empty()) std::fprintf(stderr, "%s\n", radius.note.c_str());
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
    for (const std::string& w : checkRunScale(scale, xs))
        if (!a.quiet) std::fprintf(stderr, "warning: %s\n", w.c_str());
    // Disk and memory the run needs at least, before minutes of work.
    {
        const std::string outputDir = std::filesystem::path(a.output).parent_path().string();
        const bool store = !a.workDir.empty() || a.keepWorkDir || a.resume;
        const RunPlace place{outputDir, store ? (a.workDir.empty() ? outputDir : a.workDir) : "",
                             a.backend == "cpu" && a.method != "dense"};
        const std::string problem = checkNeeds(estimateNeeds(garment, radius.radius, voxelSize, a.precision == "half"),
                                               place, scale.voxelSource);
        if (!problem.empty()) throw Error(a.input + ": " + problem);
    }
    const bool explicitSpacing = a.slicesPerSegment > 0 || a.spacing > 0.0;
    sliceOptions.slicesPerSegment = a.slicesPerSegment;
    sliceOptions.spacing = explicitSpacing ? a.spacing : defaultSliceSpacing(voxelSize, a.supersample);
    const SlicePlan plan = [&] {
        try {
            return planSlices(garment, sliceOptions);
        } catch (const Error& e) {
            throw Error(a.input + ": " + e.what());
        }
    }();
    stages.set("slices", timer.lap());
    const VoxelGrid grid = makeGrid(plan, a.resolution, a.voxelSize);
    if (explicitSpacing && !a.quiet && plan.maxSpacing > 1.05 * grid.voxelSize)
        std::fprintf(stderr,
                     "warning: %s places slices up to %.3g voxels apart: each slab is split over the voxels it "
                     "spans and treated as flat across them, so bends are coarsened (leave it out for one slice "
                     "per voxel)\n",
                     a.slicesPerSegment > 0 ? ("--slices-per-segment " + std::to_string(a.slicesPerSegment)).c_str()
                                            : "--slice-spacing",
                     plan.maxSpacing / grid.voxelSize);
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

    VdbWriteTimings writeTimings;
    VdbWriteOptions writeOptions;
    writeOptions.compression = parseVdbCompression(a.compression);
    writeOptions.precision = parseVdbPrecision(a.precision);
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

    JsonObject backendStats;
    std::uint64_t samples = 0, active = 0, bricks = 0;
    double voxelizeSeconds = 0.0;
    ResolveTally tally;
    bool tallyComplete = true; // false when regions came from a resumed run
    if (a.method == "dense") {
        // The paper's method, kept as a benchmark baseline: one dense 3D texture set.
        if (a.backend != "gl") throw Error("--method dense needs --backend gl");
        if (!a.workDir.empty() || a.resume) throw Error("--work-dir and --resume need the sparse method");
        GlVoxelizeSettings gl;
        gl.base = settings;
        gl.device = a.device;
        DenseVoxelizeCounters counters;
        const BrickVolume volume = voxelizeDense(plan, xs, grid, gl, &counters);
        voxelizeSeconds = timer.lap();
        stages.set("voxelize", voxelizeSeconds);
        meta.backend = "gl-dense";
        active = volume.activeVoxelCount();
        refuseEmpty(active);
        writeVdb(a.output, volume, meta, writeOptions);
        stages.set("write", timer.lap());
        bricks = volume.bricks.size();
        tally = volume.tally;
        backendStats.set("renderer", counters.renderer)
            .set("platform", counters.platform)
            .set("method", "dense")
            .set("gpu_peak_bytes", counters.textureBytes)
            .set("slices_drawn", counters.instances)
            .set("gpu_clear_seconds", counters.clearSeconds)
            .set("gpu_raster_seconds", counters.rasterSeconds)
            .set("readback_seconds", counters.readbackSeconds);
    } else if (a.backend == "cpu") {
        if (!a.workDir.empty() || a.resume) throw Error("--work-dir and --resume need --backend gl");
        CpuVoxelizeCounters counters;
        const BrickVolume volume = voxelizeCpu(plan, xs, grid, settings, &counters);
        samples = counters.samples;
        backendStats.set("samples", counters.samples);
        voxelizeSeconds = timer.lap();
        stages.set("voxelize", voxelizeSeconds);
        active = volume.activeVoxelCount();
        refuseEmpty(active);
        writeVdb(a.output, volume, meta, writeOptions);
        stages.set("write", timer.lap());
        bricks = volume.bricks.size();
        tally = volume.tally;
    } else {
        GlVoxelizeSettings gl;
        gl.base = settings;
        gl.device = a.device;
        gl.fragmentCapacity = a.fragmentCapacity;
        gl.verbose = a.verbose;
        GlVoxelizeCounters counters;
        GlBackend backend(plan, xs, grid, gl, counters);
        const ZoomPlan zoom = planZoomRegions(plan, grid, xs, {backend.fragmentBudget(), backend.maxRegionSize(), a.supersample});
        counters.plannedRegions = zoom.regions.size();
        stages.set("plan", timer.lap());
        if (a.verbose && !a.quiet)
            std::fprintf(stderr, "plan: %zu zoom regions, %.3g fragments expected, budget %llu per pass\n",
                         zoom.regions.size(), zoom.estimatedFragments, static_cast<unsigned long long>(backend.fragmentBudget()));

        // Without a work dir, regions go straight into the .vdb's leaves.
        // With one, they stream through a bounded queue to it while the GPU
        // moves on, and the merge then builds one OpenVDB tree from the files.
        const bool ownWorkDir = a.workDir.empty();
        const bool inMemory = ownWorkDir && !a.keepWorkDir;
        const std::string workDir = ownWorkDir ? a.output + ".work" : a.workDir;
        StoreManifest manifest;
        manifest.fingerprint =
            runFingerprint(a.input, sliceOptions, xs, grid, settings.reduce, settings.overlap, a.supersample, zoom);
        manifest.samplingCode = samplingCodeHash();
        manifest.grid = grid;
        manifest.reduce = settings.reduce;
        manifest.runMetadata = encodeMetadata(meta);
        RegionWriterStats writerStats;
        std::uint64_t recomputed = 0, storeBytes = 0;
        // Unpacking the GPU's bricks and compressing them keep several cores busy.
        const unsigned workers = std::max(2u, std::thread::hardware_concurrency() / 2);
        if (inMemory) {
            VdbAssembler assembler(a.output, grid, settings.reduce, writeOptions);
            RegionWriter writer([&](std::uint64_t id, std::vector<VoxelBrick>&& resolved) {
                assembler.add(resolved, "region " + std::to_string(id));
            }, settings.reduce, settings.overlap, writerQueueBytes(), workers);
            QueueSink sink(writer);
            {
                const InterruptScope interruptible;
                backend.run(zoom.regions, sink);
            }
            for (const RegionInfo& r : writer.finish()) {
                active += r.activeVoxels;
                bricks += r.brickCount;
            }
            if (interruptSignal())
                throw Error("interrupted by " + interruptSignalName() + " after " + std::to_string(sink.consumed) +
                            " of " + std::to_string(zoom.regions.size()) + " regions: nothing was written (" +
                            a.output + " is untouched; a run with --work-dir DIR can be resumed)");
            writerStats = writer.stats();
            tally = writerStats.tally;
            voxelizeSeconds = timer.lap();
            stages.set("voxelize", voxelizeSeconds);
            refuseEmpty(active);
            assembler.write(meta);
            stages.set("write", timer.lap());
        } else {
            BrickStore store(workDir, manifest, a.resume);
            RegionWriter writer(store, settings.reduce, settings.overlap, writerQueueBytes(), workers);
            StoreSink sink(store, writer, a.resume);
            {
                const InterruptScope interruptible;
                backend.run(zoom.regions, sink);
            }
            writer.finish(); // every region handed over is on disk before the run stops
            if (interruptSignal()) {
                const std::string& line = commandLine();
                const bool resuming = line.find(" --resume") != std::string::npos;
                throw Error("interrupted by " + interruptSignalName() + " after " +
                            std::to_string(sink.consumed + counters.resumedRegions) + " of " +
                            std::to_string(zoom.regions.size()) + " regions, all of them kept in " + workDir +
                            "; go on with: " + line + (resuming ? "" : " --resume"));
            }
            writerStats = writer.stats();
            recomputed = sink.recomputed;
            store.markComplete(zoom.regions.size());
            voxelizeSeconds = timer.lap();
            stages.set("voxelize", voxelizeSeconds);
            for (const RegionInfo& r : store.listRegions()) {
                active += r.activeVoxels;
                bricks += r.brickCount;
            }
            refuseEmpty(active);
            mergeStoreToVdb(store, a.output, meta, writeOptions);
            stages.set("merge", timer.lap());
            storeBytes = store.bytesOnDisk();
            // Regions taken from a resumed run were not resolved here.
            tally = writerStats.tally;
            tallyComplete = counters.resumedRegions == 0;
        }

        samples = counters.fragments;
        backendStats.set("renderer", counters.renderer)
            .set("platform", counters.platform)
            .set("fragments", counters.fragments)
            .set("raster_passes", counters.passes)
            .set("overflow_retries", counters.overflows)
            .set("fragment_list_growths", counters.listGrowths)
            .set("bricks_summed_on_host", counters.hostSummedBricks)
            .set("zoom_regions", counters.plannedRegions)
            .set("regions_computed", counters.regions)
            .set("regions_resumed", counters.resumedRegions)
            .set("regions_damaged_recomputed", recomputed)
            .set("fragment_budget", counters.fragmentCapacity)
            .set("gpu_slice_data_bytes", counters.sliceDataBytes)
            .set("gpu_peak_bytes", counters.peakGpuBytes)
            .set("gpu_raster_seconds", counters.rasterSeconds)
            .set("gpu_brick_seconds", counters.brickSeconds)
            .set("gpu_resolve_seconds", counters.resolveSeconds)
            .set("readback_seconds", counters.readbackSeconds)
            .set("readback_bytes", counters.readbackBytes)
            .set("store_bytes_on_disk", storeBytes)
            .set("store_resolve_seconds", writerStats.resolveSeconds)
            .set("store_encode_seconds", writerStats.encodeSeconds)
            .set("store_write_seconds", writerStats.writeSeconds)
            .set("store_wait_seconds", writerStats.submitWaitSeconds)
            .set("store_peak_queued_bytes", writerStats.peakQueuedBytes)
            .set("regions_to", inMemory ? "memory" : "work dir");
        if (a.verbose && !a.quiet)
            std::fprintf(stderr, "renderer: %s (%s); %llu regions (%llu resumed), %llu overflow retries\n",
                         counters.renderer.c_str(), counters.platform.c_str(),
                         static_cast<unsigned long long>(counters.plannedRegions),
                         static_cast<unsigned long long>(counters.resumedRegions),
                         static_cast<unsigned long long>(counters.overflows));
    }

    const double h3 = grid.voxelSize * grid.voxelSize * grid.voxelSize;
    if (!a.statsPath.empty()) {
        JsonObject stats;
        stats.set("yarnvox_version", YV_VERSION)
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
            .set("active_voxels", active)
            .set("bricks", bricks)
            .set("slice_spacing", plan.maxSpacing)
            .set("overlap", toString(settings.overlap))
            .set("fiber_volume", tallyComplete ? tally.densitySum * h3 : -1.0)
            .set("voxels_over_one", tallyComplete ? static_cast<std::int64_t>(tally.voxelsOverOne) : std::int64_t(-1))
            .set("mass_share_over_one", tallyComplete ? tally.excessShare() : -1.0)
            .set("slices_per_second", plan.sliceCount / voxelizeSeconds)
            .set("active_voxels_per_second", active / voxelizeSeconds)
            .set("peak_host_bytes", peakResidentBytes())
            .set("vdb_compression", toString(writeOptions.compression))
            .set("vdb_precision", toString(writeOptions.precision))
            .set("vdb_seconds", JsonObject()
                                    .set("read_regions", writeTimings.readSeconds)
                                    .set("encode_leaves", writeTimings.encodeSeconds)
                                    .set("topology", writeTimings.topologySeconds)
                                    .set("write", writeTimings.writeSeconds))
            .set("seconds", stages)
            .set("backend_stats", backendStats);
        writeTextFileAtomically(a.statsPath, stats.dump() + "\n");
    }
    if (!a.quiet)
        std::printf("%s: %llu slices -> %llu active voxels in %zu bricks (grid %dx%dx%d, voxel %.4g), %.2f s voxelize\n"
                    "wrote %s\n",
                    a.input.c_str(), static_cast<unsigned long long>(plan.sliceCount),
                    static_cast<unsigned long long>(active), static_cast<std::size_t>(bricks), grid.dims.x, grid.dims.y,
                    grid.dims.z, grid.voxelSize, voxelizeSeconds, a.output.c_str());
    // Interpenetrating yarns: say how much fibre the overlap rule met, when more than a trace.
    if (!a.quiet && tallyComplete && settings.reduce == Reduce::Mean && tally.excessShare() > 1e-3)
        std::printf("overlap: %llu voxels held more than their volume of fibre (%.2f %% of the fibre volume above 1); %s\n",
                    static_cast<unsigned long long>(tally.voxelsOverOne), 100.0 * tally.excessShare(),
                    settings.overlap == Overlap::Clamp ? "clamped to 1 (--overlap sum keeps the sums)"
                                                       : "kept as sums (--overlap sum)");
}

} // namespace

void addVoxelizeCommand(CLI::App& app) {
    auto a = std::make_shared<VoxelizeArgs>();
    CLI::App* cmd = app.add_subcommand("voxelize", "Voxelize a garment (BCC) into an OpenVDB file of fibre density and orientation");
    cmd->add_option("input", a->input, "Garment .bcc file")->required()->check(CLI::ExistingFile);
    cmd->add_option("-o,--output", a->output, "Output file: OUT.vdb, OUT.vol or OUT.nvdb (see --format)")->required();
    cmd->add_option("--format", a->format,
                    "vdb, vol (Mitsuba: OUT.vol density, OUT.orientation.vol axes, float32) or nvdb (NanoVDB); default "
                    "from the output's extension, else vdb. vol and nvdb are converted from a temporary .vdb "
                    "(`yarnvox export` converts one you have, with more choices)")
        ->check(CLI::IsMember({"vdb", "vol", "nvdb"}));
    cmd->add_option("--backend", a->backend,
                    "auto (gl on a GPU, else cpu; gl for --work-dir, --resume and --method dense), gl (OpenGL 4.5 "
                    "through EGL: a GPU, or Mesa's llvmpipe) or cpu (the TBB reference)")
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "gl", "cpu"}));
    cmd->add_option("--method", a->method,
                    "sparse: fragment list, bricks, zoom regions; dense: the paper's dense 3D textures "
                    "(a benchmark baseline, limited to one texture, max reduction)")
        ->capture_default_str()
        ->check(CLI::IsMember({"sparse", "dense"}));
    auto* res = cmd->add_option("--resolution", a->resolution, "Voxels on the longest axis of the padded garment box")
                    ->check(CLI::Range(8, 1 << 20));
    cmd->add_option("--voxel-size", a->voxelSize, "Voxel edge length, world units (instead of --resolution)")
        ->check(worldLength())
        ->excludes(res);
    cmd->add_option("--yarn-radius", a->yarnRadius, "Yarn radius, world units (default: from the cross-section PNG or the garment file, else "
                    "estimated from the distances between touching yarns)")
        ->check(worldLength());
    auto* perSegment =
        cmd->add_option("--slices-per-segment", a->slicesPerSegment,
                        "Slices per curve segment (the paper uses 25 and 50; default: one slice per voxel along the yarn)")
            ->check(CLI::Range(1, 100000));
    cmd->add_option("--slice-spacing", a->spacing,
                    "Distance between slices, world units (default: the voxel size over --supersample)")
        ->check(worldLength())
        ->excludes(perSegment);
    cmd->add_option("--twist", a->twist, "Yarn twist, radians per world unit of yarn length")
        ->capture_default_str()
        ->check(finiteNumber(kMaxTwist));
    cmd->add_option("--cross-section", a->crossSection, "Fibre density on each slice: fibers, disk, or FILE.png (alpha = density)")
        ->capture_default_str();
    cmd->add_option("--reduce", a->reduce, "mean: fibre volume fraction and mean axis; max: the paper's max density")
        ->capture_default_str()
        ->check(CLI::IsMember({"mean", "max"}));
    cmd->add_option("--overlap", a->overlap,
                    "Where yarns interpenetrate (mean): clamp keeps every voxel's fibre fraction at or below 1; "
                    "sum adds them up")
        ->capture_default_str()
        ->check(CLI::IsMember({"clamp", "sum"}));
    cmd->add_option("--vdb-compression", a->compression,
                    "How the .vdb's leaves are compressed: mask (active values only, no codec: the fastest), "
                    "blosc (OpenVDB's default: smaller, slower), zip (the orientation grid only) or none")
        ->capture_default_str()
        ->check(CLI::IsMember({"blosc", "zip", "mask", "none"}));
    cmd->add_option("--precision", a->precision,
                    "How the .vdb's values are stored: float, or half (16-bit: about half the bytes; density "
                    "within 2^-11 relative)")
        ->capture_default_str()
        ->check(CLI::IsMember({"float", "half"}));
    cmd->add_option("--supersample", a->supersample, "Samples per voxel face along each axis")
        ->capture_default_str()
        ->check(CLI::Range(1, 16));
    cmd->add_option("--device", a->device, "GL backend: EGL device index (default: first GPU, else llvmpipe)")
        ->check(CLI::Range(0, 1023));
    // The GL append counter is 32 bits, and a pass that reaches 2^31 counts as overflowed.
    cmd->add_option("--fragment-budget", a->fragmentCapacity,
                    "GL backend: fragments one pass may append (default: from GPU limits and free memory); "
                    "zoom regions are sized to it")
        ->check(CLI::Range(std::uint64_t(1), std::uint64_t(0x7fffffffu)));
    cmd->add_option("--work-dir", a->workDir,
                    "GL backend: directory for the per-region brick files (default: OUT.vdb.work, removed after the merge)");
    cmd->add_flag("--resume", a->resume, "Re-use the complete, verified regions in --work-dir and compute the rest");
    cmd->add_flag("--keep-work-dir", a->keepWorkDir, "Keep the default work directory after the merge");
    cmd->add_option("--stats", a->statsPath, "Write run statistics (JSON) to this file");
    cmd->add_flag("-q,--quiet", a->quiet, "No progress and no summary");
    cmd->add_flag("-v,--verbose", a->verbose, "Name the renderer and print GPU limits");
    cmd->callback([a] {
        voxelizeInFormat(a->format, a->output, a->input, a->quiet, [&](const std::string& vdbPath) {
            VoxelizeArgs run = *a;
            run.output = vdbPath;
            runVoxelize(run);
        });
    });
}

} // namespace yv
