// The GPU resolve (shaders/brick_resolve.comp) against the CPU's resolveBrick,
// voxel by voxel, on crafted accumulators: the edges of the brick, voxels over
// one under both overlap rules, tensors with a known principal axis, the max
// reduction, empty bricks, and enough slots to span several scan blocks.
#include "core/packed_bricks.h"
#include "cpu/cpu_voxelizer.h"
#include "gpu/brick_resolver.h"
#include "gpu/egl_context.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

using namespace yv;

namespace {

BrickAccumulator emptyBrick(Reduce reduce, glm::ivec3 brick) {
    return {brickKey(brick), std::vector<std::uint32_t>(std::size_t(wordsPerVoxel(reduce)) * kBrickVoxels, 0)};
}

void addMean(BrickAccumulator& acc, int voxel, double fraction, glm::dvec3 axis) {
    accumulateSample(Reduce::Mean, acc.words.data(), voxel, fraction, 1.0f, glm::normalize(axis));
}

void addMax(BrickAccumulator& acc, int voxel, float density, glm::dvec3 axis) {
    accumulateSample(Reduce::Max, acc.words.data(), voxel, 1.0, density, glm::normalize(axis));
}

bool relClose(double a, double b, double rel) { return std::abs(a - b) <= rel * std::max(std::abs(a), std::abs(b)); }

struct Resolved {
    std::vector<VoxelBrick> bricks;
    ResolveTally tally;
};

Resolved resolveOnCpu(Reduce reduce, Overlap overlap, const std::vector<BrickAccumulator>& accs) {
    Resolved r;
    for (const BrickAccumulator& a : accs) {
        VoxelBrick b;
        if (resolveBrick(reduce, overlap, a, b, &r.tally)) r.bricks.push_back(b);
    }
    return r;
}

Resolved resolveOnGpu(Reduce reduce, Overlap overlap, const std::vector<BrickAccumulator>& accs,
                      std::uint64_t* bytesRead = nullptr) {
    const GlContext context;
    GlBrickResolver resolver(reduce, overlap);
    PackedBricks packed;
    resolver.resolve(accs, packed);
    if (bytesRead) *bytesRead = resolver.bytesRead();
    Resolved r;
    r.bricks = unpackBricks(packed, &r.tally);
    return r;
}

/// Compares brick by brick and voxel by voxel; returns the first differences found (empty: none).
std::string differences(const Resolved& cpu, const Resolved& gpu) {
    std::ostringstream out;
    int reported = 0;
    auto report = [&](const std::string& what) {
        if (reported++ < 10) out << what << "\n";
    };
    if (cpu.bricks.size() != gpu.bricks.size())
        report("bricks: cpu " + std::to_string(cpu.bricks.size()) + ", gpu " + std::to_string(gpu.bricks.size()));
    for (std::size_t i = 0; i < std::min(cpu.bricks.size(), gpu.bricks.size()); ++i) {
        const VoxelBrick &c = cpu.bricks[i], &g = gpu.bricks[i];
        const std::string at = "brick " + std::to_string(i) + " key " + std::to_string(c.key);
        if (c.key != g.key) report(at + ": gpu key " + std::to_string(g.key));
        if (c.activeMask != g.activeMask) report(at + ": active masks differ");
        for (int v = 0; v < kBrickVoxels; ++v) {
            std::ostringstream voxel;
            voxel << at << " voxel " << v << ": ";
            if (!relClose(c.density[v], g.density[v], 1e-6))
                report(voxel.str() + "density cpu " + std::to_string(c.density[v]) + " gpu " + std::to_string(g.density[v]));
            const glm::vec3 d = glm::abs(c.orientation[v] - g.orientation[v]);
            if (std::max({d.x, d.y, d.z}) > 1e-4f) {
                voxel << "axis cpu (" << c.orientation[v].x << ", " << c.orientation[v].y << ", " << c.orientation[v].z
                      << ") gpu (" << g.orientation[v].x << ", " << g.orientation[v].y << ", " << g.orientation[v].z << ")";
                report(voxel.str());
            }
        }
    }
    const ResolveTally &c = cpu.tally, &g = gpu.tally;
    if (c.activeVoxels != g.activeVoxels)
        report("tally activeVoxels cpu " + std::to_string(c.activeVoxels) + " gpu " + std::to_string(g.activeVoxels));
    if (c.voxelsOverOne != g.voxelsOverOne)
        report("tally voxelsOverOne cpu " + std::to_string(c.voxelsOverOne) + " gpu " + std::to_string(g.voxelsOverOne));
    const double pairs[3][2] = {{c.densitySum, g.densitySum}, {c.rawDensitySum, g.rawDensitySum}, {c.excessOverOne, g.excessOverOne}};
    const char* names[3] = {"densitySum", "rawDensitySum", "excessOverOne"};
    for (int i = 0; i < 3; ++i)
        if (!relClose(pairs[i][0], pairs[i][1], 1e-9))
            report(std::string("tally ") + names[i] + " cpu " + std::to_string(pairs[i][0]) + " gpu " +
                   std::to_string(pairs[i][1]));
    return out.str();
}

/// Resolves on both sides and requires agreement; returns the GPU's result.
Resolved requireAgreement(Reduce reduce, Overlap overlap, const std::vector<BrickAccumulator>& accs) {
    const Resolved cpu = resolveOnCpu(reduce, overlap, accs);
    const Resolved gpu = resolveOnGpu(reduce, overlap, accs);
    const std::string diff = differences(cpu, gpu);
    INFO(toString(reduce) << ", " << toString(overlap) << ": " << accs.size() << " accumulators\n" << diff);
    CHECK(diff.empty());
    return gpu;
}

/// A random unit vector, both hemispheres.
glm::dvec3 randomAxis(std::mt19937_64& rng) {
    std::normal_distribution<double> n;
    glm::dvec3 v;
    do v = {n(rng), n(rng), n(rng)};
    while (glm::length(v) < 1e-3);
    return glm::normalize(v);
}

} // namespace

