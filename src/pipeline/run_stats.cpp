#include "pipeline/run_stats.h"

#include "core/process_memory.h"

#include <string>

namespace yv {

void addDestinationStats(JsonObject& backendStats, const RunTotals& totals, std::size_t plannedRegions,
                         double zoomPlanSeconds, const char* regionsTo, int ranks) {
    const RegionWriterStats& w = totals.writer;
    backendStats.set("zoom_regions", static_cast<std::uint64_t>(plannedRegions))
        .set("regions_computed", totals.regionsRasterized)
        .set("regions_resumed", totals.regionsResumed)
        .set("zoom_plan_seconds", zoomPlanSeconds)
        .set("regions_missing_recomputed", totals.regionsMissing)
        .set("regions_damaged_recomputed", totals.regionsDamaged)
        .set("store_bytes_on_disk", totals.storeBytes)
        .set("store_resolve_seconds", w.resolveSeconds)
        .set("store_encode_seconds", w.encodeSeconds)
        .set("store_write_seconds", w.writeSeconds)
        .set("store_wait_seconds", w.submitWaitSeconds)
        .set("store_peak_queued_bytes", w.peakQueuedBytes)
        .set("regions_to", regionsTo)
        .set("ranks", static_cast<std::uint64_t>(ranks));
}

JsonObject runStats(const RunRecord& run) {
    const VoxelGrid& grid = run.grid;
    const SlicePlan& plan = run.sliced.plan();
    const double h3 = grid.voxelSize * grid.voxelSize * grid.voxelSize;
    const ResolveTally& tally = run.totals.writer.tally;
    // Regions taken from a resumed run were not resolved here: no totals over them.
    const bool complete = run.totals.tallyComplete();
    const VdbWriteTimings& t = run.writeTimings;
    JsonObject stats;
    stats.set("yarnvox_version", YV_VERSION)
        .set("input", run.job.input)
        .set("output", run.job.output)
        .set("backend", backendName(run.backend))
        .set("reduce", toString(run.job.reduce))
        .set("yarns", static_cast<std::uint64_t>(run.sliced.garment().yarns.size()))
        .set("segments", static_cast<std::uint64_t>(plan.segments.size()))
        .set("slices", plan.sliceCount)
        .set("samples", run.samples)
        .set("voxel_size", grid.voxelSize)
        .set("grid_dims", std::to_string(grid.dims.x) + "x" + std::to_string(grid.dims.y) + "x" +
                              std::to_string(grid.dims.z));
    if (run.box) stats.set("bbox", *run.box);
    stats.set("active_voxels", run.totals.activeVoxels)
        .set("bricks", run.totals.bricks)
        .set("slice_spacing", plan.maxSpacing)
        .set("overlap", toString(run.job.overlap))
        .set("fiber_volume", complete ? tally.densitySum * h3 : -1.0)
        .set("voxels_over_one", complete ? static_cast<std::int64_t>(tally.voxelsOverOne) : std::int64_t(-1))
        .set("mass_share_over_one", complete ? tally.excessShare() : -1.0)
        .set("slices_per_second", plan.sliceCount / run.voxelizeSeconds)
        .set("active_voxels_per_second", run.totals.activeVoxels / run.voxelizeSeconds)
        .set("peak_host_bytes", peakResidentBytes())
        .set("vdb_compression", toString(run.job.compression))
        .set("vdb_precision", toString(run.job.precision))
        .set("vdb_seconds", JsonObject()
                                .set("read_regions", t.readSeconds)
                                .set("encode_leaves", t.encodeSeconds)
                                .set("topology", t.topologySeconds)
                                .set("write", t.writeSeconds)
                                .set("stream", t.streamSeconds))
        .set("vdb_streamed_bytes", t.streamedBytes)
        .set("vdb_streamed_before_end_bytes", t.streamedBeforeEndBytes)
        .set("seconds", run.timer.json())
        .set("backend_stats", run.backendStats);
    return stats;
}

} // namespace yv
