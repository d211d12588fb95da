// Procedural garments: yarn centre curves as Catmull-Rom control points placed
// at the crossings (the paper's knots), alternating sides of the fabric.
#include "garment/generate.h"

#include "core/error.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace yv {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSqrtHalf = 0.70710678118654752440;
// Far beyond the paper's 410k-crossing vest; stops a typo from eating all memory.
constexpr std::uint64_t kMaxCrossings = 100'000'000;

// Knit stitch (stockinette), in yarn spacings s and yarn radii r. A wale holds two
// legs, so it is 2s wide and the legs come out evenly s apart.
constexpr double kWaleWidth = 2.0;   // s
// Loops reach into the next course (2b > dy) to interlock, but not the one after
// (b < dy); the overhang gives the omega shape (a > pi/4: legs lean back under the
// head). Tuned so yarns crossing in the fabric plane are > 2r apart along the normal.
constexpr double kCourseHeight = 1.3;   // dy, in s
constexpr double kLoopHalfHeight = 1.1; // b, in s
constexpr double kLoopOverhang = 1.5;   // a in x = t + a sin 2t
constexpr double kKnitDepth = 2.0;      // c, in r

std::uint64_t mix64(std::uint64_t x) { // splitmix64 finaliser
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

// Counter-based so each point's jitter depends only on (seed, yarn, point): no
// generator state to replay, and no std distribution whose output varies by library.
class Jitter {
  public:
    Jitter(std::uint64_t seed, double amplitude) : base_(mix64(seed)), amp_(amplitude) {}
    glm::dvec3 at(std::uint64_t yarn, std::uint64_t point) const {
        if (amp_ == 0.0) return glm::dvec3(0.0);
        const std::uint64_t h = mix64(mix64(base_ ^ yarn) ^ point);
        return amp_ * glm::dvec3(sym(mix64(h ^ 1)), sym(mix64(h ^ 2)), sym(mix64(h ^ 3)));
    }

  private:
    static double sym(std::uint64_t h) { return double(h >> 11) * 0x1.0p-52 - 1.0; } // [-1, 1)
    std::uint64_t base_;
    double amp_;
};

constexpr auto kInvFactorial = [] {
    std::array<double, 18> inv{};
    double f = 1.0; // exact: 17! < 2^53
    for (int k = 0; k < 18; ++k) inv[k] = 1.0 / (f *= (k > 0 ? k : 1));
    return inv;
}();

struct SinCos {
    double s, c;
};

// sin and cos of 2*pi*turns with + - * only, so points do not depend on the libm
// (nor on FMA contraction: ISO -std=c++20, as CMake builds it, does not contract).
SinCos sinCosTurns(double turns) {
    const double t = turns - std::floor(turns);
    const double q = std::floor(t * 4.0 + 0.5); // nearest quarter turn
    const double r = (t - 0.25 * q) * (2.0 * kPi); // |r| <= pi/4: Taylor to r^17 is off by < 1e-17
    const double r2 = r * r;
    double s = kInvFactorial[17], c = kInvFactorial[16];
    for (int k = 15; k >= 1; k -= 2) { // Horner, alternating signs
        s = kInvFactorial[k] - r2 * s;
        c = kInvFactorial[k - 1] - r2 * c;
    }
    s *= r;
    switch (int(q) & 3) {
    case 0: return {s, c};
    case 1: return {c, -s};
    case 2: return {-s, -c};
    default: return {-c, s};
    }
}

// cols x rows with cols*rows close to n, aspect at most 1.25, cols a multiple of
// `period` (a closed cylinder yarn must repeat the pattern exactly around the seam).
struct Grid {
    std::uint64_t cols, rows;
};
Grid nearSquareGrid(std::uint64_t n, std::uint64_t period) {
    const double root = std::sqrt(double(n));
    const std::uint64_t lo = std::max<std::uint64_t>(period, std::uint64_t(root / 1.25) / period * period);
    const std::uint64_t hi = std::max<std::uint64_t>(lo, std::uint64_t(std::ceil(root * 1.25 / double(period))) * period);
    Grid best{0, 0};
    std::uint64_t bestCost[3] = {~0ull, ~0ull, ~0ull};
    for (std::uint64_t cols = lo; cols <= hi; cols += period) {
        const std::uint64_t rows = std::max<std::uint64_t>(1, (n + cols / 2) / cols);
        const std::uint64_t big = std::max(cols, rows), small = std::min(cols, rows);
        const std::uint64_t cost[3] = {4 * big > 5 * small + 4, // too skewed (+4 lets tiny grids be 1x2, 2x3)
                                       cols * rows > n ? cols * rows - n : n - cols * rows, big - small};
        if (std::lexicographical_compare(cost, cost + 3, bestCost, bestCost + 3))
            best = {cols, rows}, std::copy(cost, cost + 3, bestCost);
    }
    return best;
}

// Does the warp yarn (row j, along x) pass over the weft yarn (column i) at crossing (i, j)?
bool warpOver(WeavePattern p, std::uint64_t i, std::uint64_t j) {
    switch (p) {
    case WeavePattern::Plain: return (i + j) % 2 == 0;
    case WeavePattern::Twill: return (i + j) % 4 < 2;    // 2/2, diagonal moves one per row
    case WeavePattern::Satin: return (i + 2 * j) % 5 != 0; // 5-harness, move 2: floats over 4
    case WeavePattern::Knit: break;
    }
    return false;
}

std::uint64_t patternPeriod(WeavePattern p) {
    switch (p) {
    case WeavePattern::Plain: return 2;
    case WeavePattern::Twill: return 4;
    case WeavePattern::Satin: return 5;
    case WeavePattern::Knit: return 1; // one wale is one period
    }
    return 1;
}

// Maps cloth space (x, y, offset along the cloth normal) onto the garment's surface.
class ShapeMap {
  public:
    // circumference: the x period that closes the cylinder; (cx, cy): the cloth centre.
    ShapeMap(GarmentShape shape, double circumference, double cx, double cy, double spacing)
        : shape_(shape), circ_(circumference), cx_(cx), cy_(cy) {
        if (shape == GarmentShape::Cylinder) radius_ = circumference / (2.0 * kPi);
        // Sphere: a cap whose corners stay within 60 degrees of its top, where the map
        // shrinks spacings across the radial direction by sin(a)/a = 0.83 at most.
        // The 2s margin covers knit loops overhanging the grid.
        if (shape == GarmentShape::Sphere) radius_ = (std::hypot(cx, cy) + 2.0 * spacing) / (kPi / 3.0);
    }
    glm::dvec3 operator()(double x, double y, double n) const {
        switch (shape_) {
        case GarmentShape::Flat: return {x - cx_, y - cy_, n};
        case GarmentShape::Cylinder: {
            const SinCos a = sinCosTurns(x / circ_);
            return {(radius_ + n) * a.c, (radius_ + n) * a.s, y - cy_};
        }
        case GarmentShape::Sphere: {
            // Azimuthal equidistant about +z: distances from the centre are kept, so
            // the cloth bends without the shear and pinching of a latitude band.
            const double dx = x - cx_, dy = y - cy_, rho = std::sqrt(dx * dx + dy * dy);
            const SinCos a = sinCosTurns(rho / radius_ / (2.0 * kPi));
            const double k = rho > 0.0 ? a.s / rho : 1.0 / radius_;
            return (radius_ + n) * glm::dvec3(k * dx, k * dy, a.c);
        }
        }
        return {};
    }

  private:
    GarmentShape shape_;
    double circ_, cx_, cy_, radius_ = 0.0;
};

void generateWoven(const GenerateOptions& o, Garment& g) {
    const bool cylinder = o.shape == GarmentShape::Cylinder;
    const Grid grid = nearSquareGrid(o.crossings, cylinder ? patternPeriod(o.pattern) : 1);
    const double s = o.yarnSpacing, h = o.yarnRadius; // h = r: crossing yarns just touch
    const ShapeMap map(o.shape, double(grid.cols) * s, 0.5 * double(grid.cols - 1) * s, 0.5 * double(grid.rows - 1) * s, s);
    const Jitter jitter(o.seed, o.jitter * s);
    g.yarns.resize(grid.rows + grid.cols);
    std::uint64_t yarn = 0;
    for (std::uint64_t j = 0; j < grid.rows; ++j, ++yarn) { // warp: along x, around the cylinder
        Yarn& y = g.yarns[yarn];
        y.closed = cylinder;
        y.points.reserve(grid.cols);
        for (std::uint64_t i = 0; i < grid.cols; ++i) {
            const glm::dvec3 p = glm::dvec3(double(i) * s, double(j) * s, warpOver(o.pattern, i, j) ? h : -h) + jitter.at(yarn, i);
            y.points.push_back(map(p.x, p.y, p.z));
        }
    }
    for (std::uint64_t i = 0; i < grid.cols; ++i, ++yarn) { // weft: along y
        Yarn& y = g.yarns[yarn];
        y.points.reserve(grid.rows);
        for (std::uint64_t j = 0; j < grid.rows; ++j) {
            const glm::dvec3 p = glm::dvec3(double(i) * s, double(j) * s, warpOver(o.pattern, i, j) ? -h : h) + jitter.at(yarn, j);
            y.points.push_back(map(p.x, p.y, p.z));
        }
    }
}

// Stockinette: course j follows x = t + a sin 2t, y = b cos t, z = c cos 2t per wale
// (t in [0, 2 pi)), sampled at its eight contacts and turning points. The legs
// (t = pi/2, 3pi/2) of course j+1 pass behind the head (t = 0) of course j, then
// their sinker (t = pi) in front of course j's legs: loop j+1 goes through loop j,
// and the contacts along a yarn alternate sides: +c, -c, +c, -c.
void generateKnit(const GenerateOptions& o, Garment& g) {
    const bool cylinder = o.shape == GarmentShape::Cylinder;
    // rows = interlocking course pairs, so there are rows + 1 courses.
    const Grid grid = nearSquareGrid(o.crossings, 1);
    const double s = o.yarnSpacing, w = kWaleWidth * s, u = w / (2.0 * kPi);
    const double dy = kCourseHeight * s, b = kLoopHalfHeight * s, c = kKnitDepth * o.yarnRadius;
    // sin 2t, cos t, cos 2t at t = k pi/4, exact so no libm enters the points.
    static constexpr double sin2t[8] = {0, 1, 0, -1, 0, 1, 0, -1};
    static constexpr double cost[8] = {1, kSqrtHalf, 0, -kSqrtHalf, -1, -kSqrtHalf, 0, kSqrtHalf};
    static constexpr double cos2t[8] = {1, 0, -1, 0, 1, 0, -1, 0};
    const double lastX = double(grid.cols - 1) * w + u * (7.0 * kPi / 4.0 - kLoopOverhang);
    const ShapeMap map(o.shape, double(grid.cols) * w, 0.5 * lastX, 0.5 * double(grid.rows) * dy, s);
    const Jitter jitter(o.seed, o.jitter * s);
    g.yarns.resize(grid.rows + 1);
    for (std::uint64_t j = 0; j <= grid.rows; ++j) {
        Yarn& y = g.yarns[j];
        y.closed = cylinder; // circular knitting: each course goes once around
        y.points.reserve(8 * grid.cols);
        for (std::uint64_t i = 0; i < grid.cols; ++i)
            for (int k = 0; k < 8; ++k) {
                const double t = k * (kPi / 4.0);
                const std::uint64_t index = 8 * i + std::uint64_t(k);
                const glm::dvec3 p = glm::dvec3(double(i) * w + u * (t + kLoopOverhang * sin2t[k]), double(j) * dy + b * cost[k],
                                                c * cos2t[k]) + jitter.at(j, index);
                y.points.push_back(map(p.x, p.y, p.z));
            }
    }
}

void validate(const GenerateOptions& o) {
    if (o.crossings == 0 || o.crossings > kMaxCrossings)
        throw Error("generate: crossings must be between 1 and " + std::to_string(kMaxCrossings) + ", got " +
                    std::to_string(o.crossings));
    if (!std::isfinite(o.yarnSpacing) || o.yarnSpacing <= 0.0)
        throw Error("generate: yarn spacing must be a positive number, got " + std::to_string(o.yarnSpacing));
    if (!std::isfinite(o.yarnRadius) || o.yarnRadius <= 0.0)
        throw Error("generate: yarn radius must be a positive number, got " + std::to_string(o.yarnRadius));
    if (!std::isfinite(o.jitter) || o.jitter < 0.0 || o.jitter > 0.5)
        throw Error("generate: jitter must be in [0, 0.5] (a fraction of the yarn spacing), got " + std::to_string(o.jitter));
}

} // namespace

