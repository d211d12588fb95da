#include "cpu/cpu_region_backend.h"
#include "cpu/cpu_voxelizer.h"
#include "cpu/slice_sampler.h"
#include "garment/cross_section.h"
#include "garment/generate.h"
#include "plan/zoom_plan.h"
#include "test_helpers.h"
#include "vdb_bytes.h"
#include "vdb/vdb_writer.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>

using namespace yv;
namespace fs = std::filesystem;

namespace {

struct StraightYarnCase {
    SlicePlan plan;
    VoxelGrid grid;
    CrossSection xs = makeDiskCrossSection();
    glm::dvec3 start, axis;
    double radius = 0.3;
    int length = 6;
};

/// A disk yarn of radius 0.3 and length 6, 6 voxels per radius (h = 0.05).
StraightYarnCase straightCase(glm::dvec3 axis, double twist, int slicesPerSegment = 25) {
    StraightYarnCase c;
    c.start = {0.1, 0.2, 0.3};
    c.axis = glm::normalize(axis);
    SliceOptions opt;
    opt.radius = c.radius;
    opt.twist = twist;
    opt.slicesPerSegment = slicesPerSegment;
    c.plan = planSlices(test::straightYarn(c.start, c.axis, c.length), opt);
    c.grid = makeGrid(c.plan, 0, c.radius / 6.0);
    return c;
}

VoxelizeSettings settings(Reduce r = Reduce::Mean, int supersample = 1) {
    VoxelizeSettings s;
    s.reduce = r;
    s.supersample = supersample;
    return s;
}

glm::dvec3 voxelCenter(const VoxelGrid& g, glm::ivec3 v) { return g.origin + (glm::dvec3(v) + 0.5) * g.voxelSize; }

} // namespace

TEST_CASE("A straight disk yarn fills pi r^2 L", "[cpu][analytic]") {
    for (glm::dvec3 axis : {glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(1, 0.4, 0.25), glm::dvec3(0.3, -1, 0.7)}) {
        for (int ss : {1, 2}) {
            const StraightYarnCase c = straightCase(axis, 0.0);
            const BrickVolume v = voxelizeCpu(c.plan, c.xs, c.grid, settings(Reduce::Mean, ss));
            const double expected = M_PI * c.radius * c.radius * c.length;
            INFO("axis " << axis.x << "," << axis.y << "," << axis.z << " supersample " << ss);
            CHECK(v.totalMass() == Approx(expected).epsilon(0.02));
        }
    }
}

TEST_CASE("Without twist every orientation follows the yarn axis", "[cpu][analytic]") {
    const StraightYarnCase c = straightCase({1, 0.4, 0.25}, 0.0);
    const BrickVolume v = voxelizeCpu(c.plan, c.xs, c.grid, settings());
    REQUIRE(v.activeVoxelCount() > 1000);
    double worst = 0.0;
    for (const VoxelBrick& b : v.bricks)
        for (int i = 0; i < kBrickVoxels; ++i)
            // Below 1e-3 of a voxel's fibre the fixed-point structure tensor
            // holds too few units for a meaningful axis.
            if (b.isActive(i) && b.density[i] >= 1e-3f)
                worst = std::max(worst, std::acos(std::min(1.0, std::abs(glm::dot(glm::dvec3(b.orientation[i]), c.axis)))));
    CHECK(worst * 180.0 / M_PI < 1.0);
}

TEST_CASE("With twist the fibre angle at radius rho is atan(rho tau)", "[cpu][analytic]") {
    const double tau = 3.0;
    const StraightYarnCase c = straightCase({0, 1, 0}, tau);
    const BrickVolume v = voxelizeCpu(c.plan, c.xs, c.grid, settings());
    int checked = 0;
    double worst = 0.0;
    for (const VoxelBrick& b : v.bricks) {
        const glm::ivec3 origin = brickCoord(b.key) * 8;
        for (int i = 0; i < kBrickVoxels; ++i) {
            if (!b.isActive(i)) continue;
            const glm::ivec3 voxel = origin + glm::ivec3(i >> 6, (i >> 3) & 7, i & 7);
            const glm::dvec3 p = voxelCenter(c.grid, voxel) - c.start;
            const double along = glm::dot(p, c.axis);
            const double rho = glm::length(p - along * c.axis);
            // Whole voxels inside the yarn, away from the ends.
            if (rho > c.radius - c.grid.voxelSize || along < 0.5 || along > c.length - 0.5) continue;
            const double angle = std::acos(std::min(1.0, std::abs(glm::dot(glm::dvec3(b.orientation[i]), c.axis))));
            worst = std::max(worst, std::abs(angle - std::atan(rho * tau)));
            ++checked;
        }
    }
    CHECK(checked > 1000);
    CHECK(worst * 180.0 / M_PI < 2.0);
}

