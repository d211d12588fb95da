#include "core/error.h"
#include "garment/cross_section.h"
#include "garment/generate.h"
#include "gpu/dense_voxelizer.h"
#include "gpu/egl_context.h"
#include "gpu/gl_voxelizer.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>

using namespace yv;

namespace {

GlVoxelizeSettings maxSettings() {
    GlVoxelizeSettings s;
    s.base.reduce = Reduce::Max;
    s.base.quiet = true;
    return s;
}

/// The dense method against the sparse GL backend in max mode (same sample
/// rule): only its racy read-modify-write and 8-bit storage may differ.
void checkAgainstSparse(const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid, const char* what) {
    const GlContext context;
    const BrickVolume sparse = voxelizeGl(plan, xs, grid, maxSettings(), context);
    DenseVoxelizeCounters counters;
    const BrickVolume dense = voxelizeDense(plan, xs, grid, maxSettings(), context, &counters);
    CHECK(dense.reduce == Reduce::Max);
    CHECK(counters.textureBytes == 3 * grid.voxelCount());
    CHECK(!counters.renderer.empty());
    CHECK(std::is_sorted(dense.bricks.begin(), dense.bricks.end(),
                         [](const VoxelBrick& a, const VoxelBrick& b) { return a.key < b.key; }));

    const VolumeComparison cmp = compareVolumes(sparse, dense);
    const test::VolumeIndex index(dense);
    std::uint64_t both = 0, equal = 0;
    for (const VoxelBrick& b : sparse.bricks) {
        const glm::ivec3 o = brickCoord(b.key) * 8;
        for (int v = 0; v < kBrickVoxels; ++v) {
            if (!b.isActive(v)) continue;
            const float d = index.density(o + glm::ivec3(v >> 6, (v >> 3) & 7, v & 7));
            if (d == 0.0f) continue;
            ++both;
            // The dense textures hold densities in 8 bits.
            if (std::abs(d - b.density[v]) <= 0.5f / 255.0f + 1e-6f) ++equal;
        }
    }
    INFO(what << ": IoU " << cmp.iou << " (" << cmp.onlyA << " only sparse, " << cmp.onlyB << " only dense), angle "
              << cmp.meanAngleDeg << ", equal max density " << equal << " of " << both);
    CHECK(both > 1000);
    CHECK(cmp.iou >= 0.98);
    CHECK(double(equal) >= 0.98 * double(both));
    CHECK(cmp.meanAngleDeg < 3.0); // 8-bit angles, racy orientation writes
}

} // namespace

TEST_CASE("dense method agrees with the sparse GL backend on a straight disk yarn", "[gl][dense]") {
    YV_REQUIRE_GL();
    SliceOptions opt;
    opt.radius = 0.3;
    const SlicePlan plan = planSlices(test::straightYarn({0.1, 0.2, 0.3}, glm::normalize(glm::dvec3(1, 0.4, 0.25)), 6), opt);
    const VoxelGrid grid = makeGrid(plan, 0, 0.05);
    checkAgainstSparse(plan, makeDiskCrossSection(), grid, "straight yarn");
}

TEST_CASE("dense method agrees with the sparse GL backend on a generated garment", "[gl][dense]") {
    YV_REQUIRE_GL();
    GenerateOptions g;
    g.pattern = WeavePattern::Knit;
    g.shape = GarmentShape::Cylinder;
    g.crossings = 36;
    g.seed = 3;
    const Garment garment = generateGarment(g);
    SliceOptions opt;
    opt.radius = garment.yarnRadius;
    opt.twist = 1.0;
    opt.slicesPerSegment = 8;
    const SlicePlan plan = planSlices(garment, opt);
    checkAgainstSparse(plan, makeFiberCrossSection(), makeGrid(plan, 64, 0.0), "knit cylinder");
}

TEST_CASE("dense method refuses a grid larger than one 3D texture", "[gl][dense]") {
    YV_REQUIRE_GL();
    const GlContext context;
    const int max3d = context.info().max3dTextureSize;
    GenerateOptions g;
    g.crossings = 16;
    const Garment garment = generateGarment(g);
    SliceOptions opt;
    opt.radius = garment.yarnRadius;
    const SlicePlan plan = planSlices(garment, opt);
    const VoxelGrid grid = makeGrid(plan, std::max(4096, max3d + 8), 0.0);
    REQUIRE(std::max({grid.dims.x, grid.dims.y, grid.dims.z}) > max3d);
    try {
        voxelizeDense(plan, makeDiskCrossSection(), grid, maxSettings(), context);
        FAIL("expected yv::Error");
    } catch (const Error& e) {
        INFO(e.what());
        CHECK(std::string(e.what()).find("dense method: grid ") == 0);
        CHECK(std::string(e.what()).find("exceeds one 3D texture") != std::string::npos);
    }
}
