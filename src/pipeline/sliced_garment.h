// The first stage of a run: the garment read, checked and sliced.
#pragma once

#include "garment/cross_section.h"
#include "garment/garment.h"
#include "garment/slices.h"
#include "pipeline/stage_timer.h"
#include "pipeline/voxelize_job.h"
#include "pipeline/yarn_radius.h"
#include "plan/resource_estimate.h"

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace yv {

/// What reading and slicing the garment gives the rest of the run. The
/// garment and its plan are shared with a SlicePlanCache where the job has one.
struct SlicedGarment {
    std::shared_ptr<const Garment> garmentRead;
    CrossSection xs;
    YarnRadiusChoice radius;
    SliceOptions sliceOptions;
    bool explicitSpacing = false; ///< --slices-per-segment or --slice-spacing asked for
    std::shared_ptr<const SlicePlan> slicePlan;

    const Garment& garment() const { return *garmentRead; }
    const SlicePlan& plan() const { return *slicePlan; }
};

/// The garment read and its slices planned, kept for the next runs of the
/// same garment file (its path, size and modification time) and slice
/// options: the live view voxelizes box after box of one garment, and at the
/// paper's 50 slices a segment its plan took 0.3 s a run on the H200. Keeps
/// the last garment and the last two plans (a view's coarse and final
/// passes). Safe to share between threads.
class SlicePlanCache {
  public:
    /// The garment file's identity: a file changed on disk is read again.
    struct FileKey {
        std::string path;
        std::uintmax_t size = 0;
        std::int64_t modified = 0;
        bool operator==(const FileKey&) const = default;
    };
    static FileKey keyOf(const std::string& path);

    std::shared_ptr<const Garment> garment(const FileKey& file) const;
    void keepGarment(const FileKey& file, std::shared_ptr<const Garment> garment);
    std::shared_ptr<const SlicePlan> plan(const FileKey& file, const SliceOptions& options) const;
    void keepPlan(const FileKey& file, const SliceOptions& options, std::shared_ptr<const SlicePlan> plan);

  private:
    struct PlanEntry {
        FileKey file;
        SliceOptions options;
        std::shared_ptr<const SlicePlan> plan;
    };
    mutable std::mutex mutex_;
    FileKey garmentFile_;
    std::shared_ptr<const Garment> garment_;
    std::vector<PlanEntry> plans_; ///< most recent last
};

/// Reads the garment and tidies its curves, makes the cross-section, chooses
/// the yarn radius, refuses a run that would leave no voxels or does not fit
/// on disk (`throughWorkDir`: the regions go through a work directory too),
/// and places the slices (one a supersampled voxel along the yarn unless the
/// job says otherwise). Laps "read" and "slices" on `timer`; warnings go to
/// `tell`. Throws yv::Error naming the input.
SlicedGarment sliceGarment(const VoxelizeJob& job, bool throughWorkDir, const Tell& tell, StageTimer& timer);

/// Refuses, once the slices lie on `grid`, a run whose expected output (the
/// .vdb as `shape` stores it, its scratch file, the work dir's regions) does
/// not fit the free disk: the bound sliceGarment checks before slicing
/// catches only runs far too large. `boxYarnLength`: a --bbox run's, the
/// arc length of the segments that reach its box (the whole garment's
/// otherwise). Throws yv::Error naming the input, the bytes expected and
/// free, and what to change.
void checkOutputFits(const VoxelizeJob& job, bool throughWorkDir, const SlicedGarment& sliced, const VoxelGrid& grid,
                     const VdbShape& shape, std::optional<double> boxYarnLength = std::nullopt);

} // namespace yv