TEST_CASE("GPU resolve: single voxels at offset 0, 511 and inside a brick", "[gl][resolve]") {
    YV_REQUIRE_GL();
    const Overlap overlap = GENERATE(Overlap::Clamp, Overlap::Sum);
    std::vector<BrickAccumulator> accs;
    for (int v : {0, 511, brickOffset(3, 5, 2)}) {
        accs.push_back(emptyBrick(Reduce::Mean, {v, 7, 1}));
        addMean(accs.back(), v, 0.375, {0.2, -0.5, 1.0});
    }
    const Resolved gpu = requireAgreement(Reduce::Mean, overlap, accs);
    REQUIRE(gpu.bricks.size() == 3);
    CHECK(gpu.bricks[0].isActive(0));
    CHECK(gpu.bricks[1].isActive(511));
    for (const VoxelBrick& b : gpu.bricks) CHECK(b.activeCount() == 1);
    CHECK(gpu.tally.activeVoxels == 3);
}

TEST_CASE("GPU resolve: voxels over one clamp to 1 or keep their sum, and are tallied", "[gl][resolve]") {
    YV_REQUIRE_GL();
    const Overlap overlap = GENERATE(Overlap::Clamp, Overlap::Sum);
    BrickAccumulator acc = emptyBrick(Reduce::Mean, {2, 3, 4});
    // 1.0 exactly, within the over-one margin, past it, far past it.
    const double fractions[] = {1.0, 1.0 + 1.0 / 4096.0, 1.01, 1.5, 2.75, 0.25};
    for (int i = 0; i < 6; ++i) {
        addMean(acc, 40 * i + 7, fractions[i] / 2, {1, 0, 0});
        addMean(acc, 40 * i + 7, fractions[i] / 2, {0, 1, 0.1});
    }
    const Resolved gpu = requireAgreement(Reduce::Mean, overlap, {acc});
    REQUIRE(gpu.bricks.size() == 1);
    CHECK(gpu.tally.voxelsOverOne == 3);
    CHECK(gpu.tally.excessOverOne == Approx(1.0 / 4096.0 + 0.01 + 0.5 + 1.75).epsilon(1e-6));
    const float expected = overlap == Overlap::Clamp ? 1.0f : 2.75f;
    CHECK(gpu.bricks[0].density[40 * 4 + 7] == Approx(expected).epsilon(1e-6));
}

