#include "garment/cross_section.h"
#include "garment/generate.h"
#include "gpu/egl_context.h"
#include "cpu/cpu_voxelizer.h"
#include "gpu/gl_voxelizer.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include <cstring>

using namespace yv;

namespace {

/// The GPU resolve, as on a GPU (on llvmpipe the backend would resolve on the host).
GlVoxelizeSettings glSettings(Reduce r = Reduce::Mean, std::uint64_t capacity = 0) {
    GlVoxelizeSettings s;
    s.base.reduce = r;
    s.fragmentCapacity = capacity;
    s.brickResolve = BrickResolve::Gpu;
    return s;
}

bool identical(const BrickVolume& a, const BrickVolume& b) {
    if (a.bricks.size() != b.bricks.size()) return false;
    for (std::size_t i = 0; i < a.bricks.size(); ++i)
        if (a.bricks[i].key != b.bricks[i].key || a.bricks[i].activeMask != b.bricks[i].activeMask ||
            std::memcmp(a.bricks[i].density.data(), b.bricks[i].density.data(), 4 * kBrickVoxels) != 0 ||
            std::memcmp(a.bricks[i].orientation.data(), b.bricks[i].orientation.data(), 12 * kBrickVoxels) != 0)
            return false;
    return true;
}

} // namespace

TEST_CASE("GL: a straight disk yarn fills pi r^2 L and follows its axis", "[gl][analytic]") {
    YV_REQUIRE_GL();
    const GlContext context;
    for (glm::dvec3 axis : {glm::dvec3(1, 0, 0), glm::dvec3(1, 0.4, 0.25)}) {
        SliceOptions opt;
        opt.radius = 0.3;
        const glm::dvec3 dir = glm::normalize(axis);
        const SlicePlan plan = planSlices(test::straightYarn({0.1, 0.2, 0.3}, dir, 6), opt);
        const VoxelGrid grid = makeGrid(plan, 0, 0.05);
        const BrickVolume v = voxelizeGl(plan, makeDiskCrossSection(), grid, glSettings(), context);
        CHECK(v.totalMass() == Approx(M_PI * 0.09 * 6).epsilon(0.02));
        double worst = 0.0;
        for (const VoxelBrick& b : v.bricks)
            for (int i = 0; i < kBrickVoxels; ++i)
                // Below 1e-3 of a voxel's fibre the fixed-point structure tensor
                // holds too few units for a meaningful axis.
                if (b.isActive(i) && b.density[i] >= 1e-3f)
                    worst = std::max(worst, std::acos(std::min(1.0, std::abs(glm::dot(glm::dvec3(b.orientation[i]), dir)))));
        CHECK(worst * 180 / M_PI < 1.0);
    }
}

TEST_CASE("GL: twisted yarn angle at radius rho is atan(rho tau)", "[gl][analytic]") {
    YV_REQUIRE_GL();
    const GlContext context;
    SliceOptions opt;
    opt.radius = 0.3;
    opt.twist = 3.0;
    const glm::dvec3 start(0.1, 0.2, 0.3), axis(0, 1, 0);
    const SlicePlan plan = planSlices(test::straightYarn(start, axis, 6), opt);
    const VoxelGrid grid = makeGrid(plan, 0, 0.05);
    const BrickVolume v = voxelizeGl(plan, makeDiskCrossSection(), grid, glSettings(), context);
    int checked = 0;
    double worst = 0.0;
    for (const VoxelBrick& b : v.bricks) {
        const glm::ivec3 o = brickCoord(b.key) * 8;
        for (int i = 0; i < kBrickVoxels; ++i) {
            if (!b.isActive(i)) continue;
            const glm::dvec3 p = grid.origin + (glm::dvec3(o + glm::ivec3(i >> 6, (i >> 3) & 7, i & 7)) + 0.5) * grid.voxelSize - start;
            const double along = p.y, rho = std::hypot(p.x, p.z);
            if (rho > opt.radius - grid.voxelSize || along < 0.5 || along > 5.5) continue;
            const double angle = std::acos(std::min(1.0, std::abs(double(b.orientation[i].y))));
            worst = std::max(worst, std::abs(angle - std::atan(rho * opt.twist)));
            ++checked;
        }
    }
    CHECK(checked > 1000);
    CHECK(worst * 180 / M_PI < 2.0);
}

