// Procedural garments: counts, determinism, the over/under pattern and the shapes.
#include "garment/generate.h"

#include "core/error.h"

#include <catch2/catch.hpp>
#include <glm/common.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

using namespace yv;

namespace {

constexpr double kPi = 3.14159265358979323846;

GenerateOptions options(WeavePattern p, GarmentShape s, std::uint64_t crossings, double jitter = 0.0) {
    GenerateOptions o;
    o.pattern = p;
    o.shape = s;
    o.crossings = crossings;
    o.jitter = jitter;
    return o;
}

bool sameBits(const Garment& a, const Garment& b) {
    if (a.yarns.size() != b.yarns.size()) return false;
    for (std::size_t i = 0; i < a.yarns.size(); ++i) {
        const auto& p = a.yarns[i].points;
        const auto& q = b.yarns[i].points;
        if (a.yarns[i].closed != b.yarns[i].closed || p.size() != q.size()) return false;
        if (!p.empty() && std::memcmp(p.data(), q.data(), p.size() * sizeof(p[0])) != 0) return false;
    }
    return true;
}

// Flat woven, no jitter: warp yarns run along x (constant y), weft yarns along y.
struct WovenCounts {
    std::size_t warps = 0, wefts = 0;
    bool consistent = true; // every warp crosses every weft exactly once
};
WovenCounts countWoven(const Garment& g) {
    WovenCounts c;
    for (const Yarn& y : g.yarns) (y.points.front().y == y.points.back().y && y.points.size() > 1 ? c.warps : c.wefts)++;
    for (const Yarn& y : g.yarns) {
        const bool warp = y.points.front().y == y.points.back().y && y.points.size() > 1;
        c.consistent = c.consistent && y.points.size() == (warp ? c.wefts : c.warps);
    }
    return c;
}

double radialXY(const glm::dvec3& p) { return std::sqrt(p.x * p.x + p.y * p.y); }
double norm(const glm::dvec3& p) { return std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z); }

} // namespace

TEST_CASE("pattern and shape names round-trip, and unknown names list the valid ones", "[generate]") {
    for (WeavePattern p : {WeavePattern::Plain, WeavePattern::Twill, WeavePattern::Satin, WeavePattern::Knit})
        CHECK(parseWeavePattern(toString(p)) == p);
    for (GarmentShape s : {GarmentShape::Flat, GarmentShape::Cylinder, GarmentShape::Sphere})
        CHECK(parseGarmentShape(toString(s)) == s);
    CHECK(std::string(toString(WeavePattern::Satin)) == "satin");
    CHECK(std::string(toString(GarmentShape::Cylinder)) == "cylinder");
    CHECK_THROWS_WITH(parseWeavePattern("tweed"), Catch::Contains("plain") && Catch::Contains("twill") &&
                                                      Catch::Contains("satin") && Catch::Contains("knit"));
    CHECK_THROWS_WITH(parseGarmentShape("cube"), Catch::Contains("flat") && Catch::Contains("cylinder") &&
                                                     Catch::Contains("sphere"));
    CHECK_THROWS_AS(parseWeavePattern("Plain"), Error);
}

TEST_CASE("bad options are refused", "[generate]") {
    GenerateOptions o;
    o.crossings = 0;
    CHECK_THROWS_AS(generateGarment(o), Error);
    o = GenerateOptions{};
    o.yarnSpacing = 0.0;
    CHECK_THROWS_AS(generateGarment(o), Error);
    o = GenerateOptions{};
    o.yarnRadius = -1.0;
    CHECK_THROWS_AS(generateGarment(o), Error);
    o = GenerateOptions{};
    o.jitter = std::nan("");
    CHECK_THROWS_AS(generateGarment(o), Error);
}