TEST_CASE("max and mean reductions differ the way they should", "[cpu]") {
    const StraightYarnCase c = straightCase({1, 0.2, 0.1}, 0.0);
    // Four by four samples per voxel face, so a voxel can be partly covered.
    const BrickVolume mean = voxelizeCpu(c.plan, c.xs, c.grid, settings(Reduce::Mean, 4));
    const BrickVolume max = voxelizeCpu(c.plan, c.xs, c.grid, settings(Reduce::Max, 4));
    // Same voxels are touched by samples either way.
    CHECK(mean.activeVoxelCount() == max.activeVoxelCount());
    // Max holds the densest sample, in [0, 1]; inside a solid disk that is 1.
    // Mean holds volume fractions: about 1 inside, partial at the surface.
    test::VolumeIndex mi(mean), xi(max);
    std::uint64_t active = 0, surfaceLike = 0;
    for (const VoxelBrick& b : max.bricks) {
        const glm::ivec3 origin = brickCoord(b.key) * 8;
        for (int i = 0; i < kBrickVoxels; ++i) {
            if (!b.isActive(i)) continue;
            ++active;
            CHECK(b.density[i] <= 1.0f);
            const float m = mi.density(origin + glm::ivec3(i >> 6, (i >> 3) & 7, i & 7));
            // A voxel the yarn only grazes: a small volume fraction, yet the
            // densest sample in it is solid fibre.
            if (b.density[i] - m > 0.25f) ++surfaceLike;
        }
    }
    const glm::ivec3 centre = glm::ivec3(glm::floor((c.start + 3.0 * c.axis - c.grid.origin) / c.grid.voxelSize));
    CHECK(xi.density(centre) == 1.0f);
    CHECK(mi.density(centre) == Approx(1.0).epsilon(0.3));
    CHECK(surfaceLike > active / 20);
}

TEST_CASE("Results are bit-identical for any thread count: the same .vdb bytes from 1, 2, 3 and 8 threads", "[cpu]") {
    // Enough segments that TBB splits the slices into many tasks (64
    // segments each at most), and enough bricks that merging them is parallel too.
    GenerateOptions g;
    g.pattern = WeavePattern::Twill;
    g.crossings = 1600;
    const Garment garment = generateGarment(g);
    SliceOptions opt;
    opt.radius = garment.yarnRadius;
    opt.twist = 2.0;
    const SlicePlan plan = planSlices(garment, opt);
    const VoxelGrid grid = makeGrid(plan, 256, 0);
    REQUIRE(plan.segments.size() >= 64 * 32);

    const fs::path dir = fs::temp_directory_path() / ("yv_threads_" + std::to_string(getpid()));
    fs::create_directories(dir);
    // Whether TBB's workers wake before the calling thread has taken every
    // task is the scheduler's, on a loaded machine too: the runs asked for
    // several threads must together have run on at least 2.
    std::uint64_t mostThreadsRan = 0;
    for (Reduce r : {Reduce::Mean, Reduce::Max}) {
        std::vector<std::uint8_t> first;
        for (int threads : {1, 2, 3, 8}) {
            // global_control lifts TBB's thread limit past the core count; the
            // arena then has that many slots, so 8 threads run even on 2 cores.
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
            tbb::task_arena arena(threads);
            CpuVoxelizeCounters counters;
            const fs::path vdb = dir / ("t" + std::to_string(threads) + ".vdb");
            arena.execute([&] {
                const BrickVolume v = voxelizeCpu(plan, makeFiberCrossSection(), grid, settings(r), &counters);
                REQUIRE(v.bricks.size() > 1000);
                writeVdb(vdb.string(), v, VolumeMetadata{});
            });
            INFO(toString(r) << ", " << threads << " threads: " << counters.tasks << " tasks on " << counters.threads
                             << " threads");
            CHECK(counters.tasks >= 8);
            if (threads > 1) mostThreadsRan = std::max(mostThreadsRan, std::uint64_t(counters.threads));
            const std::vector<std::uint8_t> bytes = test::vdbBytesWithoutUuid(vdb);
            const bool sameBytes = first.empty() || bytes == first; // not CHECKed directly: megabytes to print
            CHECK(sameBytes);
            if (first.empty()) first = bytes;
        }
    }
    CHECK(mostThreadsRan >= 2);
    fs::remove_all(dir);
}