TEST_CASE("GL agrees with the CPU reference on generated garments", "[gl][agreement]") {
    YV_REQUIRE_GL();
    const GlContext context;
    struct Case {
        WeavePattern pattern;
        GarmentShape shape;
        double twist;
        Reduce reduce;
    };
    const Case cases[] = {
        {WeavePattern::Plain, GarmentShape::Flat, 0.0, Reduce::Mean},
        {WeavePattern::Twill, GarmentShape::Cylinder, 2.0, Reduce::Mean},
        {WeavePattern::Knit, GarmentShape::Flat, 1.0, Reduce::Mean},
        {WeavePattern::Satin, GarmentShape::Sphere, 0.5, Reduce::Mean},
        {WeavePattern::Knit, GarmentShape::Cylinder, 1.0, Reduce::Max},
    };
    for (const Case& c : cases) {
        GenerateOptions g;
        g.pattern = c.pattern;
        g.shape = c.shape;
        g.crossings = 64;
        g.seed = 3;
        const Garment garment = generateGarment(g);
        SliceOptions opt;
        opt.radius = garment.yarnRadius;
        opt.twist = c.twist;
        opt.spacing = defaultSliceSpacing(voxelSizeFor(garment, opt.radius, 96, 0.0), 1);
        const SlicePlan plan = planSlices(garment, opt);
        const VoxelGrid grid = makeGrid(plan, 96, 0.0);
        const CrossSection xs = makeFiberCrossSection();
        VoxelizeSettings cpu;
        cpu.reduce = c.reduce;
        const BrickVolume ref = voxelizeCpu(plan, xs, grid, cpu);
        GlVoxelizeCounters counters;
        const BrickVolume gl = voxelizeGl(plan, xs, grid, glSettings(c.reduce), context, &counters);
        // What comes back from the GPU: packed bricks, and a few counts per
        // pass (the fragments and the sample items with their wrap flags, the
        // touched bricks, the resolve's totals: 28 bytes).
        const std::uint64_t packed =
            gl.bricks.size() * sizeof(PackedBrickHeader) + gl.activeVoxelCount() * sizeof(PackedVoxel);
        CHECK(counters.readbackBytes >= packed);
        CHECK(counters.readbackBytes - packed <=
              28 * (counters.passes + counters.listGrowths + 2 * counters.overflows + counters.plannedRegions));
        const test::VolumeComparison cmp = test::compareVolumes(ref, gl);
        INFO(toString(c.pattern) << " " << toString(c.shape) << " twist " << c.twist << " " << toString(c.reduce)
                                 << ": IoU " << cmp.iou << " mass ratio " << cmp.massRatio << " angle "
                                 << cmp.meanAngleDeg << "; density difference max " << cmp.maxDensityDiff
                                 << " mean " << cmp.meanDensityDiff << ", within 1e-4: " << cmp.densityWithinShare());
        CHECK(cmp.iou >= 0.9999);
        CHECK(std::abs(cmp.massRatio - 1.0) <= 1e-4);
        CHECK(cmp.densityWithinShare() >= 0.9999);
        CHECK(cmp.meanAngleDeg < 2.0);
    }
}