TEST_CASE("woven crossings: warps x wefts = requested, near-square grid", "[generate]") {
    for (WeavePattern p : {WeavePattern::Plain, WeavePattern::Twill, WeavePattern::Satin})
        for (std::uint64_t n : {4ull, 5ull, 10ull, 99ull, 1000ull, 4321ull, 20000ull}) {
            CAPTURE(toString(p), n);
            const Garment g = generateGarment(options(p, GarmentShape::Flat, n));
            const WovenCounts c = countWoven(g);
            REQUIRE(c.consistent);
            const std::uint64_t crossings = c.warps * c.wefts;
            CHECK(g.yarns.size() == c.warps + c.wefts);
            CHECK(g.controlPointCount() == 2 * crossings); // one point per crossing per yarn
            // warps = round(n / wefts): off by at most half a row.
            CHECK(2 * (crossings > n ? crossings - n : n - crossings) <= c.wefts);
            if (n >= 1000) CHECK(std::abs(double(crossings) - double(n)) <= 0.01 * double(n));
            const std::size_t big = std::max(c.warps, c.wefts), small = std::min(c.warps, c.wefts);
            CHECK(4 * big <= 5 * small + 4);
            CHECK(g.curveType == CurveType::CatmullRom);
            CHECK(g.yarnRadius == 0.3);
        }
    const WovenCounts four = countWoven(generateGarment(options(WeavePattern::Plain, GarmentShape::Flat, 4)));
    CHECK((four.warps == 2 && four.wefts == 2));
}

TEST_CASE("generation is deterministic and follows the seed", "[generate]") {
    for (WeavePattern p : {WeavePattern::Plain, WeavePattern::Twill, WeavePattern::Satin, WeavePattern::Knit})
        for (GarmentShape s : {GarmentShape::Flat, GarmentShape::Cylinder, GarmentShape::Sphere}) {
            CAPTURE(toString(p), toString(s));
            GenerateOptions o = options(p, s, 300, 0.05);
            const Garment a = generateGarment(o), b = generateGarment(o);
            CHECK(sameBits(a, b));
            o.seed = 2;
            CHECK_FALSE(sameBits(a, generateGarment(o)));
        }
    // Pinned bits: a change of generator, distribution or libm would show here.
    GenerateOptions o;
    o.crossings = 100;
    o.seed = 7;
    const glm::dvec3 flat = generateGarment(o).yarns[1].points[3];
    CHECK(flat == glm::dvec3(-0x1.80ecdca7e0748p+0, -0x1.be09d5376cdf6p+1, 0x1.20bc1608535a8p-2));
    o.pattern = WeavePattern::Twill;
    o.shape = GarmentShape::Cylinder;
    const glm::dvec3 cyl = generateGarment(o).yarns[1].points[3];
    CHECK(cyl == glm::dvec3(0x1.0fd4e0f2ee943p-8, 0x1.188da6fa51343p+1, -0x1.3e09d5376cdf6p+1));
    o.pattern = WeavePattern::Knit;
    o.shape = GarmentShape::Sphere;
    const glm::dvec3 sph = generateGarment(o).yarns[1].points[3];
    CHECK(sph == glm::dvec3(-0x1.084bb26c060dep+3, -0x1.507557aadff81p+2, 0x1.11457e71345a8p+3));
}

TEST_CASE("jitter stays within its fraction of the spacing", "[generate]") {
    GenerateOptions o = options(WeavePattern::Twill, GarmentShape::Flat, 500);
    o.yarnSpacing = 2.0;
    const Garment exact = generateGarment(o);
    o.jitter = 0.05;
    const Garment moved = generateGarment(o);
    REQUIRE(exact.yarns.size() == moved.yarns.size());
    double largest = 0.0;
    for (std::size_t i = 0; i < exact.yarns.size(); ++i)
        for (std::size_t k = 0; k < exact.yarns[i].points.size(); ++k) {
            const glm::dvec3 d = glm::abs(moved.yarns[i].points[k] - exact.yarns[i].points[k]);
            largest = std::max({largest, d.x, d.y, d.z});
        }
    CHECK(largest <= 0.05 * 2.0);
    CHECK(largest > 0.05 * 2.0 * 0.9); // the jitter does reach its range
}

