// What a live view draws, opened once when `yarnvox view` starts: the
// volume's bricks (a work directory or a .vdb as inspect reads them, or a
// garment voxelized here first) and, where they can be found, the garment's
// slices in the volume's voxel coordinates. Nothing here is reloaded per frame.
#pragma once

#include "inspect/run_slices.h"
#include "inspect/slice_instances.h"
#include "inspect/volume_source.h"
#include "core/voxel_grid.h"
#include "pipeline/voxelize_job.h"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

namespace yv {

struct ViewVolume {
    std::unique_ptr<VolumeSource> source;
    std::optional<SliceInstances> slices; ///< the garment's slices, where the garment is known
    /// A garment was given: its slices are drawn beside the ray cast of its voxelization.
    bool garment = false;
    std::uint64_t activeVoxels = 0;
    /// Where the volume's voxels lie in the world, where known (a garment's
    /// run): what voxelizing the view at a finer voxel size needs.
    std::optional<VoxelGrid> grid;
    /// The yarn twist the garment was sliced and voxelized with, radians per
    /// world unit (a garment given; 0 otherwise).
    double twist = 0.0;
    /// How what the camera sees is voxelized (its input the garment): a
    /// garment given, with the view's options and the slice plan cache its
    /// first voxelization filled; a .vdb or work directory
    /// whose run's garment is found, with the options that run recorded.
    /// None: the view cannot voxelize.
    std::optional<VoxelizeJob> voxelizeJob;
    std::string name; ///< the input's file name, for the page's title
    std::filesystem::path scratch; ///< where a garment's voxelization lies while the view runs ("" when none)

    ViewVolume() = default;
    /// The scratch directory goes with the move: only the last owner removes it.
    ViewVolume(ViewVolume&& other) noexcept;
    ViewVolume& operator=(ViewVolume&&) = delete;
    ~ViewVolume(); ///< removes `scratch`
};

/// Opens `path`: a work directory or a .vdb (its slices, grid and options
/// too, where the run that made it names a garment that is still there: the
/// view then voxelizes what the camera sees as that run would, with the
/// device, backend and budgets of `job`), or a .bcc garment,
/// voxelized first as `voxelize` (with `job`'s options, its input and output
/// set here) would, into a scratch .vdb removed when the view ends. Must run
/// on the thread that will render (a voxelization makes a GL context of its
/// own and leaves none current). Notes go to `note`. Throws yv::Error naming
/// `path` (missing, not a volume, an empty volume, a voxelization refused).
ViewVolume openViewVolume(const std::string& path, const VoxelizeJob& job, const Tell& note);

/// The job that voxelizes again as the run recorded in `run` did (its
/// garment, cross-section, yarn radius, twist, supersampling, slice
/// placement, reduce and overlap, colour), on `view`'s device, backend,
/// precision and budgets. Throws yv::Error naming `volumePath` for a
/// recorded value it cannot read.
VoxelizeJob recordedVoxelizeJob(const RunSlices& run, const VoxelizeJob& view, const std::string& volumePath);

} // namespace yv