TEST_CASE("GL: texels read by one gather, by four fetches or from the quad texture give the same voxels bit for bit",
          "[gl][agreement]") {
    YV_REQUIRE_GL();
    const GlContext context;
    const test::GeneratedRun run = test::generatedRun(WeavePattern::Twill, GarmentShape::Cylinder, 64, 1.0, 96);
    const SlicePlan& plan = run.plan;
    const VoxelGrid& grid = run.grid;
    // Random texels everywhere, the four edges included: lookups near the
    // border clamp there, and a texture that wrapped instead would differ.
    CrossSection xs = makeFiberCrossSection(64);
    std::uint32_t state = 12345;
    for (std::uint8_t& t : xs.density) t = std::uint8_t((state = state * 1664525u + 1013904223u) >> 24);
    REQUIRE(xs.density.front() != xs.density.back());
    GlVoxelizeSettings fetch = glSettings(), gather = glSettings(), quad = glSettings();
    fetch.texelReads = TexelReads::Fetch;
    gather.texelReads = TexelReads::Gather;
    quad.texelReads = TexelReads::Quad;
    const BrickVolume a = voxelizeGl(plan, xs, grid, fetch, context), b = voxelizeGl(plan, xs, grid, gather, context);
    REQUIRE(a.activeVoxelCount() > 1000);
    CHECK(identical(a, b));
    CHECK(identical(a, voxelizeGl(plan, xs, grid, quad, context)));
    // And both agree with the CPU reference.
    const test::VolumeComparison cmp = test::compareVolumes(voxelizeCpu(plan, xs, grid, VoxelizeSettings{}), a);
    CHECK(cmp.iou >= 0.9999);
    CHECK(cmp.densityWithinShare() >= 0.9999);
}

TEST_CASE("GL: slices drawn as triangles or as point sprites (a slice each or runs of slices) or tested in compute give the same voxels bit for bit", "[gl][agreement]") {
    YV_REQUIRE_GL();
    const GlContext context;
    // A twisted cylinder (every tangent direction, so every projection axis
    // and tilt), once at one sample a voxel and once supersampled, with the
    // fibre texture and with the disk, whose square fallback differs.
    for (int supersample : {1, 2}) {
        const test::GeneratedRun run = test::generatedRun(WeavePattern::Twill, GarmentShape::Cylinder, 64, 1.0, 96 / supersample);
        for (const CrossSection& xs : {makeFiberCrossSection(64), makeDiskCrossSection()}) {
            INFO("supersample " << supersample << ", " << xs.name);
            GlVoxelizeSettings triangles = glSettings(), points = glSettings();
            triangles.base.supersample = points.base.supersample = supersample;
            triangles.slicePrimitive = SlicePrimitive::Triangle;
            points.slicePrimitive = SlicePrimitive::Point;
            GlVoxelizeCounters drawnAsTriangles, drawnAsPoints;
            const BrickVolume a = voxelizeGl(run.plan, xs, run.grid, triangles, context, &drawnAsTriangles);
            const BrickVolume b = voxelizeGl(run.plan, xs, run.grid, points, context, &drawnAsPoints);
            CHECK(drawnAsTriangles.slicePrimitive == "triangle");
            REQUIRE(drawnAsPoints.slicePrimitive == "point");
            REQUIRE(a.activeVoxelCount() > 1000);
            CHECK(drawnAsPoints.fragments == drawnAsTriangles.fragments);
            CHECK(identical(a, b));
            CHECK(drawnAsTriangles.primitivesDrawn == drawnAsTriangles.slicesDrawn);
            // The items appended in compute (slice_items.comp): no draw, the
            // same test over a box that holds every sprite's pixels.
            GlVoxelizeSettings computed = glSettings();
            computed.base.supersample = supersample;
            computed.slicePrimitive = SlicePrimitive::Compute;
            GlVoxelizeCounters appendedInCompute;
            CHECK(identical(a, voxelizeGl(run.plan, xs, run.grid, computed, context, &appendedInCompute)));
            CHECK(appendedInCompute.slicePrimitive == "compute");
            CHECK(appendedInCompute.fragments == drawnAsTriangles.fragments);
            CHECK(appendedInCompute.sampleItems >= drawnAsPoints.sampleItems);
            CHECK(appendedInCompute.sampleItems >= drawnAsTriangles.sampleItems);
            CHECK(appendedInCompute.primitivesDrawn == 0);
            CHECK(appendedInCompute.slicesDrawn == drawnAsTriangles.slicesDrawn);
            // Point sprites a slice each, or runs of consecutive slices
            // (slice_runs.comp): fewer points than slices (runs break where
            // the projection axis changes), the same voxels.
            for (int sliceRun : {1, 2, 4}) {
                INFO("runs of up to " << sliceRun << " slices");
                GlVoxelizeSettings runs = points;
                runs.sliceRun = sliceRun;
                GlVoxelizeCounters drawnInRuns;
                CHECK(identical(a, voxelizeGl(run.plan, xs, run.grid, runs, context, &drawnInRuns)));
                CHECK(drawnInRuns.fragments == drawnAsTriangles.fragments);
                CHECK(drawnInRuns.primitivesDrawn * sliceRun >= drawnInRuns.slicesDrawn);
                if (sliceRun == 1)
                    CHECK(drawnInRuns.primitivesDrawn == drawnInRuns.slicesDrawn);
                else
                    CHECK(drawnInRuns.primitivesDrawn * (sliceRun + 1) < drawnInRuns.slicesDrawn * 2);
            }
            // Many small regions: sprites whose centre lies outside a region
            // still reach into it (the viewport's margin keeps them).
            GlVoxelizeSettings smallPoints = points;
            smallPoints.sliceRun = 2;
            smallPoints.fragmentCapacity = test::smallestFragmentBudget(run.plan) * supersample * supersample + 2000;
            GlVoxelizeCounters drawnInPieces;
            const BrickVolume c = voxelizeGl(run.plan, xs, run.grid, smallPoints, context, &drawnInPieces);
            CHECK(drawnInPieces.plannedRegions > 8);
            CHECK(identical(a, c));
        }
    }
}

