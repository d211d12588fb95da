// `yarnvox voxelize`: garment -> slices -> voxels -> .vdb, with --stats.
#include "bcc.h"
#include "cli/commands.h"
#include "core/error.h"
#include "core/process_memory.h"
#include "core/stats.h"
#include "cpu/cpu_voxelizer.h"
#include "garment/cross_section.h"
#include "garment/slices.h"
#include "gpu/gl_voxelizer.h"
#include "plan/grid.h"
#include "vdb/vdb_writer.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <memory>

namespace yv {
namespace {

struct VoxelizeArgs {
    std::string input, output, backend = "gl", crossSection = "fibers", reduce = "mean", statsPath;
    int resolution = 0, slicesPerSegment = 25, supersample = 1, device = -1;
    double voxelSize = 0.0, yarnRadius = 0.0, spacing = 0.0, twist = 0.0;
    std::uint64_t fragmentCapacity = 0;
    bool quiet = false, verbose = false;
};

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

void runVoxelize(const VoxelizeArgs& a) {
    StageTimer timer;
    JsonObject stages;
    const Garment garment = readBcc(a.input);
    stages.set("read", timer.lap());

    CrossSection xs = makeCrossSection(a.crossSection);
    SliceOptions sliceOptions;
    sliceOptions.slicesPerSegment = a.slicesPerSegment;
    sliceOptions.spacing = a.spacing;
    sliceOptions.twist = a.twist;
    sliceOptions.radius = a.yarnRadius > 0 ? a.yarnRadius : (xs.radius > 0 ? xs.radius : garment.yarnRadius);
    if (!(sliceOptions.radius > 0))
        throw Error(a.input + ": the file gives no yarn radius: pass --yarn-radius R (world units)");
    const SlicePlan plan = planSlices(garment, sliceOptions);
    stages.set("slices", timer.lap());

    if (a.resolution == 0 && a.voxelSize == 0.0)
        throw Error("give --resolution N (voxels on the longest axis) or --voxel-size H");
    const VoxelGrid grid = makeGrid(plan, a.resolution, a.voxelSize);
    VoxelizeSettings settings;
    settings.reduce = a.reduce == "max" ? Reduce::Max : Reduce::Mean;
    settings.supersample = a.supersample;
    settings.quiet = a.quiet;

    JsonObject backendStats;
    BrickVolume volume;
    std::uint64_t samples = 0;
    if (a.backend == "cpu") {
        CpuVoxelizeCounters counters;
        volume = voxelizeCpu(plan, xs, grid, settings, &counters);
        samples = counters.samples;
        backendStats.set("samples", counters.samples);
    } else {
        GlVoxelizeSettings gl;
        gl.base = settings;
        gl.device = a.device;
        gl.fragmentCapacity = a.fragmentCapacity;
        gl.verbose = a.verbose;
        GlVoxelizeCounters counters;
        volume = voxelizeGl(plan, xs, grid, gl, &counters);
        samples = counters.fragments;
        backendStats.set("renderer", counters.renderer)
            .set("platform", counters.platform)
            .set("fragments", counters.fragments)
            .set("raster_passes", counters.passes)
            .set("overflow_retries", counters.overflows)
            .set("fragment_capacity", counters.fragmentCapacity)
            .set("gpu_slice_data_bytes", counters.sliceDataBytes)
            .set("gpu_peak_bytes", counters.peakGpuBytes)
            .set("gpu_raster_seconds", counters.rasterSeconds)
            .set("gpu_brick_seconds", counters.brickSeconds)
            .set("readback_seconds", counters.readbackSeconds);
        if (a.verbose && !a.quiet) std::fprintf(stderr, "renderer: %s (%s)\n", counters.renderer.c_str(), counters.platform.c_str());
    }
    const double voxelizeSeconds = timer.lap();
    stages.set("voxelize", voxelizeSeconds);

    VolumeMetadata meta;
    meta.input = a.input;
    meta.backend = a.backend;
    meta.crossSection = xs.name;
    meta.resolution = a.resolution;
    meta.sliceCount = plan.sliceCount;
    meta.yarnRadius = sliceOptions.radius;
    meta.twist = a.twist;
    meta.supersample = a.supersample;
    writeVdb(a.output, volume, meta);
    stages.set("write", timer.lap());

    const std::uint64_t active = volume.activeVoxelCount();
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
            .set("bricks", static_cast<std::uint64_t>(volume.bricks.size()))
            .set("fiber_volume", volume.totalMass())
            .set("slices_per_second", plan.sliceCount / voxelizeSeconds)
            .set("active_voxels_per_second", active / voxelizeSeconds)
            .set("peak_host_bytes", peakResidentBytes())
            .set("seconds", stages)
            .set("backend_stats", backendStats);
        writeTextFileAtomically(a.statsPath, stats.dump() + "\n");
    }
    if (!a.quiet)
        std::printf("%s: %llu slices -> %llu active voxels in %zu bricks (grid %dx%dx%d, voxel %.4g), %.2f s voxelize\n"
                    "wrote %s\n",
                    a.input.c_str(), static_cast<unsigned long long>(plan.sliceCount),
                    static_cast<unsigned long long>(active), volume.bricks.size(), grid.dims.x, grid.dims.y,
                    grid.dims.z, grid.voxelSize, voxelizeSeconds, a.output.c_str());
}

} // namespace

