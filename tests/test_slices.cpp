#include "garment/slices.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include <cmath>
#include <cstring>

using namespace yv;

namespace {

Garment helix() {
    Garment g;
    Yarn y;
    for (int i = 0; i < 40; ++i) y.points.push_back({std::cos(i * 0.4), std::sin(i * 0.4), 0.15 * i});
    g.yarns.push_back(y);
    return g;
}

} // namespace

TEST_CASE("Slice frames stay orthonormal and do not flip on a curved yarn", "[slices]") {
    SliceOptions opt;
    opt.slicesPerSegment = 10;
    opt.radius = 0.05;
    opt.twist = 0.0;
    const SlicePlan plan = planSlices(helix(), opt);
    REQUIRE(plan.sliceCount == 39u * 10u);
    glm::dvec3 prevUp(0.0);
    double worstTurn = 0.0;
    for (const SegmentRecord& seg : plan.segments)
        for (std::uint32_t k = 0; k < seg.sliceCount; ++k) {
            const Slice s = placeSlice(seg, k);
            CHECK(std::abs(glm::length(s.tangent) - 1) < 1e-9);
            CHECK(std::abs(glm::length(s.right) - 1) < 1e-9);
            CHECK(std::abs(glm::length(s.up) - 1) < 1e-9);
            CHECK(std::abs(glm::dot(s.tangent, s.right)) < 1e-9);
            CHECK(std::abs(glm::dot(s.tangent, s.up)) < 1e-9);
            CHECK(glm::length(glm::cross(s.right, s.up) - s.tangent) < 1e-9);
            if (prevUp != glm::dvec3(0.0)) worstTurn = std::max(worstTurn, std::acos(std::min(1.0, glm::dot(prevUp, s.right))));
            prevUp = s.right;
        }
    // Parallel transport turns the frame only as much as the tangent turns
    // between neighbouring slices (a few degrees here), never by a flip.
    CHECK(worstTurn < 0.1);
}

TEST_CASE("Twist turns the frame by twist times arc length", "[slices]") {
    SliceOptions opt;
    opt.slicesPerSegment = 4;
    opt.radius = 0.1;
    opt.twist = 0.5;
    const SlicePlan plan = planSlices(test::straightYarn({0, 0, 0}, {0, 0, 1}, 6), opt);
    const Slice first = placeSlice(plan.segments[0], 0);
    const Slice later = placeSlice(plan.segments[3], 2);
    const double arc = 3.0 + 2.5 / 4.0 - 0.5 / 4.0;
    const double angle = std::atan2(glm::dot(glm::cross(first.right, later.right), first.tangent), glm::dot(first.right, later.right));
    CHECK(angle == Approx(std::remainder(opt.twist * arc, 2 * M_PI)).margin(1e-9));
    CHECK(first.thickness == Approx(0.25).epsilon(1e-12));
}

TEST_CASE("Slice thicknesses add up to the yarn length", "[slices]") {
    SliceOptions opt;
    opt.slicesPerSegment = 7;
    opt.radius = 0.1;
    const SlicePlan plan = planSlices(test::straightYarn({1, 2, 3}, {1, 1, 0.5}, 9), opt);
    double total = 0.0;
    for (const SegmentRecord& seg : plan.segments)
        for (std::uint32_t k = 0; k < seg.sliceCount; ++k) total += placeSlice(seg, k).thickness;
    CHECK(total == Approx(9.0).epsilon(1e-12));
}

TEST_CASE("Slice spacing picks the slice count per segment", "[slices]") {
    SliceOptions opt;
    opt.spacing = 0.1;
    opt.radius = 0.1;
    const SlicePlan plan = planSlices(test::straightYarn({0, 0, 0}, {1, 0, 0}, 3), opt);
    for (const SegmentRecord& seg : plan.segments) CHECK(seg.sliceCount == 10u);
    CHECK(plan.fewestSlices == 10u);
    CHECK(plan.mostSlices == 10u);
    CHECK(plan.uniformSlices() == 10u);
}

TEST_CASE("The plan's yarn length and fewest and most slices are its segments'", "[slices]") {
    // Segments of different lengths (the curve's spans grow), so different slice counts at one spacing.
    Garment g;
    g.yarns.push_back(Yarn{{{0, 0, 0}, {0.3, 0, 0}, {1, 0.2, 0}, {2.5, 0, 0.4}, {5, 1, 0}}, false});
    g.yarns.push_back(Yarn{{{0, 2, 0}, {1, 2, 0}, {1, 3, 0}, {0, 3, 0}}, true});
    SliceOptions opt;
    opt.spacing = 0.05;
    opt.radius = 0.1;
    const SlicePlan plan = planSlices(g, opt);
    double length = 0.0;
    std::uint32_t fewest = ~0u, most = 0;
    for (const SegmentRecord& seg : plan.segments) {
        length += seg.length;
        fewest = std::min(fewest, seg.sliceCount);
        most = std::max(most, seg.sliceCount);
    }
    CHECK(fewest < most);
    CHECK(plan.fewestSlices == fewest);
    CHECK(plan.mostSlices == most);
    CHECK(plan.uniformSlices() == 0u);
    CHECK(plan.yarnLength == length); // the same sum, in the same order
    CHECK(planSlices(Garment{}, opt).mostSlices == 0u);
}