TEST_CASE("GPU resolve: structure tensors give their known principal axis, in the CPU's hemisphere", "[gl][resolve]") {
    YV_REQUIRE_GL();
    // A strong direction plus weaker ones across it: the principal axis is the
    // strong one, folded onto z > 0 (then y > 0, then x >= 0 on the rim).
    const glm::dvec3 axes[] = {{0, 0, -1}, {1, 2, -3}, {-1, 0, 0}, {0.3, -1, 0}, {1, 1, 1}, {-2, 0.5, 0.001}};
    BrickAccumulator acc = emptyBrick(Reduce::Mean, {0, 0, 0});
    for (int i = 0; i < 6; ++i) {
        const glm::dvec3 a = glm::normalize(axes[i]);
        const glm::dvec3 across = glm::normalize(glm::cross(a, std::abs(a.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
        addMean(acc, 80 * i + 3, 0.6, a);
        addMean(acc, 80 * i + 3, 0.15, across);
        addMean(acc, 80 * i + 3, 0.1, glm::cross(a, across));
    }
    const Resolved gpu = requireAgreement(Reduce::Mean, Overlap::Clamp, {acc});
    REQUIRE(gpu.bricks.size() == 1);
    for (int i = 0; i < 6; ++i) {
        const glm::dvec3 want = canonicalAxis(glm::normalize(axes[i]));
        const glm::vec3 got = gpu.bricks[0].orientation[80 * i + 3];
        INFO("axis " << i);
        CHECK(glm::length(glm::dvec3(got) - want) < 1e-4);
    }
}

TEST_CASE("GPU resolve: every voxel of random mean bricks, near-isotropic tensors included", "[gl][resolve]") {
    YV_REQUIRE_GL();
    const Overlap overlap = GENERATE(Overlap::Clamp, Overlap::Sum);
    std::mt19937_64 rng(7);
    std::vector<BrickAccumulator> accs;
    for (int b = 0; b < 6; ++b) {
        accs.push_back(emptyBrick(Reduce::Mean, {b, 2 * b, 1000 + b}));
        for (int v = 0; v < kBrickVoxels; ++v) {
            if (b == 3 && v % 3 != 0) continue; // a partly filled brick
            const int samples = 1 + int(rng() % 4);
            for (int s = 0; s < samples; ++s) addMean(accs.back(), v, double(rng() % 1000 + 1) / 1500.0, randomAxis(rng));
        }
    }
    // Three equal orthogonal samples: an isotropic tensor, whose axis is the
    // CPU's tie-break, not geometry.
    accs.push_back(emptyBrick(Reduce::Mean, {9, 9, 9}));
    for (glm::dvec3 a : {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)}) addMean(accs.back(), 100, 0.25, a);
    requireAgreement(Reduce::Mean, overlap, accs);
}

TEST_CASE("GPU resolve: the max reduction keeps the densest sample and its axis", "[gl][resolve]") {
    YV_REQUIRE_GL();
    std::mt19937_64 rng(11);
    std::vector<BrickAccumulator> accs;
    accs.push_back(emptyBrick(Reduce::Max, {1, 1, 1}));
    addMax(accs.back(), 0, 0.5f, {0, 1, -1});
    addMax(accs.back(), 511, 1.0f, {1, 0, 0});
    accs.push_back(emptyBrick(Reduce::Max, {1, 1, 2})); // stays empty
    accs.push_back(emptyBrick(Reduce::Max, {1, 1, 3}));
    for (int v = 0; v < kBrickVoxels; ++v)
        for (int s = 0; s < 3; ++s) addMax(accs.back(), v, float(rng() % 1000) / 997.0f, randomAxis(rng));
    const Resolved gpu = requireAgreement(Reduce::Max, Overlap::Clamp, accs);
    REQUIRE(gpu.bricks.size() == 2);
    CHECK(gpu.bricks[0].activeCount() == 2);
    CHECK(gpu.bricks[0].density[511] == 1.0f);
    CHECK(gpu.bricks[1].key == brickKey({1, 1, 3}));
}

TEST_CASE("GPU resolve: empty bricks are dropped on the GPU and nothing of them is read back", "[gl][resolve]") {
    YV_REQUIRE_GL();
    const Reduce reduce = GENERATE(Reduce::Mean, Reduce::Max);
    std::vector<BrickAccumulator> accs;
    for (int i = 0; i < 5; ++i) accs.push_back(emptyBrick(reduce, {i, 0, 0}));
    std::uint64_t bytesRead = 0;
    const Resolved gpu = resolveOnGpu(reduce, Overlap::Clamp, accs, &bytesRead);
    CHECK(gpu.bricks.empty());
    CHECK(gpu.tally.activeVoxels == 0);
    CHECK(bytesRead == 8); // the totals only
}

TEST_CASE("GPU resolve: thousands of sparse slots across scan blocks, packed in slot order", "[gl][resolve]") {
    YV_REQUIRE_GL();
    std::mt19937_64 rng(5);
    std::vector<BrickAccumulator> accs;
    std::uint64_t active = 0;
    for (int i = 0; i < 2600; ++i) { // three blocks of 1024 slots in the scan
        accs.push_back(emptyBrick(Reduce::Mean, {i % 13, i / 13, (i * 7) % 100}));
        if (i % 5 == 2) continue; // empty slots between kept ones
        const int voxels = 1 + int(rng() % 6);
        for (int n = 0; n < voxels; ++n) addMean(accs.back(), int(rng() % kBrickVoxels), 0.2, randomAxis(rng));
    }
    const Resolved gpu = requireAgreement(Reduce::Mean, Overlap::Clamp, accs);
    for (const VoxelBrick& b : gpu.bricks) active += b.activeCount();
    CHECK(gpu.bricks.size() == 2600 - 520);
    CHECK(active == gpu.tally.activeVoxels);
    // Proportional to active voxels: a header per kept brick, 16 bytes per voxel.
    std::uint64_t bytesRead = 0;
    resolveOnGpu(Reduce::Mean, Overlap::Clamp, accs, &bytesRead);
    CHECK(bytesRead == 8 + gpu.bricks.size() * sizeof(PackedBrickHeader) + active * sizeof(PackedVoxel));
}
