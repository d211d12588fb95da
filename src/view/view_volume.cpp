#include "view/view_volume.h"

#include "core/brick_mask.h"
#include "core/error.h"
#include "inspect/slice_instances.h"
#include "inspect/run_slices.h"
#include "pipeline/sliced_garment.h"
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
            const std::span<const std::uint64_t, kBrickMaskWords> mask(brick.active, kBrickMaskWords);
            n = std::uint64_t(activeVoxelCount(mask));
        } else {
            for (int i = 0; i < 512; ++i) n += brick.density[i] > 0.0f ? 1 : 0;
        }
        total += n;
    });
    return total.load();
}

/// The run that made `volumePath`: its garment's slices, grid and record.
/// None, with a note, where its garment cannot be found (`garment` given: an error).
std::optional<RunSlices> runOf(const std::string& volumePath, const std::string& garment, const Tell& note) {
    try {
        RunSlicesOptions options;
        options.garment = garment;
        return loadRunSlices(volumePath, options);
    } catch (const Error& e) {
        if (!garment.empty()) throw;
        note(std::string("no slices mode and no voxelizing what the camera sees: ") + e.what());
        return std::nullopt;
    }
}

std::string recordedText(const RunSlices& run, const std::string& key) {
    const auto it = run.recorded.find(key);
    return it == run.recorded.end() ? std::string() : it->second;
}

} // namespace

ViewVolume::ViewVolume(ViewVolume&& other) noexcept
    : source(std::move(other.source)), slices(std::move(other.slices)), garment(other.garment),
      activeVoxels(other.activeVoxels), grid(other.grid), twist(other.twist), voxelizeJob(std::move(other.voxelizeJob)),
      name(std::move(other.name)), scratch(std::move(other.scratch)) {
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
        // The view's later runs take the garment read here, and at a fixed
        // number of slices a segment its slice plan too (the first stop at
        // 41 M slices spent 0.3 s planning them again on the H200).
        if (!run.sliceCache) run.sliceCache = std::make_shared<SlicePlanCache>();
        const VoxelizeReport report = runVoxelize(run, note);
        note("voxelized " + v.name + ": " + std::to_string(report.dims.x) + "x" + std::to_string(report.dims.y) + "x" +
             std::to_string(report.dims.z) + " voxels, " + std::to_string(report.activeVoxels) + " active, " +
             secondsText(report.voxelizeSeconds) + " s (" + report.backend + ")");
        v.source = openVdbSource(run.output);
        v.activeVoxels = report.activeVoxels;
        v.grid = VoxelGrid{report.origin, report.voxelSize, report.dims};
        v.twist = job.twist;
        v.voxelizeJob = run;
        v.voxelizeJob->input = path;
        v.voxelizeJob->output.clear();
        if (const std::optional<RunSlices> slices = runOf(run.output, path, note))
            v.slices = sliceInstances(slices->plan, slices->grid);
    } else {
        v.source = openVolumeSource(path);
        if (v.source->occupiedBricks().empty()) throw Error(path + ": nothing to view: the volume has no active voxels");
        v.activeVoxels = countActiveVoxels(*v.source);
        if (const std::optional<RunSlices> run = runOf(path, "", note)) {
            v.slices = sliceInstances(run->plan, run->grid);
            // Where its garment is found, the view voxelizes as its run did, on the run's grid.
            VoxelGrid grid = run->grid;
            const VoxelBox bounds = v.source->bounds();
            const int resolution = int(recordedNumber(run->recorded, "resolution", 0.0, path));
            grid.dims = glm::max(glm::max(bounds.max, glm::ivec3(resolution > 0 ? resolution : 1)), glm::ivec3(1));
            v.grid = grid;
            v.voxelizeJob = recordedVoxelizeJob(*run, job, path);
            v.twist = v.voxelizeJob->twist;
        }
    }
    return v;
}

VoxelizeJob recordedVoxelizeJob(const RunSlices& run, const VoxelizeJob& view, const std::string& volumePath) {
    VoxelizeJob job;
    // The machine's side of the view's options.
    job.backend = view.backend;
    job.device = view.device;
    job.fragmentCapacity = view.fragmentCapacity;
    job.precision = view.precision;
    job.compression = view.compression;
    job.quiet = true;
    // The garment's side, as the run recorded it.
    job.input = run.garmentPath;
    const std::string crossSection = recordedText(run, "cross_section");
    if (!crossSection.empty()) job.crossSection = crossSection;
    job.yarnRadius = recordedNumber(run.recorded, "yarn_radius", 0.0, volumePath);
    job.twist = recordedNumber(run.recorded, "twist", 0.0, volumePath);
    job.supersample = std::max(1, int(recordedNumber(run.recorded, "supersample", 1.0, volumePath)));
    job.slicesPerSegment = int(recordedNumber(run.recorded, "slices_per_segment", 0.0, volumePath));
    job.spacing = recordedNumber(run.recorded, "slice_spacing_option", 0.0, volumePath);
    const std::string overlap = recordedText(run, "overlap"), reduce = recordedText(run, "reduce");
    if (!overlap.empty() && overlap != "clamp" && overlap != "sum")
        throw Error(volumePath + ": the recorded overlap '" + overlap + "' is neither clamp nor sum");
    if (!reduce.empty() && reduce != "mean" && reduce != "max")
        throw Error(volumePath + ": the recorded reduce '" + reduce + "' is neither mean nor max");
    job.overlap = overlap == "sum" ? Overlap::Sum : Overlap::Clamp;
    job.reduce = reduce == "max" ? Reduce::Max : Reduce::Mean;
    const std::string albedo = recordedText(run, "albedo");
    job.albedo = albedo == "1" || albedo == "true";
    return job;
}

} // namespace yv