TEST_CASE("GL: a tiny fragment list overflows, is redone in pieces, and loses nothing", "[gl][overflow]") {
    YV_REQUIRE_GL();
    const GlContext context;
    GenerateOptions g;
    g.pattern = WeavePattern::Plain;
    g.crossings = 36;
    const Garment garment = generateGarment(g);
    SliceOptions opt;
    opt.radius = garment.yarnRadius;
    opt.twist = 1.5;
    opt.slicesPerSegment = 8;
    const SlicePlan plan = planSlices(garment, opt);
    const VoxelGrid grid = makeGrid(plan, 64, 0.0);
    const CrossSection xs = makeFiberCrossSection();
    for (Reduce r : {Reduce::Mean, Reduce::Max}) {
        GlVoxelizeCounters ample, tiny;
        const BrickVolume a = voxelizeGl(plan, xs, grid, glSettings(r), context, &ample);
        // The smallest budget the backend accepts here: 8 slices a segment, 64
        // pixels of a brick face, each column split over up to 5 voxels.
        const BrickVolume b = voxelizeGl(plan, xs, grid, glSettings(r, 8 * 64 * 5), context, &tiny);
        CHECK(ample.overflows == 0);
        CHECK(tiny.overflows >= 1); // the heat map underestimates some regions: they split
        CHECK(tiny.passes > ample.passes + 4);
        CHECK(tiny.plannedRegions > ample.plannedRegions);
        CHECK(tiny.fragments == ample.fragments);
        CHECK(identical(a, b));
        // The same with the sample items appended in compute.
        GlVoxelizeSettings computed = glSettings(r, 8 * 64 * 5);
        computed.slicePrimitive = SlicePrimitive::Compute;
        GlVoxelizeCounters tinyComputed;
        CHECK(identical(a, voxelizeGl(plan, xs, grid, computed, context, &tinyComputed)));
        CHECK(tinyComputed.overflows >= 1);
        CHECK(tinyComputed.fragments == ample.fragments);
    }
}

TEST_CASE("GL: a brick too full for one pass is drawn in halves, summed on the host, resolved on the GPU", "[gl][overflow]") {
    YV_REQUIRE_GL();
    const GlContext context;
    // The bricks at the crossing take more fragments than the smallest list
    // holds, from many segments, so they are drawn with their segments split.
    const test::CrossingRun run = test::crossingRun();
    const CrossSection xs = makeDiskCrossSection();
    for (Reduce r : {Reduce::Mean, Reduce::Max}) {
        GlVoxelizeCounters ample, tiny;
        const BrickVolume a = voxelizeGl(run.plan, xs, run.grid, glSettings(r), context, &ample);
        const BrickVolume b = voxelizeGl(run.plan, xs, run.grid, glSettings(r, test::smallestFragmentBudget(run.plan)), context, &tiny);
        INFO(toString(r) << ": " << tiny.hostSummedBricks << " bricks summed on the host, " << tiny.overflows
                         << " overflows");
        CHECK(ample.hostSummedBricks == 0);
        CHECK(tiny.hostSummedBricks > 0);
        CHECK(tiny.fragments == ample.fragments);
        CHECK(identical(a, b));
        CHECK(b.tally.activeVoxels == a.tally.activeVoxels);
        CHECK(b.tally.densitySum == Approx(a.tally.densitySum).epsilon(1e-12));
    }
}