TEST_CASE("plain weave: yarns alternate sides at consecutive crossings", "[generate]") {
    GenerateOptions o = options(WeavePattern::Plain, GarmentShape::Flat, 400, 0.02); // jitter << h
    const Garment g = generateGarment(o);
    for (const Yarn& y : g.yarns)
        for (std::size_t k = 0; k + 1 < y.points.size(); ++k) {
            REQUIRE(std::abs(y.points[k].z) > 0.5 * o.yarnRadius);
            REQUIRE(y.points[k].z * y.points[k + 1].z < 0.0);
        }
    // At a crossing the warp and the weft are on opposite sides, about 2h apart.
    const Garment exact = generateGarment(options(WeavePattern::Plain, GarmentShape::Flat, 400));
    const WovenCounts c = countWoven(exact);
    const glm::dvec3 warp = exact.yarns[3].points[5], weft = exact.yarns[c.warps + 5].points[3];
    CHECK((warp.x == weft.x && warp.y == weft.y));
    CHECK(warp.z == -weft.z);
    CHECK(std::abs(warp.z - weft.z) == Approx(2 * o.yarnRadius));
}

TEST_CASE("twill and satin: the warp floats as the pattern says", "[generate]") {
    auto overFraction = [](WeavePattern p) {
        const Garment g = generateGarment(options(p, GarmentShape::Flat, 400)); // 20 x 20
        const WovenCounts c = countWoven(g);
        std::size_t over = 0, total = 0, longestFloat = 0;
        for (std::size_t j = 0; j < c.warps; ++j) {
            std::size_t run = 0;
            for (const glm::dvec3& p : g.yarns[j].points) {
                run = p.z > 0 ? run + 1 : 0;
                longestFloat = std::max(longestFloat, run);
                over += p.z > 0;
                ++total;
            }
        }
        return std::pair{double(over) / double(total), longestFloat};
    };
    CHECK(overFraction(WeavePattern::Twill).first == Approx(0.5));
    CHECK(overFraction(WeavePattern::Twill).second == 2);
    CHECK(overFraction(WeavePattern::Satin).first == Approx(0.8));
    CHECK(overFraction(WeavePattern::Satin).second == 4);
    // Twill's diagonal: row j+1 is row j shifted by one crossing.
    const Garment t = generateGarment(options(WeavePattern::Twill, GarmentShape::Flat, 400));
    for (std::size_t i = 0; i + 1 < t.yarns[0].points.size(); ++i)
        CHECK((t.yarns[0].points[i + 1].z > 0) == (t.yarns[1].points[i].z > 0));
}

TEST_CASE("flat cloth: bounding box is the grid, centred, h thick", "[generate]") {
    GenerateOptions o = options(WeavePattern::Plain, GarmentShape::Flat, 100);
    o.yarnSpacing = 1.5;
    o.yarnRadius = 0.4;
    const Garment g = generateGarment(o);
    const WovenCounts c = countWoven(g);
    REQUIRE((c.warps == 10 && c.wefts == 10));
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const Yarn& y : g.yarns)
        for (const glm::dvec3& p : y.points) lo = glm::min(lo, p), hi = glm::max(hi, p);
    CHECK(lo.x == Approx(-6.75));
    CHECK(hi.x == Approx(6.75));
    CHECK(lo.y == Approx(-6.75));
    CHECK(hi.y == Approx(6.75));
    CHECK(lo.z == Approx(-0.4));
    CHECK(hi.z == Approx(0.4));
    for (const Yarn& y : g.yarns) CHECK_FALSE(y.closed);
}

