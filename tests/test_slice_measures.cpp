// A segment's slices measured in lanes (measureSlices and the zoom plan's
// sliceVoxels: SSE2's two, AVX's four) against one at a time (sliceOnCurve,
// glm): the same bits for every measure, on every kind of segment (straight,
// bent, a cusp, a segment that does not move) and every slice count, whole
// groups of lanes or not.
#include "core/cpu_features.h"
#include "garment/catmull_rom.h"
#include "garment/slice_measures.h"

#include <catch2/catch.hpp>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

using namespace yv;

namespace {

SegmentRecord segmentOf(const SegmentPoints& points, std::uint32_t slices) {
    SegmentRecord s{};
    s.points = points;
    s.sliceCount = slices;
    return s;
}

/// Random segments of a yarn's scale and shape, and the awkward ones.
std::vector<SegmentPoints> testSegments() {
    std::vector<SegmentPoints> all = {
        {glm::dvec3(-1, 0, 0), glm::dvec3(0, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(2, 0, 0)},         // straight, along x
        {glm::dvec3(0, 0, -1), glm::dvec3(0, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, 0, 2)},         // straight, along z
        {glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 0)},          // turns straight back (cusps)
        {glm::dvec3(0.5, 0.5, 0.5), glm::dvec3(0.5, 0.5, 0.5), glm::dvec3(0.5, 0.5, 0.5), glm::dvec3(0.5, 0.5, 0.5)}, // does not move
        {glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(1, 1, 0)},          // a tight bend
    };
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> coordinate(-40.0, 40.0), step(-0.6, 0.6);
    for (int i = 0; i < 400; ++i) {
        glm::dvec3 p(coordinate(rng), coordinate(rng), coordinate(rng));
        SegmentPoints s;
        for (auto& q : s) {
            q = p;
            p += glm::dvec3(0.3, 0.0, 0.0) + glm::dvec3(step(rng), step(rng), step(rng));
        }
        all.push_back(s);
    }
    return all;
}

bool sameBits(const SegmentMeasures& a, const SegmentMeasures& b) {
    return std::memcmp(&a.length, &b.length, sizeof(double)) == 0 && std::memcmp(&a.spacing, &b.spacing, sizeof(double)) == 0 &&
           std::memcmp(&a.reach, &b.reach, sizeof(double)) == 0 &&
           std::memcmp(&a.centerMin, &b.centerMin, sizeof(glm::dvec3)) == 0 &&
           std::memcmp(&a.centerMax, &b.centerMax, sizeof(glm::dvec3)) == 0 &&
           std::memcmp(&a.dominantSum, &b.dominantSum, sizeof(double)) == 0 && a.flat == b.flat;
}

} // namespace

TEST_CASE("measureSlices gives one slice at a time's bits in every lane, for every slice count", "[slices]") {
    std::vector<SliceLanes> paths = {SliceLanes::Sse2, SliceLanes::Auto};
    if (cpuHasAvx()) paths.push_back(SliceLanes::Avx);
    else WARN("this CPU has no AVX: the AVX lanes are not checked here");
    const double halfDiagonal = 0.1 * std::sqrt(2.0);
    std::size_t compared = 0, flat = 0;
    for (const SegmentPoints& points : testSegments())
        for (std::uint32_t slices : {1u, 2u, 3u, 4u, 5u, 7u, 8u, 9u, 25u, 50u, 51u}) {
            const SegmentRecord segment = segmentOf(points, slices);
            const SegmentMeasures want = measureSlices(segment, halfDiagonal, SliceLanes::Scalar);
            flat += want.flat;
            for (SliceLanes lanes : paths) {
                const SegmentMeasures got = measureSlices(segment, halfDiagonal, lanes);
                INFO("slices " << slices << ", lanes " << int(lanes) << ": length " << got.length << " want "
                               << want.length << ", reach " << got.reach << " want " << want.reach << ", dominant sum "
                               << got.dominantSum << " want " << want.dominantSum);
                CHECK(sameBits(got, want));
                ++compared;
            }
        }
    CHECK(compared > 8000);
    CHECK(flat > 0); // the segment that does not move was measured flat in every path
}

