#include "pipeline/voxelize_run.h"

#include "core/error.h"
#include "core/interrupt.h"
#include "core/trace.h"
#include "core/world_units.h"
#include "pipeline/backend_choice.h"
#include "pipeline/cluster.h"
#include "pipeline/dense_run.h"
#include "pipeline/rasterizers.h"
#include "pipeline/region_destination.h"
#include "pipeline/run_fingerprint.h"
#include "pipeline/run_stats.h"
#include "pipeline/sliced_garment.h"
#include "pipeline/voxelize_box.h"
#include "plan/grid.h"
#include "vdb/lod_request.h"
#include "vdb/spill_file.h"

#include <algorithm>
#include <cstdio>
#include <future>
#include <thread>

namespace yv {
namespace {

/// Three significant digits, for messages.
std::string shortNumber(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", v);
    return text;
}

/// Slices asked to lie further apart than a voxel coarsen the bends: said once.
void warnCoarseSpacing(const VoxelizeJob& job, const SlicedGarment& sliced, const VoxelGrid& grid, const Tell& tell) {
    if (!sliced.explicitSpacing || sliced.plan().maxSpacing <= 1.05 * grid.voxelSize) return;
    tell("warning: " +
         (job.slicesPerSegment > 0 ? "--slices-per-segment " + std::to_string(job.slicesPerSegment)
                                   : std::string("--slice-spacing")) +
         " places slices up to " + shortNumber(sliced.plan().maxSpacing / grid.voxelSize) +
         " voxels apart: each slab is split over the voxels it spans and treated as flat across them, so "
         "bends are coarsened (leave it out for one slice per voxel)");
}

/// What the .vdb records of the run (formats/vdb-subset.md).
VolumeMetadata describeRun(const VoxelizeJob& job, Backend backend, const SlicedGarment& sliced,
                           const std::optional<RunBox>& box) {
    VolumeMetadata meta;
    meta.input = job.input;
    meta.backend = backendName(backend);
    meta.crossSection = sliced.xs.name;
    meta.resolution = job.resolution;
    meta.sliceCount = sliced.plan().sliceCount;
    meta.yarnRadius = sliced.sliceOptions.radius;
    meta.yarnRadiusSource = sliced.radius.source;
    meta.twist = job.twist;
    meta.supersample = job.supersample;
    meta.overlap = toString(job.overlap);
    meta.sliceSpacing = sliced.plan().maxSpacing;
    meta.slicesPerSegment = job.slicesPerSegment;
    meta.sliceSpacingOption = job.spacing;
    meta.albedo = sliced.xs.hasAlbedo();
    if (box) meta.bbox = box->placed.text();
    return meta;
}

VdbWriteOptions writeOptionsFor(const VoxelizeJob& job, const VoxelGrid& grid, const SlicedGarment& sliced,
                                int processesHere, VdbWriteTimings& timings) {
    VdbWriteOptions options;
    options.compression = job.compression;
    options.precision = job.precision;
    // Refused here, before any work, when --lod N asks for more levels than the grid has.
    const LodLevels lod = lodLevelsFor(lodOf(job), grid);
    options.lodFirstLevel = lod.first;
    options.lodLevels = lod.last;
    options.albedo = sliced.xs.hasAlbedo();
    options.timings = &timings;
    options.streamLeaves = streamLeavesFromEnvironment();
    options.scratchMemoryBytes = spillMemoryBytes() / std::uint64_t(std::max(processesHere, 1));
    return options;
}

/// The checks before slicing refuse what cannot leave a voxel; a yarn that
/// falls between sample pixels can still miss them all. An empty volume is
/// never a result: the run fails before anything is written.
RefuseEmpty refuseEmptyFor(const VoxelizeJob& job, const SlicedGarment& sliced, const VoxelGrid& grid) {
    return [&job, &sliced, voxelSize = grid.voxelSize](std::uint64_t activeVoxels) {
        if (activeVoxels == 0)
            throw Error(job.input + ": no yarn reached a voxel's samples" + (job.box ? " in " + job.box->named() : "") +
                        " (" + sliced.radius.description + ", voxel size " + numberText(voxelSize) +
                        "): the volume would be empty, " + (job.output.empty() ? "nothing was kept" : job.output + " was not written") +
                        " (a finer --resolution, a higher --supersample, or --cross-section disk)");
    };
}

/// Every rank writes regions of the same run: rank 0's choice holds (a rank
/// whose own choice differs makes the context it now needs).
Backend agreeOnBackend(Backend mine, Cluster* group, const VoxelizeJob& job, GlStart& gl) {
    if (!group) return mine;
    const Backend agreed = group->broadcast(mine == Backend::Gl) ? Backend::Gl : Backend::Cpu;
    if (agreed == Backend::Gl && !gl.current()) {
        VoxelizeJob onGl = job;
        onGl.backend = BackendRequest::Gl;
        gl = startGl(onGl, group->localRank());
        if (gl.error) std::rethrow_exception(gl.error);
    }
    return agreed;
}

/// The work dir's identity: a fingerprint of everything that decides the
/// bricks (it reads the whole garment file, so only a work dir computes it).
StoreManifest workDirManifest(const VoxelizeJob& job, Backend backend, const SlicedGarment& sliced,
                              const VoxelGrid& grid, const VoxelizeSettings& settings, const ZoomPlan& zoom,
                              const VolumeMetadata& meta) {
    StoreManifest manifest;
    manifest.fingerprint = runFingerprint(job.input, sliced.sliceOptions, sliced.xs, grid, job.reduce, job.overlap,
                                          job.supersample, zoom, backendName(backend), settings.clip);
    manifest.samplingCode = samplingCodeHash();
    manifest.grid = grid;
    manifest.reduce = job.reduce;
    manifest.run = meta;
    return manifest;
}

/// In memory when nothing asks for a work dir; else the job's work dir,
/// shared by the ranks of an MPI run.
std::unique_ptr<RegionDestination> makeDestination(DestinationSetup& setup, Cluster* group, Backend backend,
                                                   const SlicedGarment& sliced, const ZoomPlan& zoom,
                                                   const VolumeMetadata& meta) {
    const VoxelizeJob& job = setup.job;
    if (!group && job.workDir.empty() && !job.keepWorkDir) return makeMemoryDestination(setup);
    setup.manifest = workDirManifest(job, backend, sliced, setup.grid, setup.settings, zoom, meta);
    return group ? makeClusterDestination(setup, *group) : makeWorkDirDestination(setup);
}

/// What the sparse method's stages leave for the report.
struct SparseRun {
    std::optional<RunTotals> totals; ///< none on an MPI rank other than 0
    std::uint64_t samples = 0;
    double voxelizeSeconds = 0.0;
    JsonObject backendStats;
};

/// The zoom regions rasterized one after another into the destination, which
/// writes the .vdb. Returns once the rasterizer and the destination's threads
/// are gone.
SparseRun runSparse(const VoxelizeJob& job, Backend backend, const SlicedGarment& sliced, const VoxelGrid& grid,
                    const VoxelizeSettings& settings, GlStart&& gl, Cluster* group, VolumeMetadata& meta,
                    const VdbWriteOptions& writeOptions, StageTimer& timer, const Tell& note, const Tell& tell) {
    std::unique_ptr<RegionRasterizer> rasterizer = makeRasterizer(backend, sliced, grid, settings, job, std::move(gl));
    double zoomPlanSeconds = 0.0;
    const ZoomPlan zoom = planZoomWhilePreparing(*rasterizer, sliced, grid, job.supersample, settings.clip, group,
                                                 job.cancel.get(), zoomPlanSeconds);
    timer.lap("plan");
    throwIfCancelled(job, zoom.givenUp ? "while planning its regions" : "before its regions");
    YV_CHECK(!zoom.givenUp); // only a run given up stops its planning
    if (job.verbose)
        tell("plan: " + std::to_string(zoom.regions.size()) + " zoom regions, " + numberText(zoom.estimatedFragments) +
             " fragments expected, budget " + std::to_string(rasterizer->fragmentBudget()) + " per pass");

    DestinationSetup setup{job, zoom.regions, note, grid, settings, writeOptions, {},
                           writerThreads(backend == Backend::Cpu, group ? group->localSize() : 1)};
    const std::unique_ptr<RegionDestination> destination = makeDestination(setup, group, backend, sliced, zoom, meta);
    {
        const InterruptScope interruptible;
        rasterizer->run(destination->regionOrder(), destination->sink());
    }
    if (job.verbose) tell(rasterizer->describe());
    SparseRun run;
    run.backendStats = rasterizer->stats();
    run.samples = rasterizer->samples();
    StageSeconds stages = rasterizer->voxelizeParts();
    // A context made for the run goes with the backend on a thread of its own
    // while the output is written; a kept one stays current here for the next.
    std::jthread freeing;
    if (job.glContext) rasterizer.reset();
    else freeing = freeInBackground(std::move(rasterizer));
    run.totals = destination->collect();
    throwIfCancelled(job, "after " + std::to_string(run.totals ? run.totals->regionsRasterized : 0) + " of " +
                              std::to_string(zoom.regions.size()) + " regions");
    if (!run.totals) return run;
    run.voxelizeSeconds = timer.lap("voxelize");
    // The stages so far, and the parts of the voxelize stage that the
    // rasterizer and the writer threads timed, for the work dir's manifest.
    const RegionWriterStats& w = run.totals->writer;
    stages.insert(stages.begin(), timer.laps().begin(), timer.laps().end());
    stages.insert(stages.end(), {{"voxelize.store_resolve", w.resolveSeconds},
                                 {"voxelize.store_encode", w.encodeSeconds},
                                 {"voxelize.store_write", w.writeSeconds},
                                 {"voxelize.store_wait", w.submitWaitSeconds}});
    destination->writeVdb(meta, *run.totals, stages, timer, refuseEmptyFor(job, sliced, grid));
    addDestinationStats(run.backendStats, *run.totals, zoom.regions.size(), zoomPlanSeconds, destination->kind(),
                        group ? group->size() : 1);
    return run;
}

VoxelizeReport reportOf(const VoxelizeJob& job, Backend backend, const SlicedGarment& sliced, const VoxelGrid& grid,
                        const RunTotals& totals, double voxelizeSeconds) {
    VoxelizeReport report;
    report.backend = backendName(backend);
    report.slices = sliced.plan().sliceCount;
    report.activeVoxels = totals.activeVoxels;
    report.bricks = totals.bricks;
    report.dims = grid.dims;
    report.origin = grid.origin;
    report.voxelSize = grid.voxelSize;
    report.voxelizeSeconds = voxelizeSeconds;
    report.reduce = job.reduce;
    report.overlap = job.overlap;
    report.tally = totals.writer.tally;
    report.tallyComplete = totals.tallyComplete();
    return report;
}

} // namespace

VoxelizeReport runVoxelize(const VoxelizeJob& job, const Tell& note) {
    // Several processes under mpirun share the regions of one run; one (or
    // mpirun -np 1) runs as a plain process.
    Cluster* const group = !job.alone && cluster() && cluster()->size() > 1 ? cluster() : nullptr;
    checkJob(job, group != nullptr);
    // Under mpirun rank 0 speaks for the run: the others see the same things.
    const Tell tell = [&](const std::string& line) {
        if (!job.quiet && (!group || group->rank() == 0)) note(line);
    };
    // The garment is read and sliced on a thread of its own while this thread
    // makes the GL context: the driver's start-up overlaps the slicing, and
    // the context is current where the GL backend runs (binding a context
    // made on another thread took about 0.03 s on the H100).
    StageTimer timer;
    std::future<SlicedGarment> pendingSlices = std::async(std::launch::async, [&] {
        return sliceGarment(job, job.throughWorkDir(group != nullptr), tell, timer);
    });
    GlStart gl = startGl(job, cluster() ? cluster()->localRank() : 0);
    const SlicedGarment sliced = pendingSlices.get();
    throwIfCancelled(job, "after slicing the garment");
    const Backend chosen = chooseBackend(job, gl);
    if (job.backend == BackendRequest::Auto && chosen == Backend::Cpu && job.verbose && !job.quiet)
        note("backend: no GPU found, using the CPU backend (--backend gl forces the software GL path)");
    if (chosen == Backend::Cpu && job.sampleItems != SampleItemsRequest::Auto)
        tell(std::string("warning: --sample-items ") + toString(job.sampleItems) +
             ": the CPU backend runs here (no GPU found), which has no sample items to find; "
             "--backend gl runs the GL backend on the software GL path");
    const Backend backend = agreeOnBackend(chosen, group, job, gl);

    const VoxelGrid grid = makeGrid(sliced.plan(), job.resolution, job.voxelSize);
    // --bbox: the box selects voxels of that grid (refused here, before anything is written, when it misses).
    const std::optional<RunBox> box = placeRunBox(job, sliced, grid, tell);
    warnCoarseSpacing(job, sliced, grid, tell);
    VoxelizeSettings settings{job.reduce, job.supersample, job.quiet, job.overlap, {}};
    if (box) settings.clip = box->placed.box;
    VolumeMetadata meta = describeRun(job, backend, sliced, box);
    VdbWriteTimings writeTimings;
    const VdbWriteOptions writeOptions =
        writeOptionsFor(job, grid, sliced, group ? group->localSize() : 1, writeTimings);
    if (!job.bricksOnly()) // nothing goes to disk otherwise
        checkOutputFits(job, job.throughWorkDir(group != nullptr), sliced, grid,
                        {job.precision == VdbPrecision::Half, writeOptions.albedo, writeOptions.lodLevels,
                         writeOptions.lodFirstLevel},
                        box ? std::optional<double>(box->yarnLength) : std::nullopt);

    RunTotals totals;
    double voxelizeSeconds = 0.0;
    std::uint64_t samples = 0;
    JsonObject backendStats;
    if (backend == Backend::GlDense) {
        DenseRun dense = runDense(sliced, grid, settings, job, std::move(gl), meta, writeOptions, timer,
                                  refuseEmptyFor(job, sliced, grid));
        totals = dense.totals;
        voxelizeSeconds = dense.voxelizeSeconds;
        backendStats = dense.backendStats;
    } else {
        SparseRun sparse = runSparse(job, backend, sliced, grid, settings, std::move(gl), group, meta, writeOptions,
                                     timer, note, tell);
        if (!sparse.totals) {
            VoxelizeReport rankOnly;
            rankOnly.rankOnly = true;
            return rankOnly;
        }
        totals = *sparse.totals;
        voxelizeSeconds = sparse.voxelizeSeconds;
        samples = sparse.samples;
        backendStats = sparse.backendStats;
    }
    // Releasing the GPU's buffers and context, the writer's threads and the
    // scratch file, once the output is in place.
    timer.lap("finish");
    VoxelizeReport report = reportOf(job, backend, sliced, grid, totals, voxelizeSeconds);
    report.stats = runStats({job, backend, sliced, grid, totals, samples, voxelizeSeconds, writeTimings,
                             timer, backendStats, box ? std::optional<JsonObject>(boxStats(job, *box, grid)) : std::nullopt});
    if (!job.statsPath.empty()) {
        const TraceSpan span("write the stats");
        writeTextFileAtomically(job.statsPath, report.stats.dump() + "\n");
    }
    return report;
}

} // namespace yv
