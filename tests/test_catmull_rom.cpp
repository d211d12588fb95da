#include "garment/catmull_rom.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

using namespace yv;

namespace {
double dist(glm::dvec3 a, glm::dvec3 b) { return glm::length(a - b); }
} // namespace

TEST_CASE("Catmull-Rom passes through its knots with the paper's tangents", "[catmull-rom]") {
    Yarn yarn;
    yarn.points = {{0, 0, 0}, {1, 2, 0}, {3, 1, 1}, {4, 4, -1}, {6, 3, 0}};
    for (std::size_t s = 1; s + 2 < yarn.points.size(); ++s) {
        const SegmentPoints p = segmentPoints(yarn, s, CurveType::CatmullRom);
        const auto& P = yarn.points;
        CHECK(dist(evalCatmullRom(p, 0.0), P[s]) < 1e-12);
        CHECK(dist(evalCatmullRom(p, 1.0), P[s + 1]) < 1e-12);
        CHECK(dist(evalCatmullRomDerivative(p, 0.0), (P[s + 1] - P[s - 1]) / 2.0) < 1e-12);
        CHECK(dist(evalCatmullRomDerivative(p, 1.0), (P[s + 2] - P[s]) / 2.0) < 1e-12);
    }
}

TEST_CASE("Catmull-Rom derivative matches finite differences", "[catmull-rom]") {
    const SegmentPoints p = {glm::dvec3(0, 0, 0), glm::dvec3(1, 2, 0), glm::dvec3(3, 1, 1), glm::dvec3(4, 4, -1)};
    for (double t : {0.1, 0.37, 0.5, 0.9}) {
        const double e = 1e-6;
        const glm::dvec3 fd = (evalCatmullRom(p, t + e) - evalCatmullRom(p, t - e)) / (2 * e);
        CHECK(dist(fd, evalCatmullRomDerivative(p, t)) < 1e-6);
    }
}

TEST_CASE("Open ends estimate tangents from the end chord", "[catmull-rom]") {
    Yarn yarn;
    yarn.points = {{0, 0, 0}, {2, 0, 0}, {3, 1, 0}};
    const SegmentPoints first = segmentPoints(yarn, 0, CurveType::CatmullRom);
    CHECK(dist(evalCatmullRomDerivative(first, 0.0), glm::dvec3(2, 0, 0)) < 1e-12);
    const SegmentPoints last = segmentPoints(yarn, 1, CurveType::CatmullRom);
    CHECK(dist(evalCatmullRomDerivative(last, 1.0), glm::dvec3(1, 1, 0)) < 1e-12);
    CHECK(dist(evalCatmullRom(last, 1.0), glm::dvec3(3, 1, 0)) < 1e-12);
}

TEST_CASE("Closed yarns wrap around and polylines stay straight", "[catmull-rom]") {
    Yarn loop;
    loop.closed = true;
    loop.points = {{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
    const SegmentPoints wrap = segmentPoints(loop, 3, CurveType::CatmullRom);
    CHECK(dist(evalCatmullRom(wrap, 1.0), loop.points[0]) < 1e-12);
    CHECK(dist(evalCatmullRomDerivative(wrap, 1.0), (loop.points[1] - loop.points[3]) / 2.0) < 1e-12);

    Yarn poly;
    poly.points = {{0, 0, 0}, {1, 3, 0}, {4, 3, 2}};
    const SegmentPoints p = segmentPoints(poly, 1, CurveType::Polyline);
    for (double t : {0.25, 0.5, 0.75})
        CHECK(dist(evalCatmullRom(p, t), poly.points[1] + t * (poly.points[2] - poly.points[1])) < 1e-12);
}