void addVoxelizeCommand(CLI::App& app) {
    auto a = std::make_shared<VoxelizeArgs>();
    CLI::App* cmd = app.add_subcommand("voxelize", "Voxelize a garment (BCC) into an OpenVDB file of fibre density and orientation");
    cmd->add_option("input", a->input, "Garment .bcc file")->required()->check(CLI::ExistingFile);
    cmd->add_option("-o,--output", a->output, "Output .vdb file")->required();
    cmd->add_option("--backend", a->backend, "gl (OpenGL 4.5 through EGL: GPU, or llvmpipe) or cpu (TBB reference)")
        ->capture_default_str()
        ->check(CLI::IsMember({"gl", "cpu"}));
    auto* res = cmd->add_option("--resolution", a->resolution, "Voxels on the longest axis of the padded garment box")
                    ->check(CLI::Range(8, 1 << 20));
    cmd->add_option("--voxel-size", a->voxelSize, "Voxel edge length, world units (instead of --resolution)")
        ->check(CLI::PositiveNumber)
        ->excludes(res);
    cmd->add_option("--yarn-radius", a->yarnRadius, "Yarn radius, world units (default: from the cross-section PNG or the garment file)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--slices-per-segment", a->slicesPerSegment, "Slices per curve segment (the paper uses 25 and 50)")
        ->capture_default_str()
        ->check(CLI::Range(1, 100000));
    cmd->add_option("--slice-spacing", a->spacing, "Distance between slices, world units (instead of --slices-per-segment)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--twist", a->twist, "Yarn twist, radians per world unit of yarn length")->capture_default_str();
    cmd->add_option("--cross-section", a->crossSection, "Fibre density on each slice: fibers, disk, or FILE.png (alpha = density)")
        ->capture_default_str();
    cmd->add_option("--reduce", a->reduce, "mean: fibre volume fraction and mean axis; max: the paper's max density")
        ->capture_default_str()
        ->check(CLI::IsMember({"mean", "max"}));
    cmd->add_option("--supersample", a->supersample, "Samples per voxel face along each axis")
        ->capture_default_str()
        ->check(CLI::Range(1, 16));
    cmd->add_option("--device", a->device, "GL backend: EGL device index (default: first GPU, else llvmpipe)");
    cmd->add_option("--fragment-capacity", a->fragmentCapacity,
                    "GL backend: fragment-list capacity in fragments (default: from GPU limits)");
    cmd->add_option("--stats", a->statsPath, "Write run statistics (JSON) to this file");
    cmd->add_flag("-q,--quiet", a->quiet, "No progress and no summary");
    cmd->add_flag("-v,--verbose", a->verbose, "Name the renderer and print GPU limits");
    cmd->callback([a] { runVoxelize(*a); });
}

} // namespace yv
