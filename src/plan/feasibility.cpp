#include "plan/feasibility.h"

#include "core/error.h"
#include "core/sampling.h"
#include "core/world_units.h"

#include <cmath>

namespace yv {

/// More slices than this per voxel along a yarn change nothing but the run time.
constexpr double kMaxSlicesPerVoxel = 64.0;

std::vector<std::string> checkRunScale(const RunScale& scale, const CrossSection& xs) {
    std::vector<std::string> warnings;
    const double h = scale.voxelSize, r = scale.radius;
    const std::string sizes = "yarn radius " + numberText(r) + " (" + scale.radiusSource + ") against voxel size " +
                              numberText(h) + " (" + scale.voxelSource + ")";
    // A sample hands a voxel at most the fibre area of the slice over the
    // voxel's face; shares under kMinVoxelShare are dropped by every backend.
    const double fibreArea = xs.analyticDisk ? M_PI * r * r : xs.meanDensity() * 4.0 * r * r;
    const double faceShare = fibreArea / (h * h);
    if (faceShare < kMinVoxelShare)
        throw Error(sizes + ": the yarn's fibre covers " + numberText(faceShare) +
                    " of a voxel face, below the smallest share a voxel keeps (1/65536): the volume would be empty "
                    "(wrong units? a finer --resolution or --voxel-size, or a larger --yarn-radius)");
    if (faceShare < 16.0 * kMinVoxelShare)
        warnings.push_back(sizes + ": the yarn's fibre covers " + numberText(faceShare) +
                           " of a voxel face: much of it falls under the smallest share a voxel keeps");
    if (!xs.analyticDisk) {
        // A texture is read at sample-pixel centres: a yarn narrower than a
        // pixel is hit by few of them, or none.
        const double pixelsAcross = 2.0 * r * scale.supersample / h;
        if (pixelsAcross < 0.25)
            throw Error(sizes + ": the yarn is " + numberText(pixelsAcross) + " sample pixels wide, so the " + xs.name +
                        " cross-section would miss nearly every sample and leave no voxels (a finer --resolution, a "
                        "higher --supersample, or --cross-section disk)");
        if (pixelsAcross < 1.0)
            warnings.push_back(sizes + ": the yarn is " + numberText(pixelsAcross) + " sample pixels wide: the " +
                               xs.name + " cross-section is aliased (raise --supersample or the resolution)");
    }
    if (scale.sliceSpacing > 0.0 && scale.sliceSpacing * kMaxSlicesPerVoxel < h)
        throw Error("--slice-spacing " + numberText(scale.sliceSpacing) + " puts more than " +
                    numberText(kMaxSlicesPerVoxel) + " slices in a voxel of size " + numberText(h) + " (" +
                    scale.voxelSource + "): it changes nothing but the run time (leave it out for one slice per voxel)");
    return warnings;
}

} // namespace yv
