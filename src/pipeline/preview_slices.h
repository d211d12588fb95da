// The slices a preview draws straight from a garment (`yarnvox inspect
// GARMENT.bcc --render volumetric-triangles`), planned as `voxelize` plans
// them, or found for a volume yarnvox made from the garment its metadata
// names, on the volume's own grid so the pictures line up.
#pragma once

#include "garment/slices.h"
#include "plan/grid.h"

#include <string>

namespace yv {

struct PreviewSliceOptions {
    double yarnRadius = 0.0;   ///< 0: the garment file's, else estimated (as voxelize)
    int resolution = 0;        ///< voxels on the longest axis; 0: kPreviewResolution
    double spacing = 0.0;      ///< slice spacing, world units; 0: one slice per voxel
    int slicesPerSegment = 0;  ///< instead of spacing, when > 0
    std::string crossSection;  ///< fibers, disk or FILE.png; "": the volume's, else voxelize's default (fibers)
};

/// The grid a preview of a bare garment uses when no --resolution is given.
constexpr int kPreviewResolution = 512;

struct PreviewSlices {
    std::string garment; ///< the garment file the slices come from
    SlicePlan plan;
    VoxelGrid grid;
    double yarnDensity = 1.0; ///< the cross-section's mean density inside the yarn's disk
};

/// Slices of the garment file at `path`. Throws yv::Error naming the file.
PreviewSlices garmentPreviewSlices(const std::string& path, const PreviewSliceOptions& options);

/// Slices of the garment a work directory or a yarnvox .vdb was made from
/// (its recorded input, yarn radius, supersampling and grid), unless
/// `options` says otherwise. Throws yv::Error asking for the garment when the
/// volume names none or the file is not there.
PreviewSlices volumePreviewSlices(const std::string& volumePath, const PreviewSliceOptions& options);

} // namespace yv