TEST_CASE("cylinder: points at the radius, warps closed around the axis", "[generate]") {
    for (WeavePattern p : {WeavePattern::Plain, WeavePattern::Twill, WeavePattern::Satin}) {
        CAPTURE(toString(p));
        GenerateOptions o = options(p, GarmentShape::Cylinder, 2000, 0.02);
        const Garment g = generateGarment(o);
        std::size_t closed = 0, cols = 0, rows = 0;
        for (const Yarn& y : g.yarns)
            if (y.closed) ++closed, cols = y.points.size();
        for (const Yarn& y : g.yarns)
            if (!y.closed) rows = y.points.size();
        REQUIRE(closed > 0);
        CHECK(closed == rows);                      // every warp goes all the way around
        CHECK(g.yarns.size() - closed == cols);     // one weft per column
        CHECK(std::abs(double(cols * rows) - 2000.0) <= 0.02 * 2000.0);
        const double radius = double(cols) * o.yarnSpacing / (2 * kPi);
        const double slack = o.yarnRadius + o.jitter * o.yarnSpacing + 1e-9;
        double zlo = 1e300, zhi = -1e300;
        for (const Yarn& y : g.yarns)
            for (const glm::dvec3& q : y.points) {
                REQUIRE(std::abs(radialXY(q) - radius) <= slack);
                zlo = std::min(zlo, q.z), zhi = std::max(zhi, q.z);
            }
        CHECK(zhi - zlo == Approx(double(rows - 1) * o.yarnSpacing).margin(2 * o.jitter * o.yarnSpacing));
        // Faces every direction: the first warp's points cover all eight octants of angle.
        int octants = 0;
        for (const glm::dvec3& q : g.yarns[0].points) octants |= 1 << (int(std::floor((std::atan2(q.y, q.x) + kPi) / (kPi / 4))) & 7);
        CHECK(octants == 0xff);
    }
    // Plain: the closed warp keeps alternating across the seam (an even column count).
    GenerateOptions o = options(WeavePattern::Plain, GarmentShape::Cylinder, 1000);
    const Garment g = generateGarment(o);
    const Yarn& warp = g.yarns[0];
    REQUIRE(warp.closed);
    const double radius = double(warp.points.size()) * o.yarnSpacing / (2 * kPi);
    for (std::size_t k = 0; k < warp.points.size(); ++k) {
        const double a = radialXY(warp.points[k]) - radius;
        const double b = radialXY(warp.points[(k + 1) % warp.points.size()]) - radius;
        REQUIRE(a * b < 0.0);
    }
}

TEST_CASE("sphere: a cap of open yarns at a constant radius", "[generate]") {
    for (WeavePattern p : {WeavePattern::Plain, WeavePattern::Knit}) {
        CAPTURE(toString(p));
        GenerateOptions o = options(p, GarmentShape::Sphere, 1500, 0.02);
        const Garment g = generateGarment(o);
        const double depth = (p == WeavePattern::Knit ? 2.0 : 1.0) * o.yarnRadius + o.jitter * o.yarnSpacing;
        double rlo = 1e300, rhi = -1e300, cosMin = 1.0;
        glm::dvec3 lo(1e300), hi(-1e300);
        for (const Yarn& y : g.yarns) {
            CHECK_FALSE(y.closed);
            for (const glm::dvec3& q : y.points) {
                rlo = std::min(rlo, norm(q)), rhi = std::max(rhi, norm(q));
                cosMin = std::min(cosMin, q.z / norm(q));
                lo = glm::min(lo, q), hi = glm::max(hi, q);
            }
        }
        CHECK(rhi - rlo <= 2 * depth + 1e-9);
        CHECK(rhi - rlo >= depth); // both sides of the cloth are there
        CHECK(cosMin >= 0.45);      // within ~63 degrees of the cap's top
        CHECK(cosMin <= 0.75);      // but genuinely curved
        if (p == WeavePattern::Plain) { // warps first, then wefts: the cloth keeps its proportions
            const double cols = double(g.yarns.front().points.size() - 1), rows = double(g.yarns.back().points.size() - 1);
            CHECK((hi.x - lo.x) / cols == Approx((hi.y - lo.y) / rows).epsilon(0.05));
        }
    }
}