namespace {

/// Resolves each region's accumulators as they come, keeping the bricks.
class ResolvingSink : public RegionSink {
  public:
    explicit ResolvingSink(Reduce reduce) : reduce_(reduce) {}
    void consume(const ZoomRegion&, PackedBricks&&) override { FAIL("the CPU backend hands over accumulators"); }
    void consumeAccumulators(const ZoomRegion& region, std::vector<BrickAccumulator>&& accumulators) override {
        ++regions;
        largestRegion = std::max(largestRegion, accumulators.size());
        for (const BrickAccumulator& a : accumulators) {
            const glm::ivec3 corner = brickCoord(a.key) * 8;
            // Every brick lies inside the region that produced it.
            inside = inside && glm::all(glm::greaterThanEqual(corner, region.min)) &&
                     glm::all(glm::lessThanEqual(corner + 8, region.max));
            VoxelBrick b;
            if (resolveBrick(reduce_, Overlap::Clamp, a, b, nullptr)) bricks.push_back(b);
        }
    }
    std::vector<VoxelBrick> bricks;
    std::size_t regions = 0, largestRegion = 0;
    bool inside = true;

  private:
    Reduce reduce_;
};

} // namespace

TEST_CASE("CPU backend out of core: many zoom regions give the whole-volume reference bit for bit", "[cpu][out-of-core]") {
    const test::GeneratedRun run = test::generatedRun(WeavePattern::Knit, GarmentShape::Cylinder, 400, 1.0, 192);
    const SlicePlan& plan = run.plan;
    const VoxelGrid& grid = run.grid;
    const CrossSection xs = makeFiberCrossSection();
    for (Reduce r : {Reduce::Mean, Reduce::Max}) {
        const BrickVolume whole = voxelizeCpu(plan, xs, grid, settings(r));
        // A budget far below the garment's samples: dozens of regions, and
        // segments that cross region boundaries are sampled in each.
        CpuRegionBackend backend(plan, xs, grid, settings(r), 40000);
        const ZoomPlan zoom = planZoomRegions(plan, grid, xs, {backend.fragmentBudget(), backend.maxRegionSize(), 1});
        ResolvingSink sink(r);
        backend.run(zoom.regions, sink);
        INFO(toString(r) << ": " << zoom.regions.size() << " regions, largest " << sink.largestRegion << " bricks of "
                         << whole.bricks.size());
        CHECK(zoom.regions.size() >= 16);
        CHECK(sink.regions == zoom.regions.size());
        CHECK(backend.counters().regions == zoom.regions.size());
        CHECK(sink.inside);
        CHECK(sink.largestRegion < whole.bricks.size() / 4);
        std::sort(sink.bricks.begin(), sink.bricks.end(), [](const VoxelBrick& a, const VoxelBrick& b) { return a.key < b.key; });
        REQUIRE(sink.bricks.size() == whole.bricks.size());
        std::size_t mismatches = 0;
        for (std::size_t i = 0; i < whole.bricks.size(); ++i) {
            const VoxelBrick &a = sink.bricks[i], &b = whole.bricks[i];
            mismatches += a.key != b.key || a.activeMask != b.activeMask ||
                          std::memcmp(a.density.data(), b.density.data(), sizeof(float) * kBrickVoxels) != 0 ||
                          std::memcmp(a.orientation.data(), b.orientation.data(), sizeof(glm::vec3) * kBrickVoxels) != 0;
        }
        CHECK(mismatches == 0);
    }
}

