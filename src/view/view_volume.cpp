#include "view/view_volume.h"

#include "core/error.h"
#include "inspect/run_slices.h"
#include "pipeline/voxelize_run.h"

#include <atomic>
#include <bit>
#include <cstdio>
#include <cstdlib>
#include <system_error>

namespace yv {
namespace {

namespace fs = std::filesystem;

std::string secondsText(double s) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f", s);
    return text;
}

bool isGarment(const std::string& path) { return fs::path(path).extension() == ".bcc"; }

/// A directory of this process's own under the system's temporary directory.
fs::path makeScratch() {
    std::string pattern = (fs::temp_directory_path() / "yarnvox-view-XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw Error("cannot make a scratch directory under " + fs::temp_directory_path().string());
    return pattern;
}

/// Active voxels, counted on every core (the mask where the source has one, else density above 0).
std::uint64_t countActiveVoxels(const VolumeSource& source) {
    std::atomic<std::uint64_t> total{0};
    const VoxelBox bounds = source.bounds();
    // bounds() is brick-aligned: its bricks are exactly [min / 8, max / 8).
    source.forEachBrickConcurrently(bounds.min / 8, bounds.max / 8, [&](const SourceBrick& brick) {
        std::uint64_t n = 0;
        if (brick.active) {
            for (int w = 0; w < 8; ++w) n += std::uint64_t(std::popcount(brick.active[w]));
        } else {
            for (int i = 0; i < 512; ++i) n += brick.density[i] > 0.0f ? 1 : 0;
        }
        total += n;
    });
    return total.load();
}

/// The garment's slices of the run that made `volumePath`, in its voxel coordinates.
std::optional<SliceInstances> runSlicesOf(const std::string& volumePath, const std::string& garment, const Tell& note) {
    try {
        RunSlicesOptions options;
        options.garment = garment;
        const RunSlices run = loadRunSlices(volumePath, options);
        return sliceInstances(run.plan, run.grid);
    } catch (const Error& e) {
        if (!garment.empty()) throw;
        note(std::string("no slices mode: ") + e.what());
        return std::nullopt;
    }
}

} // namespace

ViewVolume::ViewVolume(ViewVolume&& other) noexcept
    : source(std::move(other.source)), slices(std::move(other.slices)), garment(other.garment),
      activeVoxels(other.activeVoxels), grid(other.grid), twist(other.twist), name(std::move(other.name)), scratch(std::move(other.scratch)) {
    other.scratch.clear();
}

ViewVolume::~ViewVolume() {
    source.reset(); // its file first
    if (!scratch.empty()) {
        std::error_code ignored;
        fs::remove_all(scratch, ignored);
    }
}

ViewVolume openViewVolume(const std::string& path, const VoxelizeJob& job, const Tell& note) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw Error(path + ": no such file or directory");
    ViewVolume v;
    v.name = fs::path(path).filename().string();
    if (isGarment(path)) {
        v.garment = true;
        v.scratch = makeScratch();
        VoxelizeJob run = job;
        run.input = path;
        run.output = (v.scratch / "garment.vdb").string();
        run.quiet = true;
        const VoxelizeReport report = runVoxelize(run, note);
        note("voxelized " + v.name + ": " + std::to_string(report.dims.x) + "x" + std::to_string(report.dims.y) + "x" +
             std::to_string(report.dims.z) + " voxels, " + std::to_string(report.activeVoxels) + " active, " +
             secondsText(report.voxelizeSeconds) + " s (" + report.backend + ")");
        v.source = openVdbSource(run.output);
        v.activeVoxels = report.activeVoxels;
        v.grid = VoxelGrid{report.origin, report.voxelSize, report.dims};
        v.twist = job.twist;
        v.slices = runSlicesOf(run.output, path, note);
    } else {
        v.source = openVolumeSource(path);
        if (v.source->occupiedBricks().empty()) throw Error(path + ": nothing to view: the volume has no active voxels");
        v.activeVoxels = countActiveVoxels(*v.source);
        v.slices = runSlicesOf(path, "", note);
    }
    return v;
}

} // namespace yv