TEST_CASE("knit: omega loops interlock with the next course, bounded thickness", "[generate]") {
    GenerateOptions o = options(WeavePattern::Knit, GarmentShape::Flat, 600, 0.02);
    const Garment g = generateGarment(o);
    const std::size_t courses = g.yarns.size();
    REQUIRE(courses >= 2);
    REQUIRE(g.yarns[0].points.size() % 8 == 0);
    const std::size_t wales = g.yarns[0].points.size() / 8; // eight control points per loop
    for (const Yarn& y : g.yarns) CHECK(y.points.size() == 8 * wales);
    const std::size_t contacts = wales * (courses - 1); // each loop holds the loop above
    CHECK(std::abs(double(contacts) - 600.0) <= 0.03 * 600.0);
    CHECK(g.controlPointCount() == 8 * wales * courses);

    const double s = o.yarnSpacing;
    double zlo = 1e300, zhi = -1e300;
    for (std::size_t j = 0; j < courses; ++j) {
        const auto& pts = g.yarns[j].points;
        for (std::size_t i = 0; i < wales; ++i) {
            const glm::dvec3* l = &pts[8 * i];
            // Loop-shaped: goes up and down by more than a spacing, and x runs backwards
            // on both legs (the head overhangs them).
            const double ylo = std::min({l[3].y, l[4].y, l[5].y}), yhi = std::max({l[0].y, l[1].y, l[7].y});
            CHECK(yhi - ylo > 1.5 * s);
            CHECK(l[3].x < l[1].x);
            CHECK(l[7].x < l[5].x);
            // Contacts (head, leg, sinker, leg) alternate sides of the fabric.
            CHECK(l[0].z > 0);
            CHECK(l[2].z < 0);
            CHECK(l[4].z > 0);
            CHECK(l[6].z < 0);
            for (int k = 0; k < 8; ++k) zlo = std::min(zlo, l[k].z), zhi = std::max(zhi, l[k].z);
            // Interlock: the head of this loop sits between the legs of the loop above,
            // above its sinker, on the other side of the fabric.
            if (j + 1 < courses && i > 0) {
                const glm::dvec3* up = &g.yarns[j + 1].points[8 * i];
                CHECK(l[0].x > up[-2].x);
                CHECK(l[0].x < up[2].x);
                CHECK(l[0].y > up[-4].y);
                CHECK(l[0].y > up[4].y);
                CHECK(l[0].y < up[0].y);
                CHECK(l[0].z * up[2].z < 0);
            }
        }
    }
    CHECK(zhi - zlo <= 4 * o.yarnRadius + 2 * o.jitter * s);
    CHECK(zhi - zlo >= 3 * o.yarnRadius);

    // Circular knitting on a cylinder: each course is one closed yarn.
    const Garment c = generateGarment(options(WeavePattern::Knit, GarmentShape::Cylinder, 600));
    for (const Yarn& y : c.yarns) CHECK(y.closed);
}

TEST_CASE("410k crossings (the paper's vest) generate fast, with memory to size", "[generate][large]") {
    for (WeavePattern p : {WeavePattern::Plain, WeavePattern::Knit}) {
        CAPTURE(toString(p));
        const auto t0 = std::chrono::steady_clock::now();
        const Garment g = generateGarment(options(p, GarmentShape::Cylinder, 410'000, 0.02));
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        CHECK(seconds < 10.0); // ~0.1 s optimised; generous for debug builds
        std::size_t crossings = 0, capacity = 0;
        if (p == WeavePattern::Knit) {
            crossings = g.yarns[0].points.size() / 8 * (g.yarns.size() - 1);
            CHECK(g.controlPointCount() <= 8 * (crossings + 1000));
        } else {
            std::size_t closed = 0;
            for (const Yarn& y : g.yarns) closed += y.closed;
            crossings = closed * (g.yarns.size() - closed);
            CHECK(g.controlPointCount() == 2 * crossings);
        }
        CHECK(crossings == 410'000); // 625 x 656 fits exactly
        for (const Yarn& y : g.yarns) capacity += y.points.capacity();
        CHECK(capacity == g.controlPointCount()); // no slack from growth
    }
}