TEST_CASE("Skipping footprints beyond the texture's support changes no sample", "[cpu][sampling]") {
    const test::GeneratedRun run = test::generatedRun(WeavePattern::Knit, GarmentShape::Sphere, 64, 1.5, 160);
    const SlicePlan& plan = run.plan;
    const VoxelGrid& grid = run.grid;

    // Textures whose fibre reaches the square's edges and corners, where the
    // bilinear rule clamps, as well as the plies' disk.
    std::vector<CrossSection> textures;
    textures.push_back(makeFiberCrossSection(64));
    CrossSection full = makeFiberCrossSection(32);
    std::fill(full.density.begin(), full.density.end(), std::uint8_t(255));
    textures.push_back(full);
    CrossSection corners = full;
    std::fill(corners.density.begin(), corners.density.end(), std::uint8_t(0));
    corners.density[0] = 255;                                           // (0, 0)
    corners.density[corners.size * corners.size - 1] = 200;             // (size-1, size-1)
    corners.density[std::size_t(corners.size / 2) * corners.size] = 90; // the left edge's middle
    textures.push_back(corners);

    for (const CrossSection& xs : textures) {
        const double support = textureSupport(xs);
        INFO("texture " << xs.size << " texels, support " << support);
        // The plies' disk leaves the square's corners to be skipped; the others reach them.
        if (&xs == &textures.front()) CHECK(support < 1.1);
        else CHECK(support > 1.4);
        std::size_t total = 0, mismatches = 0;
        for (std::size_t s = 0; s < plan.segments.size(); s += 7) {
            const SegmentRecord& seg = plan.segments[s];
            for (std::uint32_t k = 0; k < seg.sliceCount; ++k) {
                const Slice slice = placeSlice(seg, k);
                std::vector<SliceSample> skipping, all;
                sampleSlice(slice, run.radius, xs, support, grid, 1, [&](const SliceSample& x) { skipping.push_back(x); });
                sampleSlice(slice, run.radius, xs, HUGE_VAL, grid, 1, [&](const SliceSample& x) { all.push_back(x); });
                total += all.size();
                if (skipping.size() != all.size()) {
                    ++mismatches;
                    continue;
                }
                for (std::size_t i = 0; i < all.size(); ++i)
                    mismatches += skipping[i].voxel != all[i].voxel || skipping[i].volumeFraction != all[i].volumeFraction ||
                                  skipping[i].density != all[i].density;
            }
        }
        CHECK(total > 1000);
        CHECK(mismatches == 0);
    }
}

TEST_CASE("Principal axis of a structure tensor", "[cpu]") {
    const glm::dvec3 d = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
    const glm::dvec3 e = glm::normalize(glm::cross(d, glm::dvec3(1, 0, 0)));
    // Two fibres along +d and -d plus a weaker one along e: the axis is d.
    double t[6] = {};
    auto add = [&](glm::dvec3 o, double w) {
        t[0] += w * o.x * o.x, t[1] += w * o.y * o.y, t[2] += w * o.z * o.z;
        t[3] += w * o.x * o.y, t[4] += w * o.x * o.z, t[5] += w * o.y * o.z;
    };
    add(d, 1.0), add(-d, 1.0), add(e, 0.5);
    CHECK(std::abs(glm::dot(principalAxis(t), d)) == Approx(1.0).epsilon(1e-9));
}

TEST_CASE("Axis codes round-trip within a hundredth of a degree", "[cpu]") {
    for (glm::dvec3 v : {glm::dvec3(0, 0, 1), glm::dvec3(1, 0, 0), glm::dvec3(0.2, -0.9, 0.1), glm::dvec3(-0.3, 0.3, -0.9)}) {
        v = glm::normalize(v);
        const glm::dvec3 back = decodeAxis(encodeAxis(v));
        CHECK(std::acos(std::min(1.0, std::abs(glm::dot(back, v)))) < 1e-2 * M_PI / 180.0 * 5);
        CHECK(encodeAxis(v) == encodeAxis(-v));
    }
}
