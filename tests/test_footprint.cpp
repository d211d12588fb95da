// The disk cross-section's exact footprint coverage (core/footprint.h)
// against a brute-force count of points of the parallelogram inside the disk.
#include "core/footprint.h"

#include <catch2/catch.hpp>

#include <random>

namespace {

// Share of a grid of n x n points of the parallelogram c + s u + t v
// (s, t in [-1/2, 1/2)) that lie within r of the origin.
double countedCoverage(glm::dvec2 c, glm::dvec2 u, glm::dvec2 v, double r, int n) {
    long inside = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const glm::dvec2 p = c + ((i + 0.5) / n - 0.5) * u + ((j + 0.5) / n - 0.5) * v;
            inside += glm::dot(p, p) <= r * r;
        }
    return double(inside) / (double(n) * n);
}

} // namespace

TEST_CASE("Footprint: disk coverage equals the counted share of the parallelogram", "[footprint]") {
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    int partial = 0;
    for (int trial = 0; trial < 300; ++trial) {
        // Parallelograms from slivers to squares, about the circle's edge.
        const double scale = trial % 3 == 0 ? 0.1 : (trial % 3 == 1 ? 0.6 : 2.5);
        const glm::dvec2 u{scale * unit(random), scale * unit(random)}, v{scale * unit(random), scale * unit(random)};
        const glm::dvec2 c{1.3 * unit(random), 1.3 * unit(random)};
        const double exact = yv::diskCoverage(c, u, v, 1.0);
        const double counted = countedCoverage(c, u, v, 1.0, 600);
        INFO("trial " << trial << " c " << c.x << "," << c.y << " u " << u.x << "," << u.y << " v " << v.x << ","
                      << v.y);
        CHECK(exact == Approx(counted).margin(4e-3));
        // Either order of the edges (clockwise corners) gives the same area.
        CHECK(yv::diskCoverage(c, v, u, 1.0) == Approx(exact).margin(1e-12));
        partial += exact > 0.01 && exact < 0.99;
    }
    CHECK(partial > 100); // most trials cross the circle, where the arcs matter
}

TEST_CASE("Footprint: disk coverage of the special cases", "[footprint]") {
    // Wholly inside, wholly outside, the disk wholly inside a large square.
    CHECK(yv::diskCoverage({0.1, 0.2}, {0.2, 0.0}, {0.0, 0.2}, 1.0) == 1.0);
    CHECK(yv::diskCoverage({3.0, 0.0}, {0.5, 0.0}, {0.0, 0.5}, 1.0) == 0.0);
    CHECK(yv::diskCoverage({0.0, 0.0}, {4.0, 0.0}, {0.0, 4.0}, 1.0) == Approx(M_PI / 16.0).epsilon(1e-12));
    // A square centred on the circle's edge: half of it inside, to the
    // curvature's first order, and exactly the circular segment's share.
    const double h = 0.01;
    const double share = yv::diskCoverage({1.0, 0.0}, {h, 0.0}, {0.0, h}, 1.0);
    CHECK(share == Approx(countedCoverage({1.0, 0.0}, {h, 0.0}, {0.0, h}, 1.0, 2000)).margin(2e-3));
    // A corner exactly on the circle: the unit square [0, 1]^2 holds a quarter disk.
    CHECK(yv::diskCoverage({0.5, 0.5}, {1.0, 0.0}, {0.0, 1.0}, 1.0) == Approx(M_PI / 4.0).epsilon(1e-12));
    // A degenerate parallelogram covers nothing.
    CHECK(yv::diskCoverage({0.0, 0.0}, {1.0, 0.0}, {2.0, 0.0}, 1.0) == 0.0);
}
