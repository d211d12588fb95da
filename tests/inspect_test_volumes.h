// Volumes the inspect tests draw: a straight disk yarn whose silhouette is
// known, and a generated knit cylinder (shells of yarn around empty space);
// and one frame of the ray caster, as the renders draw it.
#pragma once

#include "core/bricks.h"
#include "cpu/cpu_voxelizer.h"
#include "garment/cross_section.h"
#include "garment/generate.h"
#include "garment/slices.h"
#include "plan/grid.h"
#include "render/raycast_renderer.h"
#include "test_helpers.h"

namespace yv::test {

/// A disk yarn of radius 0.3 along x, 8 voxels per radius.
struct StraightYarnVolume {
    SlicePlan plan;
    VoxelGrid grid;
    BrickVolume volume;
    glm::dvec3 start{0.0}, end{0.0}; ///< the axis's ends, in voxel coordinates
    double radiusVoxels = 0.0;
};

/// That yarn, `length` world units long, voxelized by the CPU reference.
inline StraightYarnVolume straightYarnVolume(int length) {
    const double radius = 0.3, h = radius / 8.0;
    const glm::dvec3 start(0.1, 0.2, 0.3);
    SliceOptions opt;
    opt.radius = radius;
    StraightYarnVolume y;
    y.plan = planSlices(straightYarn(start, {1, 0, 0}, length), opt);
    y.grid = makeGrid(y.plan, 0, h);
    y.volume = voxelizeCpu(y.plan, makeDiskCrossSection(), y.grid, VoxelizeSettings{});
    y.start = (start - y.grid.origin) / h;
    y.end = (start + glm::dvec3(length, 0, 0) - y.grid.origin) / h;
    y.radiusVoxels = radius / h;
    return y;
}

/// A generated knit cylinder of 300 crossings at `resolution`.
inline BrickVolume knitCylinderVolume(int resolution) {
    GenerateOptions gen;
    gen.crossings = 300;
    gen.shape = GarmentShape::Cylinder;
    gen.pattern = WeavePattern::Knit;
    const Garment garment = generateGarment(gen);
    SliceOptions opt;
    opt.radius = garment.yarnRadius;
    const SlicePlan plan = planSlices(garment, opt);
    return voxelizeCpu(plan, makeFiberCrossSection(), makeGrid(plan, resolution, 0.0), VoxelizeSettings{});
}

/// Pixels with any colour: the renders draw over black.
inline std::uint64_t nonBlackPixels(const RgbImage& im) {
    std::uint64_t n = 0;
    for (std::size_t i = 0; i < im.pixels.size(); i += 3) n += (im.pixels[i] | im.pixels[i + 1] | im.pixels[i + 2]) != 0;
    return n;
}

/// What one frame of the ray caster drew.
struct RayCast {
    RgbImage image;
    std::vector<float> samples; ///< per pixel, rows top first
    double meanSamples = 0.0;
    std::uint64_t proxyTriangles = 0;
};

/// One frame of `atlas` in `mode` from `camera` (the context must be current).
inline RayCast rayCast(const BrickAtlas& atlas, RenderMode mode, const Camera& camera, const RaycastSettings& settings = {}) {
    RaycastRenderer renderer(atlas, mode, settings);
    RenderReport report;
    drawFrames(renderer, camera, 1, report);
    return RayCast{report.image, renderer.samples(), renderer.meanSamples(), renderer.proxyTriangles()};
}

} // namespace yv::test