TEST_CASE("GL: bricks resolved on the host are the GPU resolve's, bit for bit, tally included", "[gl][agreement]") {
    YV_REQUIRE_GL();
    const GlContext context;
    // With the smallest budget, both reductions.
    const auto check = [&](const SlicePlan& plan, const VoxelGrid& grid, const CrossSection& xs) {
        for (Reduce r : {Reduce::Mean, Reduce::Max}) {
            GlVoxelizeSettings gpu = glSettings(r, test::smallestFragmentBudget(plan)), host = gpu;
            host.brickResolve = BrickResolve::Host;
            GlVoxelizeCounters onGpu, onHost;
            const BrickVolume a = voxelizeGl(plan, xs, grid, gpu, context, &onGpu);
            const BrickVolume b = voxelizeGl(plan, xs, grid, host, context, &onHost);
            INFO(toString(r) << ": " << onGpu.regions << " regions, " << onGpu.hostSummedBricks << " bricks summed");
            REQUIRE(a.activeVoxelCount() > 1000);
            CHECK((onGpu.regions > 4 || onGpu.hostSummedBricks > 0));
            CHECK(onHost.fragments == onGpu.fragments);
            CHECK(onHost.hostSummedBricks == onGpu.hostSummedBricks);
            CHECK(identical(a, b));
            CHECK(b.tally.activeVoxels == a.tally.activeVoxels);
            CHECK(b.tally.voxelsOverOne == a.tally.voxelsOverOne);
            CHECK(b.tally.densitySum == a.tally.densitySum);
            CHECK(b.tally.rawDensitySum == a.tally.rawDensitySum);
        }
    };
    // A woven cylinder in many regions.
    const test::GeneratedRun woven = test::generatedRun(WeavePattern::Twill, GarmentShape::Cylinder, 64, 1.0, 96);
    check(woven.plan, woven.grid, makeFiberCrossSection());
    // Yarns through one point, whose bricks there are drawn in halves.
    const test::CrossingRun crossing = test::crossingRun(1.0);
    check(crossing.plan, crossing.grid, makeDiskCrossSection());
}

TEST_CASE("GL: a capacity below one segment's worth is refused with a clear error", "[gl][overflow]") {
    YV_REQUIRE_GL();
    const GlContext context;
    SliceOptions opt;
    opt.radius = 0.3;
    const SlicePlan plan = planSlices(test::straightYarn({0, 0, 0}, {1, 0, 0}, 3), opt);
    const VoxelGrid grid = makeGrid(plan, 32, 0.0);
    CHECK_THROWS_WITH(voxelizeGl(plan, makeDiskCrossSection(), grid, glSettings(Reduce::Mean, 100), context),
                      Catch::Contains("fragment budget 100"));
}

TEST_CASE("GL agrees with the CPU when slice counts vary per segment (--slice-spacing)", "[gl][agreement]") {
    YV_REQUIRE_GL();
    const GlContext context;
    GenerateOptions g;
    g.pattern = WeavePattern::Knit; // knit segments differ in length, so K differs
    g.crossings = 48;
    const Garment garment = generateGarment(g);
    SliceOptions opt;
    opt.radius = garment.yarnRadius;
    opt.twist = 1.0;
    opt.spacing = 0.05;
    const SlicePlan plan = planSlices(garment, opt);
    std::uint32_t lo = ~0u, hi = 0;
    for (const SegmentRecord& s : plan.segments) lo = std::min(lo, s.sliceCount), hi = std::max(hi, s.sliceCount);
    REQUIRE(lo < hi);
    const VoxelGrid grid = makeGrid(plan, 96, 0.0);
    const CrossSection xs = makeFiberCrossSection();
    const test::VolumeComparison cmp = test::compareVolumes(voxelizeCpu(plan, xs, grid, VoxelizeSettings{}),
                                                            voxelizeGl(plan, xs, grid, glSettings(), context));
    INFO("IoU " << cmp.iou << " mass ratio " << cmp.massRatio << " angle " << cmp.meanAngleDeg);
    CHECK(cmp.iou >= 0.99);
    CHECK(std::abs(cmp.massRatio - 1.0) <= 0.01);
    CHECK(cmp.meanAngleDeg < 2.0);
}