TEST_CASE("Fibre direction follows the paper's eq. 1", "[slices]") {
    SliceOptions opt;
    opt.slicesPerSegment = 50;
    opt.radius = 0.5;
    opt.twist = 2.0;
    const SlicePlan plan = planSlices(test::straightYarn({0, 0, 0}, {0, 0, 1}, 4), opt);
    const Slice s = placeSlice(plan.segments[1], 10);
    for (double rho : {0.0, 0.1, 0.3, 0.45}) {
        const glm::dvec3 d = fiberDirection(s, rho, 0.0);
        CHECK(std::acos(glm::dot(d, s.tangent)) == Approx(std::atan(rho * opt.twist)).margin(2e-3));
        // The fibre turns about the axis in the twist's sense: towards +up at +right.
        if (rho > 0) CHECK(glm::dot(d, s.up) > 0);
    }
}

TEST_CASE("Bad yarns give clear errors", "[slices]") {
    Garment g;
    g.yarns.push_back(Yarn{{{0, 0, 0}}, false});
    SliceOptions opt;
    CHECK_THROWS_WITH(planSlices(g, opt), Catch::Contains("yarn 0") && Catch::Contains("at least 2"));
    Garment same;
    same.yarns.push_back(Yarn{{{1, 1, 1}, {1, 1, 1}}, false});
    CHECK_THROWS_WITH(planSlices(same, opt), Catch::Contains("yarn 0") && Catch::Contains("tangent"));
}

TEST_CASE("Slices of many yarns planned side by side keep file order, per-yarn frames and global offsets", "[slices]") {
    // Enough yarns to be planned on several threads.
    Garment g;
    for (int i = 0; i < 400; ++i) {
        Yarn y;
        for (int j = 0; j < 9; ++j) y.points.push_back({0.5 * j, std::sin(0.7 * j + i), 0.2 * i});
        y.closed = i % 3 == 0;
        g.yarns.push_back(y);
    }
    SliceOptions opt;
    opt.spacing = 0.13;
    opt.radius = 0.05;
    opt.twist = 1.5;
    const SlicePlan plan = planSlices(g, opt);
    std::uint64_t nextSlice = 0;
    for (std::size_t i = 0; i < plan.segments.size(); ++i) {
        const SegmentRecord& s = plan.segments[i];
        const bool first = i == 0 || plan.segments[i - 1].yarn != s.yarn;
        INFO("segment " << i << " of yarn " << s.yarn);
        REQUIRE(s.firstSlice == nextSlice);
        nextSlice += s.sliceCount;
        if (first) {
            CHECK(s.arcStart == 0.0);
            CHECK((i == 0 ? 0u : plan.segments[i - 1].yarn + 1) == s.yarn);
        } else {
            const SegmentRecord& prev = plan.segments[i - 1];
            CHECK(s.arcStart == prev.arcStart + prev.length);
            CHECK(s.twistRate == prev.twistRate);
        }
        CHECK(std::abs(glm::dot(s.knotUp, s.knotTangent)) < 1e-9);
        CHECK(s.phaseStart >= 0.0);
        CHECK(s.phaseStart < 2.0 * M_PI);
    }
    CHECK(nextSlice == plan.sliceCount);
    CHECK(plan.segments.back().yarn == 399u);
    // The same garment planned once more gives the same bits.
    const SlicePlan again = planSlices(g, opt);
    REQUIRE(again.segments.size() == plan.segments.size());
    CHECK(std::memcmp(again.segments.data(), plan.segments.data(), plan.segments.size() * sizeof(SegmentRecord)) == 0);
    CHECK(again.maxReach == plan.maxReach);
    CHECK(again.centerMin == plan.centerMin);

    // Of two yarns without a tangent, the first in the file is named. (A knot
    // whose neighbours coincide is a cusp, sliced with its one-sided tangent:
    // here four points coincide, so segment 2 does not move at all.)
    Garment bad = g;
    for (std::size_t y : {std::size_t(321), std::size_t(77)})
        for (int k : {2, 3, 4}) bad.yarns[y].points[k] = bad.yarns[y].points[1];
    CHECK_THROWS_WITH(planSlices(bad, opt), Catch::StartsWith("yarn 77: "));
}