TEST_CASE("measureSlices: a straight segment's length, bounds and reach are the analytic ones", "[slices]") {
    // Along x from 0 to 1 at uniform speed: slice k's centre at (k + 0.5) / K.
    const SegmentRecord segment =
        segmentOf({glm::dvec3(-1, 0, 0), glm::dvec3(0, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(2, 0, 0)}, 10);
    const double halfDiagonal = 0.25;
    for (SliceLanes lanes : {SliceLanes::Scalar, SliceLanes::Sse2, SliceLanes::Auto}) {
        const SegmentMeasures m = measureSlices(segment, halfDiagonal, lanes);
        CHECK(m.length == Approx(1.0).epsilon(1e-12));
        CHECK(m.spacing == Approx(0.1).epsilon(1e-12));
        CHECK(m.centerMin.x == Approx(0.05).epsilon(1e-12));
        CHECK(m.centerMax.x == Approx(0.95).epsilon(1e-12));
        CHECK(m.centerMin.y == 0.0);
        // Straight: the slab's depth is its thickness, along x.
        CHECK(m.reach == Approx(halfDiagonal + 0.5 * 0.1).epsilon(1e-12));
        // Along an axis: each slice's unit tangent is that axis.
        CHECK(m.dominantSum == Approx(10.0).epsilon(1e-12));
        CHECK_FALSE(m.flat);
    }
}

TEST_CASE("sliceVoxels gives one slice at a time's voxels in every lane, for any run of slices", "[slices]") {
    std::vector<SliceLanes> paths = {SliceLanes::Scalar, SliceLanes::Sse2, SliceLanes::Auto};
    if (cpuHasAvx()) paths.push_back(SliceLanes::Avx);
    // Voxels of two sizes, one a power of two, from an origin inside the segments: floors below zero too.
    const glm::dvec3 origin(-20.25, -10.5, 3.0);
    std::size_t compared = 0, negative = 0, outsideCentreBounds = 0;
    for (double voxelSize : {0.0625, 0.37})
        for (const SegmentPoints& points : testSegments())
            for (std::uint32_t slices : {1u, 3u, 8u, 50u, 51u}) {
                const SegmentRecord segment = segmentOf(points, slices);
                const double inv = 1.0 / voxelSize;
                // The voxel of each slice's centre as sliceOnCurve places it.
                std::vector<glm::ivec3> want(slices);
                for (std::uint32_t k = 0; k < slices; ++k)
                    want[k] = glm::ivec3(glm::floor((sliceOnCurve(segment, k).center - origin) * inv));
                // The voxels of the centres' bounds (measureSlices) bound every slice's.
                const SegmentMeasures m = measureSlices(segment, 0.1);
                const glm::ivec3 lo(glm::floor((m.centerMin - origin) * inv)), hi(glm::floor((m.centerMax - origin) * inv));
                for (const glm::ivec3& v : want)
                    outsideCentreBounds += glm::any(glm::lessThan(v, lo)) || glm::any(glm::greaterThan(v, hi));
                for (SliceLanes lanes : paths)
                    for (std::uint32_t first : {0u, 1u, slices / 2}) {
                        const std::uint32_t count = slices - first;
                        std::vector<glm::ivec3> got(count);
                        sliceVoxels(segment, first, count, origin, inv, got.data(), lanes);
                        for (std::uint32_t j = 0; j < count; ++j) {
                            INFO("slices " << slices << ", first " << first << ", slice " << first + j << ", lanes "
                                           << int(lanes) << ", voxel size " << voxelSize);
                            CHECK(got[j] == want[first + j]);
                            negative += want[first + j].x < 0;
                            ++compared;
                        }
                    }
            }
    CHECK(compared > 100000);
    CHECK(negative > 0); // centres before the origin: floor, not truncation
    CHECK(outsideCentreBounds == 0);
}

TEST_CASE("fastestCurveSpeed gives the scalar loop's bits in every lane", "[slices]") {
    std::vector<SliceLanes> paths = {SliceLanes::Scalar, SliceLanes::Sse2, SliceLanes::Auto};
    if (cpuHasAvx()) paths.push_back(SliceLanes::Avx);
    std::size_t compared = 0;
    for (const SegmentPoints& points : testSegments()) {
        // What planSlices took before: one speed at a time, the largest kept.
        double want = 0.0;
        for (int j = 0; j <= 16; ++j) want = std::max(want, glm::length(evalCatmullRomDerivative(points, j / 16.0)));
        for (SliceLanes lanes : paths) {
            const double got = fastestCurveSpeed(points, lanes);
            INFO("lanes " << int(lanes) << ": " << got << " want " << want);
            CHECK(std::memcmp(&got, &want, sizeof(double)) == 0);
            ++compared;
        }
    }
    CHECK(compared > 1000);
    // Along x at unit speed, the analytic answer.
    CHECK(fastestCurveSpeed({glm::dvec3(-1, 0, 0), glm::dvec3(0, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(2, 0, 0)}) ==
          Approx(1.0).epsilon(1e-12));
}

TEST_CASE("sliceAxes gives sliceOnCurve's centre, tangent and thickness in every lane", "[slices]") {
    std::vector<SliceLanes> paths = {SliceLanes::Scalar, SliceLanes::Sse2, SliceLanes::Auto};
    if (cpuHasAvx()) paths.push_back(SliceLanes::Avx);
    std::size_t compared = 0;
    const std::vector<SegmentPoints> segments = testSegments();
    for (std::size_t s = 0; s < segments.size(); ++s) {
        if (s == 2 || s == 3) continue; // the cusp's ends and the segment that does not move have no tangent
        for (std::uint32_t slices : {1u, 3u, 8u, 50u, 51u}) {
            const SegmentRecord segment = segmentOf(segments[s], slices);
            for (SliceLanes lanes : paths)
                for (std::uint32_t first : {0u, 1u, slices / 2}) {
                    const std::uint32_t count = slices - first;
                    std::vector<SliceAxis> got(count);
                    sliceAxes(segment, first, count, got.data(), lanes);
                    for (std::uint32_t j = 0; j < count; ++j) {
                        const SliceOnCurve want = sliceOnCurve(segment, first + j);
                        INFO("segment " << s << ", slices " << slices << ", slice " << first + j << ", lanes " << int(lanes));
                        CHECK(std::memcmp(&got[j].centre, &want.center, sizeof(glm::dvec3)) == 0);
                        CHECK(std::memcmp(&got[j].tangent, &want.tangent, sizeof(glm::dvec3)) == 0);
                        CHECK(std::memcmp(&got[j].thickness, &want.thickness, sizeof(double)) == 0);
                        ++compared;
                    }
                }
        }
    }
    CHECK(compared > 50000);
}