TEST_CASE("GL: fragment and item lists that start small grow and the pass is redone, losing nothing", "[gl][overflow]") {
    YV_REQUIRE_GL();
    const GlContext context;
    const test::GeneratedRun run = test::generatedRun(WeavePattern::Twill, GarmentShape::Cylinder, 64, 1.0, 64);
    const CrossSection xs = makeFiberCrossSection();
    // Items from the raster, and from the compute pass (slice_items.comp).
    for (SlicePrimitive primitive : {SlicePrimitive::Raster, SlicePrimitive::Compute}) {
        GlVoxelizeSettings settings = glSettings();
        settings.slicePrimitive = primitive;
        GlVoxelizeCounters plain, grown;
        const BrickVolume reference = voxelizeGl(run.plan, xs, run.grid, settings, context, &plain);
        INFO("items appended by " << plain.slicePrimitive);
        GlVoxelizeSettings small = settings;
        small.initialListSlots = 64;
        const BrickVolume volume = voxelizeGl(run.plan, xs, run.grid, small, context, &grown);
        REQUIRE(plain.sampleItems > 1000);
        CHECK(plain.listGrowths == 0);
        CHECK(grown.listGrowths >= 1);
        CHECK(grown.overflows == 0);
        CHECK(grown.fragments == plain.fragments);
        CHECK(grown.sampleItems == plain.sampleItems);
        CHECK(identical(reference, volume));
    }
}

TEST_CASE("GL: an append counter that wraps past 2^32 is caught and the pass redone, losing nothing", "[gl][overflow]") {
    YV_REQUIRE_GL();
    const GlContext context;
    SliceOptions opt;
    opt.radius = 0.3;
    const SlicePlan plan = planSlices(test::straightYarn({0, 0, 0}, {1, 0.2, 0.1}, 3), opt);
    const VoxelGrid grid = makeGrid(plan, 32, 0.0);
    const CrossSection xs = makeDiskCrossSection();
    GlVoxelizeCounters plain;
    const BrickVolume reference = voxelizeGl(plan, xs, grid, glSettings(), context, &plain);
    REQUIRE(plain.fragments > 1000); // the first pass goes past the wrap
    REQUIRE(plain.sampleItems > 1000);
    CHECK(plain.overflows == 0);
    // 256 slots before the 32-bit counter wraps: the fragments' counter (the
    // sampling pass), or the sample items' (the raster, or the compute pass
    // in its place).
    for (int counter = 0; counter < 3; ++counter) {
        const bool items = counter > 0;
        INFO((!items ? "fragment counter" : counter == 1 ? "sample item counter, raster" : "sample item counter, compute"));
        GlVoxelizeSettings nearWrap = glSettings();
        if (counter == 2) nearWrap.slicePrimitive = SlicePrimitive::Compute;
        (items ? nearWrap.firstItemCounterStart : nearWrap.firstCounterStart) = 0xffffff00u;
        GlVoxelizeCounters wrapped;
        const BrickVolume volume = voxelizeGl(plan, xs, grid, nearWrap, context, &wrapped);
        CHECK(wrapped.overflows >= 1);
        const test::VolumeComparison cmp = test::compareVolumes(reference, volume);
        CHECK(cmp.iou == 1.0);
        CHECK(cmp.massRatio == 1.0);
        CHECK(volume.activeVoxelCount() == reference.activeVoxelCount());
    }
}