Garment generateGarment(const GenerateOptions& options) {
    validate(options);
    Garment g;
    g.curveType = CurveType::CatmullRom;
    g.yarnRadius = options.yarnRadius;
    if (options.pattern == WeavePattern::Knit)
        generateKnit(options, g);
    else
        generateWoven(options, g);
    return g;
}

/// Parses a pattern name as the CLI spells it.
WeavePattern parseWeavePattern(const std::string& s) {
    for (WeavePattern p : {WeavePattern::Plain, WeavePattern::Twill, WeavePattern::Satin, WeavePattern::Knit})
        if (s == toString(p)) return p;
    throw Error("unknown weave pattern '" + s + "' (valid: plain, twill, satin, knit)");
}

/// Parses a shape name as the CLI spells it.
GarmentShape parseGarmentShape(const std::string& s) {
    for (GarmentShape g : {GarmentShape::Flat, GarmentShape::Cylinder, GarmentShape::Sphere})
        if (s == toString(g)) return g;
    throw Error("unknown garment shape '" + s + "' (valid: flat, cylinder, sphere)");
}

/// The name parseWeavePattern accepts.
const char* toString(WeavePattern p) {
    switch (p) {
    case WeavePattern::Plain: return "plain";
    case WeavePattern::Twill: return "twill";
    case WeavePattern::Satin: return "satin";
    case WeavePattern::Knit: return "knit";
    }
    return "?";
}

/// The name parseGarmentShape accepts.
const char* toString(GarmentShape s) {
    switch (s) {
    case GarmentShape::Flat: return "flat";
    case GarmentShape::Cylinder: return "cylinder";
    case GarmentShape::Sphere: return "sphere";
    }
    return "?";
}

} // namespace yv
