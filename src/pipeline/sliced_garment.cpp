#include "pipeline/sliced_garment.h"

#include "bcc.h"
#include "core/error.h"
#include "core/trace.h"
#include "core/world_units.h"
#include "garment/curve_check.h"
#include "plan/feasibility.h"
#include "plan/grid.h"
#include "plan/resource_estimate.h"

#include <filesystem>

namespace yv {
namespace {

/// Where the run writes: the output's directory, and the work dir's.
RunPlace runPlace(const VoxelizeJob& job, bool throughWorkDir) {
    const std::string outputDir = std::filesystem::path(job.output).parent_path().string();
    return {outputDir, throughWorkDir ? (job.workDir.empty() ? outputDir : job.workDir) : ""};
}

/// How the grid was asked for, as the messages name it.
std::string scaleOption(const VoxelizeJob& job) {
    return job.resolution > 0 ? "--resolution " + std::to_string(job.resolution) : "--voxel-size " + numberText(job.voxelSize);
}

/// Refuses a run that needs more disk than the output's (and the work
/// dir's) file system has, before minutes of work.
void checkDiskNeeds(const VoxelizeJob& job, bool throughWorkDir, const Garment& garment, double radius,
                    double voxelSize, const std::string& voxelSource) {
    const TraceSpan span("estimate what the run needs");
    const std::string problem = checkNeeds(estimateNeeds(garment, radius, voxelSize, job.precision == VdbPrecision::Half),
                                           runPlace(job, throughWorkDir), voxelSource);
    if (!problem.empty()) throw Error(job.input + ": " + problem);
}

} // namespace

SlicePlanCache::FileKey SlicePlanCache::keyOf(const std::string& path) {
    std::error_code ec;
    FileKey key{path, std::filesystem::file_size(path, ec), 0};
    if (ec) return FileKey{}; // unreadable: never matches, the read says why
    const auto modified = std::filesystem::last_write_time(path, ec);
    if (ec) return FileKey{};
    key.modified = std::int64_t(modified.time_since_epoch().count());
    return key;
}

std::shared_ptr<const Garment> SlicePlanCache::garment(const FileKey& file) const {
    const std::lock_guard lock(mutex_);
    return !file.path.empty() && file == garmentFile_ ? garment_ : nullptr;
}

void SlicePlanCache::keepGarment(const FileKey& file, std::shared_ptr<const Garment> garment) {
    const std::lock_guard lock(mutex_);
    garmentFile_ = file;
    garment_ = std::move(garment);
}

std::shared_ptr<const SlicePlan> SlicePlanCache::plan(const FileKey& file, const SliceOptions& options) const {
    const std::lock_guard lock(mutex_);
    if (file.path.empty()) return nullptr;
    for (const PlanEntry& e : plans_)
        if (e.file == file && e.options == options) return e.plan;
    return nullptr;
}

void SlicePlanCache::keepPlan(const FileKey& file, const SliceOptions& options, std::shared_ptr<const SlicePlan> plan) {
    const std::lock_guard lock(mutex_);
    if (plans_.size() == 2) plans_.erase(plans_.begin());
    plans_.push_back(PlanEntry{file, options, std::move(plan)});
}

SlicedGarment sliceGarment(const VoxelizeJob& job, bool throughWorkDir, const Tell& tell, StageTimer& timer) {
    SlicedGarment s;
    const SlicePlanCache::FileKey file = job.sliceCache ? SlicePlanCache::keyOf(job.input) : SlicePlanCache::FileKey{};
    if (job.sliceCache) s.garmentRead = job.sliceCache->garment(file);
    if (!s.garmentRead) {
        std::shared_ptr<Garment> garment;
        {
            const TraceSpan span("parse the garment");
            garment = std::make_shared<Garment>(readBcc(job.input));
        }
        // Real files repeat points and mislabel loops: tidied here, said once.
        CurveCheckReport curveReport;
        {
            const TraceSpan span("check the curves");
            curveReport = checkCurves(*garment, job.input);
        }
        if (const std::string dropped = curveReport.droppedText(job.input); !dropped.empty()) tell(dropped);
        for (const std::string& w : curveReport.warnings) tell("warning: " + w);
        s.garmentRead = std::move(garment);
        if (job.sliceCache) job.sliceCache->keepGarment(file, s.garmentRead);
    }
    timer.lap("read");

    s.xs = makeCrossSection(job.crossSection, job.albedo);
    s.radius = chooseYarnRadius(job.yarnRadius, s.xs, s.garment(), job.input);
    if (!s.radius.note.empty()) tell(s.radius.note);
    s.sliceOptions.twist = job.twist;
    s.sliceOptions.radius = s.radius.radius;
    // Slices follow the voxel size, not the garment's control points: one
    // slice per (supersampled) voxel along the yarn, unless asked otherwise.
    // The curves' bounds once: the voxel size and the plan both want them.
    glm::dvec3 curveMin, curveMax;
    curveBounds(s.garment(), curveMin, curveMax);
    const double voxelSize = voxelSizeForCurves(curveMin, curveMax, s.radius.radius, job.resolution, job.voxelSize);
    // A run that would leave no voxels is refused before any slicing.
    const RunScale scale{s.radius.radius, s.radius.description, voxelSize, scaleOption(job), job.supersample, job.spacing};
    for (const std::string& w : checkRunScale(scale, s.xs)) tell("warning: " + w);
    // The whole garment's bound says nothing of a --bbox run's box (a cuff at
    // a resolution the garment could never have): checkOutputFits covers it. A
    // run that keeps its bricks in memory writes nothing.
    if (!job.box && !job.bricksOnly())
        checkDiskNeeds(job, throughWorkDir, s.garment(), s.radius.radius, voxelSize, scale.voxelSource);

    s.explicitSpacing = job.slicesPerSegment > 0 || job.spacing > 0.0;
    s.sliceOptions.slicesPerSegment = job.slicesPerSegment;
    s.sliceOptions.spacing = s.explicitSpacing ? job.spacing : defaultSliceSpacing(voxelSize, job.supersample);
    if (job.sliceCache) s.slicePlan = job.sliceCache->plan(file, s.sliceOptions);
    if (!s.slicePlan) {
        const TraceSpan span("plan the slices");
        try {
            s.slicePlan = std::make_shared<const SlicePlan>(planSlices(s.garment(), s.sliceOptions, curveMin, curveMax));
        } catch (const Error& e) {
            throw Error(job.input + ": " + e.what());
        }
        if (job.sliceCache) job.sliceCache->keepPlan(file, s.sliceOptions, s.slicePlan);
    }
    timer.lap("slices");
    return s;
}

void checkOutputFits(const VoxelizeJob& job, bool throughWorkDir, const SlicedGarment& sliced, const VoxelGrid& grid,
                     const VdbShape& shape, std::optional<double> boxYarnLength) {
    const TraceSpan span("estimate the output");
    OutputPlan expected = outputPlan(sliced.plan(), grid, sliced.xs, shape);
    if (boxYarnLength) expected.yarnLength = *boxYarnLength;
    const std::string problem = checkExpectedDisk(expected, runPlace(job, throughWorkDir), scaleOption(job));
    if (!problem.empty()) throw Error(job.input + ": " + problem);
}

} // namespace yv
