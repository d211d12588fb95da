// Fidelity of the per-voxel densities: a voxel wholly inside a disk yarn holds
// exactly its volume of fibre (1.0), whatever the yarn's direction, radius,
// bend, slice spacing, resolution or backend; closed yarns have no twist seam;
// interpenetrating yarns are clamped (or summed) as asked. Every check is made
// voxel by voxel against the analytic shape, not only in sum.
#include "core/bricks.h"
#include "core/sampling.h"
#include "cpu/cpu_voxelizer.h"
#include "garment/catmull_rom.h"
#include "garment/cross_section.h"
#include "garment/generate.h"
#include "garment/slices.h"
#include "gpu/egl_context.h"
#include "gpu/gl_voxelizer.h"
#include "plan/grid.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using namespace yv;

namespace {

constexpr double kSqrt3 = 1.7320508075688772;

enum class Backend { Cpu, Gl };

const char* toString(Backend b) { return b == Backend::Cpu ? "cpu" : "gl"; }

std::string str(glm::dvec3 v) {
    std::ostringstream s;
    s << "(" << v.x << ", " << v.y << ", " << v.z << ")";
    return s.str();
}

BrickVolume voxelize(Backend backend, const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid,
                     Overlap overlap = Overlap::Clamp) {
    if (backend == Backend::Cpu) {
        VoxelizeSettings s;
        s.overlap = overlap;
        return voxelizeCpu(plan, xs, grid, s);
    }
    GlVoxelizeSettings s;
    s.base.overlap = overlap;
    s.brickResolve = BrickResolve::Gpu; // the GPU's path (llvmpipe would resolve on the host)
    const GlContext context;
    return voxelizeGl(plan, xs, grid, s, context);
}

glm::dvec3 voxelCenter(const VoxelGrid& g, glm::ivec3 v) { return g.origin + (glm::dvec3(v) + 0.5) * g.voxelSize; }

/// Voxel index range whose centres can lie in the world box [lo, hi], clipped to the grid.
void voxelRange(const VoxelGrid& g, glm::dvec3 lo, glm::dvec3 hi, glm::ivec3& first, glm::ivec3& last) {
    for (int a = 0; a < 3; ++a) {
        first[a] = std::max(0, int(std::floor((lo[a] - g.origin[a]) / g.voxelSize - 0.5)));
        last[a] = std::min(g.dims[a] - 1, int(std::ceil((hi[a] - g.origin[a]) / g.voxelSize - 0.5)));
    }
}

/// Calls fn(voxel, centre) for every voxel whose centre may lie in [lo, hi].
template <class Fn>
void forVoxelsIn(const VoxelGrid& g, glm::dvec3 lo, glm::dvec3 hi, Fn&& fn) {
    glm::ivec3 first, last;
    voxelRange(g, lo, hi, first, last);
    for (int x = first.x; x <= last.x; ++x)
        for (int y = first.y; y <= last.y; ++y)
            for (int z = first.z; z <= last.z; ++z) {
                const glm::ivec3 v(x, y, z);
                fn(v, voxelCenter(g, v));
            }
}

/// Calls fn(voxel, density) for every active voxel.
template <class Fn>
void forActive(const BrickVolume& vol, Fn&& fn) {
    for (const VoxelBrick& b : vol.bricks) {
        const glm::ivec3 o = brickCoord(b.key) * 8;
        for (int i = 0; i < kBrickVoxels; ++i)
            if (b.isActive(i)) fn(o + glm::ivec3(i >> 6, (i >> 3) & 7, i & 7), b.density[i]);
    }
}

/// Densities of the voxels a test calls interior, against a target value.
struct InteriorStats {
    double target = 1.0, tolerance = 0.05;
    std::uint64_t count = 0, within = 0;
    double minD = HUGE_VAL, maxD = -HUGE_VAL, sum = 0.0;

    void add(double d) {
        ++count;
        within += std::abs(d - target) <= tolerance * target;
        minD = std::min(minD, d);
        maxD = std::max(maxD, d);
        sum += d;
    }
    double fraction() const { return count ? double(within) / double(count) : 0.0; }
    std::string text() const {
        std::ostringstream s;
        s << count << " interior voxels, " << within << " (" << 100.0 * fraction() << " %) within "
          << 100.0 * tolerance << " % of " << target << "; min " << minD << " max " << maxD << " mean "
          << (count ? sum / double(count) : 0.0);
        return s.str();
    }
};

/// Interior voxel estimate for a tube: the cross-section of radius r - h sqrt(3)/2
/// (voxels) times the length (voxels). Tests require at least half of it, so
/// that no check passes on an empty set.
double interiorEstimate(double radiusVoxels, double lengthVoxels) {
    const double inner = std::max(0.0, radiusVoxels - 0.5 * kSqrt3);
    return M_PI * inner * inner * std::max(0.0, lengthVoxels);
}

// ---------------------------------------------------------------- straight yarns

struct StraightCase {
    glm::dvec3 start, axis;
    int length = 1;        ///< world units (one control point per unit)
    double radius = 1.0 / 3.0;
    double h = 0.0;
};

enum class Spacing { Default, Coarse };

const char* toString(Spacing s) { return s == Spacing::Default ? "default spacing" : "25 slices per unit segment"; }

SliceOptions sliceOptions(double radius, Spacing mode, double h) {
    SliceOptions opt;
    opt.radius = radius;
    if (mode == Spacing::Default)
        opt.spacing = defaultSliceSpacing(h, 1);
    else
        opt.slicesPerSegment = 25;
    return opt;
}

/// Interior of a straight yarn: the whole voxel cube inside the cylinder and
/// the centre farther than h sqrt(3) from both end faces.
bool insideStraight(const StraightCase& c, glm::dvec3 p) {
    const glm::dvec3 d = p - c.start;
    const double along = glm::dot(d, c.axis);
    const double rho = glm::length(d - along * c.axis);
    return rho + 0.5 * kSqrt3 * c.h <= c.radius && along > kSqrt3 * c.h && along < c.length - kSqrt3 * c.h;
}

InteriorStats straightInterior(const StraightCase& c, const VoxelGrid& grid, const BrickVolume& vol) {
    InteriorStats st;
    const test::VolumeIndex index(vol);
    const glm::dvec3 end = c.start + double(c.length) * c.axis;
    forVoxelsIn(grid, glm::min(c.start, end) - c.radius, glm::max(c.start, end) + c.radius,
                [&](glm::ivec3 v, glm::dvec3 p) {
                    if (insideStraight(c, p)) st.add(index.density(v));
                });
    return st;
}

/// Yarn length (world units) per radius in voxels: a few radii plus margins,
/// short for the thick yarns so that they stay cheap.
int straightLength(int radiusVoxels) { return radiusVoxels <= 2 ? 6 : radiusVoxels <= 5 ? 3 : radiusVoxels <= 12 ? 2 : 1; }

const glm::dvec3 kDirections[] = {{1, 0, 0}, {0, 0, 1}, {1, 0.4, 0.25}, {1, 1, 0}, {1, 1, 1}};

void checkStraightYarns(Backend backend, std::initializer_list<int> radiiVoxels) {
    const CrossSection xs = makeDiskCrossSection();
    for (int rv : radiiVoxels)
        for (glm::dvec3 dir : kDirections)
            for (Spacing mode : {Spacing::Default, Spacing::Coarse}) {
                StraightCase c;
                c.start = {0.1, 0.2, 0.3};
                c.axis = glm::normalize(dir);
                c.length = straightLength(rv);
                c.h = c.radius / rv;
                const SliceOptions opt = sliceOptions(c.radius, mode, c.h);
                const SlicePlan plan = planSlices(test::straightYarn(c.start, c.axis, c.length), opt);
                const VoxelGrid grid = makeGrid(plan, 0, c.h);
                // Sum: no clamping hides a voxel that stacks above 1.
                const BrickVolume vol = voxelize(backend, plan, xs, grid, Overlap::Sum);
                const InteriorStats st = straightInterior(c, grid, vol);
                const double expected = M_PI * c.radius * c.radius * c.length;
                INFO(toString(backend) << ": r = " << rv << " voxels, axis " << str(dir) << ", length "
                                       << c.length / c.h << " voxels, " << toString(mode) << " ("
                                       << plan.sliceCount << " slices)");
                INFO(st.text());
                INFO("mass " << vol.totalMass() << " expected " << expected << " ratio " << vol.totalMass() / expected);
                CHECK(double(st.count) >= std::max(20.0, 0.5 * interiorEstimate(rv, c.length / c.h - 2 * kSqrt3)));
                // An explicit coarse spacing (the CLI warns about it) treats each
                // slab as flat across several voxels: on a steep diagonal the
                // surface layer of the interior shifts by up to half a slab.
                CHECK(st.fraction() >= (mode == Spacing::Default ? 0.98 : 0.95));
                CHECK(std::abs(vol.totalMass() / expected - 1.0) <= 0.005);
            }
}

// ---------------------------------------------------------------- closed loops

/// Control points of a circle of radius R about `centre` in the plane spanned by unit u, v.
Garment circleYarn(glm::dvec3 centre, glm::dvec3 u, glm::dvec3 v, double R, int points) {
    Garment g;
    Yarn y;
    y.closed = true;
    for (int i = 0; i < points; ++i) {
        const double a = 2.0 * M_PI * i / points;
        y.points.push_back(centre + R * (std::cos(a) * u + std::sin(a) * v));
    }
    g.yarns.push_back(y);
    return g;
}

/// Length of yarn 0 of a garment from fine chords of its Catmull-Rom curve.
double curveLength(const Garment& g, int stepsPerSegment = 2000) {
    const Yarn& y = g.yarns[0];
    const std::size_t segs = y.closed ? y.points.size() : y.points.size() - 1;
    double len = 0.0;
    for (std::size_t s = 0; s < segs; ++s) {
        const SegmentPoints p = segmentPoints(y, s, g.curveType);
        glm::dvec3 prev = evalCatmullRom(p, 0.0);
        for (int j = 1; j <= stepsPerSegment; ++j) {
            const glm::dvec3 q = evalCatmullRom(p, double(j) / stepsPerSegment);
            len += glm::length(q - prev);
            prev = q;
        }
    }
    return len;
}

/// Distance from p to the circle of radius R about `centre` with unit normal n.
double circleDistance(glm::dvec3 p, glm::dvec3 centre, glm::dvec3 n, double R) {
    const glm::dvec3 d = p - centre;
    const double z = glm::dot(d, n);
    const double rho = glm::length(d - z * n);
    return std::hypot(rho - R, z);
}

/// Farthest the Catmull-Rom curve of a circle yarn strays from the circle.
double circleDeviation(const Garment& g, glm::dvec3 centre, glm::dvec3 n, double R) {
    const Yarn& y = g.yarns[0];
    double worst = 0.0;
    for (std::size_t s = 0; s < y.points.size(); ++s) {
        const SegmentPoints p = segmentPoints(y, s, g.curveType);
        for (int j = 0; j <= 200; ++j) worst = std::max(worst, circleDistance(evalCatmullRom(p, j / 200.0), centre, n, R));
    }
    return worst;
}

void checkCircles(Backend backend, std::initializer_list<int> radiiVoxels, std::initializer_list<Spacing> modes) {
    const CrossSection xs = makeDiskCrossSection();
    const double r = 1.0, R = 3.0 * r;
    struct Plane {
        glm::dvec3 u, v;
    };
    const glm::dvec3 tiltedU = glm::normalize(glm::dvec3(1, 0.4, 0.25));
    const glm::dvec3 tiltedV = glm::normalize(glm::cross(glm::dvec3(-0.2, 0.3, 1.0), tiltedU));
    const Plane planes[] = {{{1, 0, 0}, {0, 1, 0}}, {tiltedU, tiltedV}};
    const glm::dvec3 centre(0.3, -0.2, 0.1);
    for (int rv : radiiVoxels)
        for (const Plane& pl : planes)
            for (Spacing mode : modes) {
                const glm::dvec3 n = glm::normalize(glm::cross(pl.u, pl.v));
                const Garment g = circleYarn(centre, pl.u, pl.v, R, 32);
                const double h = r / rv;
                const SlicePlan plan = planSlices(g, sliceOptions(r, mode, h));
                const VoxelGrid grid = makeGrid(plan, 0, h);
                const BrickVolume vol = voxelize(backend, plan, xs, grid, Overlap::Sum);

                const double deviation = circleDeviation(g, centre, n, R);
                const double length = curveLength(g);
                const test::VolumeIndex index(vol);
                InteriorStats st;
                const glm::dvec3 reach(R + r);
                forVoxelsIn(grid, centre - reach, centre + reach, [&](glm::ivec3 v, glm::dvec3 p) {
                    if (circleDistance(p, centre, n, R) + 0.5 * kSqrt3 * h <= r - deviation) st.add(index.density(v));
                });
                const double expected = M_PI * r * r * length;
                INFO(toString(backend) << ": r = " << rv << " voxels, bend radius 3 r, normal " << str(n) << ", "
                                       << toString(mode) << " (" << plan.sliceCount << " slices); curve strays "
                                       << deviation / h << " voxels from the circle");
                INFO(st.text());
                INFO("mass " << vol.totalMass() << " expected " << expected << " ratio " << vol.totalMass() / expected);
                CHECK(double(st.count) >= 0.5 * interiorEstimate(rv - deviation / h, length / h));
                CHECK(st.fraction() >= 0.95);
                CHECK(std::abs(vol.totalMass() / expected - 1.0) <= 0.005);
            }
}

/// All slices of yarn 0 of a plan, in order along the yarn.
std::vector<Slice> yarnSlices(const SlicePlan& plan) {
    std::vector<Slice> out;
    for (const SegmentRecord& seg : plan.segments)
        if (seg.yarn == 0)
            for (std::uint32_t k = 0; k < seg.sliceCount; ++k) out.push_back(placeSlice(seg, k));
    return out;
}

/// Signed angle about b's tangent from a's `right`, carried to b by the
/// minimal rotation between the tangents, to b's `right`.
double twistAngle(const Slice& a, const Slice& b) {
    const glm::dvec3 moved = rotateMinimal(a.right, a.tangent, b.tangent);
    return std::atan2(glm::dot(glm::cross(moved, b.right), b.tangent), glm::dot(moved, b.right));
}

/// Angle k: from slice k to slice k + 1; the last one crosses the closing point.
std::vector<double> loopAngles(const SlicePlan& plan) {
    const std::vector<Slice> s = yarnSlices(plan);
    std::vector<double> a(s.size());
    for (std::size_t k = 0; k < s.size(); ++k) a[k] = twistAngle(s[k], s[(k + 1) % s.size()]);
    return a;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

Garment closedYarn(int points, const std::function<glm::dvec3(double)>& at) {
    Garment g;
    Yarn y;
    y.closed = true;
    for (int i = 0; i < points; ++i) y.points.push_back(at(2.0 * M_PI * i / points));
    g.yarns.push_back(y);
    return g;
}

double wrapAngle(double a) { return std::remainder(a, 2.0 * M_PI); }

/// Angle by which a vector comes back turned about the first tangent after
/// transport around yarn 0 by minimal rotations between finely spaced tangents.
double loopHolonomy(const Garment& g, int stepsPerSegment = 400) {
    const Yarn& y = g.yarns[0];
    std::vector<glm::dvec3> tangents;
    for (std::size_t s = 0; s < y.points.size(); ++s) {
        const SegmentPoints p = segmentPoints(y, s, g.curveType);
        for (int j = 0; j < stepsPerSegment; ++j)
            tangents.push_back(glm::normalize(evalCatmullRomDerivative(p, double(j) / stepsPerSegment)));
    }
    const glm::dvec3 t0 = tangents[0];
    const glm::dvec3 v0 = glm::normalize(glm::cross(t0, std::abs(t0.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    glm::dvec3 v = v0;
    for (std::size_t i = 0; i < tangents.size(); ++i) v = rotateMinimal(v, tangents[i], tangents[(i + 1) % tangents.size()]);
    return std::atan2(glm::dot(glm::cross(v0, v), t0), glm::dot(v0, v));
}

// ---------------------------------------------------------------- a long wavy yarn

/// One open yarn along x from 0 to length, waving in y and z; control points
/// every `step` along x. A uniform Catmull-Rom reproduces linear data, so the
/// curve's x is exactly linear in the parameter: the curve is a graph over x.
/// 180 radii long: r is 1.4 voxels at resolution 256 (a thinner yarn has
/// hardly any voxel wholly inside it there) and 22 voxels at 4096 (about 7 M
/// active voxels). The wave in z keeps voxel centres from all sitting at one
/// offset from the curve's plane, which at low resolution can leave no voxel
/// wholly inside.
struct WavyYarn {
    double radius = 1.0, step = 2.0, length = 180.0;
    Garment garment;
    std::vector<SegmentPoints> segments;

    WavyYarn() {
        Yarn y;
        for (int i = 0; i * step <= length + 1e-9; ++i) {
            const double x = i * step;
            y.points.push_back({x, 3.0 * radius * std::sin(2.0 * M_PI * x / 45.0),
                                2.0 * radius * std::sin(2.0 * M_PI * x / 60.0 + 0.7)});
        }
        garment.yarns.push_back(y);
        for (std::size_t s = 0; s + 1 < y.points.size(); ++s) segments.push_back(segmentPoints(y, s, garment.curveType));
    }

    /// Curve point over x, and its first and second derivatives with respect to x.
    void eval(double x, glm::dvec3& c, glm::dvec3& d1, glm::dvec3& d2) const {
        const int n = int(segments.size());
        const int s = std::clamp(int(std::floor(x / step)), 0, n - 1);
        const double t = x / step - s;
        const SegmentPoints& p = segments[s];
        c = evalCatmullRom(p, t);
        d1 = evalCatmullRomDerivative(p, t) / step;
        const double w0 = 4.0 - 6.0 * t, w1 = -10.0 + 18.0 * t, w2 = 8.0 - 18.0 * t, w3 = -2.0 + 6.0 * t;
        d2 = 0.5 * (w0 * p[0] + w1 * p[1] + w2 * p[2] + w3 * p[3]) / (step * step);
    }
    glm::dvec3 at(double x) const {
        glm::dvec3 c, d1, d2;
        eval(x, c, d1, d2);
        return c;
    }

    /// Distance from p to the curve: Newton on the squared distance over x,
    /// from x = p.x (the curve bends gently, so the nearest point is unique and close).
    double distance(glm::dvec3 p) const {
        double x = std::clamp(p.x, 0.0, length);
        glm::dvec3 c, d1, d2;
        for (int it = 0; it < 12; ++it) {
            eval(x, c, d1, d2);
            const glm::dvec3 e = c - p;
            const double g1 = glm::dot(d1, e), g2 = glm::dot(d1, d1) + glm::dot(d2, e);
            const double dx = g2 > 0.0 ? -g1 / g2 : -g1;
            const double next = std::clamp(x + dx, 0.0, length);
            if (std::abs(next - x) < 1e-12) break;
            x = next;
        }
        return glm::length(at(x) - p);
    }

    /// Brute-force distance (dense scan over x near p), to check `distance`.
    double distanceScan(glm::dvec3 p) const {
        double best = HUGE_VAL;
        for (double x = std::max(0.0, p.x - 3 * radius); x <= std::min(length, p.x + 3 * radius); x += 1e-4)
            best = std::min(best, glm::length(at(x) - p));
        return best;
    }
};

// ---------------------------------------------------------------- backend agreement

struct Agreement {
    std::uint64_t both = 0, onlyCpu = 0, onlyGl = 0, close = 0;
    double maxDiff = 0.0, sumDiff = 0.0, massCpu = 0.0, massGl = 0.0;
    double iou() const { return double(both) / double(both + onlyCpu + onlyGl); }
    double closeFraction() const { return both ? double(close) / double(both) : 0.0; }
    std::string text() const {
        std::ostringstream s;
        s << "active in both " << both << ", only CPU " << onlyCpu << ", only GL " << onlyGl << ", IoU " << iou()
          << "; density |GL - CPU|: max " << maxDiff << " mean " << (both ? sumDiff / double(both) : 0.0) << ", "
          << 100.0 * closeFraction() << " % within 1e-4; mass GL / CPU " << massGl / massCpu;
        return s.str();
    }
};

Agreement agree(const BrickVolume& cpu, const BrickVolume& gl) {
    Agreement a;
    const test::VolumeIndex glIndex(gl), cpuIndex(cpu);
    forActive(cpu, [&](glm::ivec3 v, float d) {
        const VoxelBrick* b = glIndex.brick(v);
        const int off = brickOffset(v.x & 7, v.y & 7, v.z & 7);
        if (!b || !b->isActive(off)) {
            ++a.onlyCpu;
            return;
        }
        ++a.both;
        const double diff = std::abs(double(b->density[off]) - double(d));
        a.maxDiff = std::max(a.maxDiff, diff);
        a.sumDiff += diff;
        a.close += diff <= 1e-4;
    });
    forActive(gl, [&](glm::ivec3 v, float) {
        const VoxelBrick* b = cpuIndex.brick(v);
        if (!b || !b->isActive(brickOffset(v.x & 7, v.y & 7, v.z & 7))) ++a.onlyGl;
    });
    a.massCpu = cpu.totalMass();
    a.massGl = gl.totalMass();
    return a;
}

void checkAgreement(const Agreement& a, std::uint64_t minVoxels) {
    INFO(a.text());
    CHECK(a.both >= minVoxels);
    CHECK(a.iou() >= 0.9999);
    CHECK(a.closeFraction() >= 0.9999);
    CHECK(std::abs(a.massGl / a.massCpu - 1.0) <= 1e-4);
}

} // namespace

// =================================================================== 1. straight yarns

TEST_CASE("Fidelity: voxels inside a straight disk yarn read 1 and the mass is pi r^2 L (CPU)", "[fidelity]") {
    checkStraightYarns(Backend::Cpu, {2, 5, 12, 40});
}

TEST_CASE("Fidelity: voxels inside a straight disk yarn read 1 and the mass is pi r^2 L (GL)", "[fidelity][gl]") {
    YV_REQUIRE_GL();
    checkStraightYarns(Backend::Gl, {2, 5});
}

// =================================================================== 2. a bent yarn

TEST_CASE("Fidelity: a closed circular yarn bent at 3 r reads 1 inside and holds pi r^2 2 pi R (CPU)", "[fidelity]") {
    checkCircles(Backend::Cpu, {4, 10, 20}, {Spacing::Default, Spacing::Coarse});
}

TEST_CASE("Fidelity: a closed circular yarn bent at 3 r reads 1 inside and holds pi r^2 2 pi R (GL)",
          "[fidelity][gl]") {
    YV_REQUIRE_GL();
    checkCircles(Backend::Gl, {4}, {Spacing::Default, Spacing::Coarse});
}

// =================================================================== 3. twist seams

TEST_CASE("Fidelity: a twisted closed yarn turns across its closing point as anywhere else", "[fidelity]") {
    const double R = 3.0;
    const Garment g = circleYarn({0.3, -0.2, 0.1}, glm::normalize(glm::dvec3(1, 0.4, 0.25)),
                                 glm::normalize(glm::cross(glm::dvec3(-0.2, 0.3, 1.0), glm::normalize(glm::dvec3(1, 0.4, 0.25)))),
                                 R, 32);
    const double loop = curveLength(g);
    for (double twist : {1.37, -2.9}) {
        for (int perSegment : {25, 7}) {
            SliceOptions opt;
            opt.radius = 1.0;
            opt.twist = twist;
            opt.slicesPerSegment = perSegment;
            const SlicePlan plan = planSlices(g, opt);
            // Equal segments with equal slice counts: every step should turn alike.
            REQUIRE(plan.segments.size() == 32);
            for (const SegmentRecord& s : plan.segments) {
                REQUIRE(s.sliceCount == std::uint32_t(perSegment));
                REQUIRE(s.length == Approx(plan.segments[0].length).epsilon(1e-9));
            }
            const double turns = twist * loop / (2.0 * M_PI);
            REQUIRE(std::abs(turns - std::round(turns)) > 0.05); // the old rule leaves a seam here
            const std::vector<double> a = loopAngles(plan);
            const double closing = a.back();
            const double med = median(std::vector<double>(a.begin(), a.end() - 1));
            const auto [lo, hi] = std::minmax_element(a.begin(), a.end() - 1);
            INFO("twist " << twist << " rad/unit (" << turns << " turns over the loop), " << perSegment
                          << " slices per segment: closing step " << closing << " rad, median step " << med
                          << " (others from " << *lo << " to " << *hi << "), expected about "
                          << twist * loop / plan.sliceCount);
            CHECK(std::abs(med) > 1e-3); // the loop really is twisted
            CHECK(std::abs(closing - med) <= 0.01 * std::abs(med));
        }
    }
}

TEST_CASE("Fidelity: a non-planar closed yarn has no frame seam at its closing point", "[fidelity]") {
    struct Loop {
        const char* name;
        int points;
        std::function<glm::dvec3(double)> at;
        double twist;
    };
    const double R = 3.0;
    // The symmetric saddle (R cos t, R sin t, h cos 2t) is its own mirror
    // image, so a transported frame comes back unturned and it would show no
    // seam even without a fix: the saddle here is tilted off its symmetry.
    auto saddle = [R](double t) {
        return glm::dvec3(R * std::cos(t), R * std::sin(t), 1.5 * std::cos(2 * t) + 1.2 * std::sin(t + 0.4));
    };
    auto knot = [R](double t) {
        const double q = R + 1.2 * std::cos(3 * t);
        return glm::dvec3(q * std::cos(2 * t), q * std::sin(2 * t), 1.2 * std::sin(3 * t));
    };
    const Loop loops[] = {
        {"lopsided saddle", 32, saddle, 0.0},
        {"(2,3) torus knot", 48, knot, 0.0},
    };
    for (const Loop& l : loops) {
        const Garment g = closedYarn(l.points, l.at);
        // What the old rule (no correction) would leave at the closing point:
        // the frame's holonomy plus the twist over the loop, modulo a turn.
        const double holonomy = loopHolonomy(g), loop = curveLength(g);
        const double seamA = wrapAngle(l.twist * loop + holonomy), seamB = wrapAngle(l.twist * loop - holonomy);
        INFO(l.name << ": holonomy " << holonomy << " rad, twist " << l.twist << " over a loop of " << loop
                    << ": an uncorrected seam of " << seamA << " or " << seamB << " rad");
        REQUIRE(std::min(std::abs(seamA), std::abs(seamB)) > 0.05);
        for (int perSegment : {25, 8}) {
            SliceOptions opt;
            opt.radius = 0.3;
            opt.twist = l.twist;
            opt.slicesPerSegment = perSegment;
            const SlicePlan plan = planSlices(g, opt);
            const std::vector<double> a = loopAngles(plan);
            const std::size_t n = a.size();
            const double closing = a[n - 1], before = a[n - 2], after = a[0];
            INFO(perSegment << " slices per segment: step before the closing point " << before << " rad, across it "
                            << closing << ", after it " << after);
            for (double neighbour : {before, after}) {
                // 1 % of the neighbour, or 1e-3 rad where the neighbour is near
                // zero (below 0.1 rad, where 1 % is less than 1e-3).
                CHECK(std::abs(closing - neighbour) <= std::max(0.01 * std::abs(neighbour), 1e-3));
            }
        }
    }
}

// =================================================================== 4. crossing yarns

namespace {

void checkCrossing(Backend backend, int rv) {
    const CrossSection xs = makeDiskCrossSection();
    struct Pair {
        glm::dvec3 a, b;
    };
    const Pair pairs[] = {{{1, 0, 0}, {0, 1, 0}}, {{1, 0.4, 0.25}, {-0.3, 1, 0.5}}};
    const glm::dvec3 centre(0.1, 0.2, 0.3);
    for (const Pair& pr : pairs) {
        StraightCase ca, cb;
        ca.radius = cb.radius = 1.0;
        ca.h = cb.h = 1.0 / rv;
        ca.length = cb.length = 6;
        ca.axis = glm::normalize(pr.a);
        cb.axis = glm::normalize(pr.b);
        ca.start = centre - 3.0 * ca.axis;
        cb.start = centre - 3.0 * cb.axis;
        Garment g = test::straightYarn(ca.start, ca.axis, ca.length);
        g.yarns.push_back(test::straightYarn(cb.start, cb.axis, cb.length).yarns[0]);
        SliceOptions opt;
        opt.radius = 1.0;
        opt.spacing = defaultSliceSpacing(ca.h, 1);
        const SlicePlan plan = planSlices(g, opt);
        const VoxelGrid grid = makeGrid(plan, 0, ca.h);
        const BrickVolume clamp = voxelize(backend, plan, xs, grid, Overlap::Clamp);
        const BrickVolume sum = voxelize(backend, plan, xs, grid, Overlap::Sum);
        INFO(toString(backend) << ": yarns along " << str(pr.a) << " and " << str(pr.b) << ", r = " << rv << " voxels");

        // Clamp: nothing above 1, and the tally saw (and removed) the stacking.
        float worst = 0.0f;
        forActive(clamp, [&](glm::ivec3, float d) { worst = std::max(worst, d); });
        const ResolveTally& t = clamp.tally;
        INFO("clamp: largest density " << worst << "; tally: active " << t.activeVoxels << ", over one "
                                       << t.voxelsOverOne << ", density sum " << t.densitySum << ", raw "
                                       << t.rawDensitySum << ", excess " << t.excessOverOne);
        CHECK(worst <= 1.0f + 1e-6f);
        CHECK(t.voxelsOverOne > 0);
        CHECK(t.excessOverOne > 0.0);
        CHECK(t.activeVoxels == clamp.activeVoxelCount());
        CHECK(std::abs(t.rawDensitySum - t.densitySum - t.excessOverOne) <= 1e-6 * t.rawDensitySum);
        CHECK(t.densitySum * std::pow(grid.voxelSize, 3) == Approx(clamp.totalMass()).epsilon(1e-6));
        CHECK(sum.tally.rawDensitySum == Approx(t.rawDensitySum).epsilon(1e-9));
        CHECK(sum.tally.voxelsOverOne == t.voxelsOverOne);

        // Per voxel, clamping is min(sum, 1).
        const test::VolumeIndex clampIndex(clamp);
        std::uint64_t mismatched = 0, overOneInSum = 0;
        forActive(sum, [&](glm::ivec3 v, float d) {
            overOneInSum += d > 1.0f + 1e-6f;
            mismatched += std::abs(double(clampIndex.density(v)) - std::min(double(d), 1.0)) > 1e-6;
        });
        INFO("sum: " << overOneInSum << " voxels above 1; " << mismatched << " voxels where clamp != min(sum, 1)");
        CHECK(overOneInSum > 0);
        CHECK(mismatched == 0);
        CHECK(clamp.activeVoxelCount() == sum.activeVoxelCount());

        // Sum: voxels wholly inside both yarns hold both yarns' fibre.
        InteriorStats both;
        both.target = 2.0;
        const test::VolumeIndex sumIndex(sum);
        forVoxelsIn(grid, centre - 1.0, centre + 1.0, [&](glm::ivec3 v, glm::dvec3 p) {
            if (insideStraight(ca, p) && insideStraight(cb, p)) both.add(sumIndex.density(v));
        });
        const double expected = 2.0 * M_PI * 6.0;
        INFO("inside both, sum: " << both.text());
        // Reported only: the straight-yarn cases check the mass of straight yarns.
        INFO("sum mass " << sum.totalMass() << " expected " << expected << " ratio " << sum.totalMass() / expected);
        // Two perpendicular cylinders of radius r' share 16 r'^3 / 3; oblique ones more.
        const double inner = rv - 0.5 * kSqrt3;
        CHECK(double(both.count) >= 0.5 * 16.0 / 3.0 * inner * inner * inner);
        CHECK(both.within == both.count);
    }
}

} // namespace

TEST_CASE("Fidelity: crossing yarns clamp at 1, or sum to 2 inside both (CPU)", "[fidelity]") {
    checkCrossing(Backend::Cpu, 8);
}

TEST_CASE("Fidelity: crossing yarns clamp at 1, or sum to 2 inside both (GL)", "[fidelity][gl]") {
    YV_REQUIRE_GL();
    checkCrossing(Backend::Gl, 4);
}

// =================================================================== 5. resolutions

TEST_CASE("Fidelity: the test's distance to a wavy yarn is exact", "[fidelity]") {
    const WavyYarn w;
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> along(3.0, w.length - 3.0), off(-1.5, 1.5);
    double worst = 0.0;
    for (int i = 0; i < 200; ++i) {
        const double x = along(rng);
        const glm::dvec3 p = w.at(x) + glm::dvec3(off(rng), off(rng), off(rng)) * w.radius;
        worst = std::max(worst, std::abs(w.distance(p) - w.distanceScan(p)));
    }
    CHECK(worst < 1e-6);
}

TEST_CASE("Fidelity: interior densities stay within 5 % of 1 from resolution 256 to 4096", "[fidelity]") {
    const WavyYarn w;
    const CrossSection xs = makeDiskCrossSection();
    const double length = curveLength(w.garment, 200);
    for (int res : {256, 512, 1024, 2048, 4096}) {
        // The command line's defaults: one slice per voxel along the yarn.
        const double h = voxelSizeFor(w.garment, w.radius, res, 0.0);
        SliceOptions opt;
        opt.radius = w.radius;
        opt.spacing = defaultSliceSpacing(h, 1);
        const SlicePlan plan = planSlices(w.garment, opt);
        const VoxelGrid grid = makeGrid(plan, res, 0.0);
        REQUIRE(grid.voxelSize == Approx(h).epsilon(1e-12));
        const BrickVolume vol = voxelize(Backend::Cpu, plan, xs, grid, Overlap::Sum);

        // Interior voxels, column by column along x, away from the yarn's ends.
        const test::VolumeIndex index(vol);
        tbb::enumerable_thread_specific<std::vector<float>> found;
        tbb::parallel_for(0, grid.dims.x, [&](int i) {
            const double px = grid.origin.x + (i + 0.5) * h;
            if (px < 3.0 * w.radius || px > w.length - 3.0 * w.radius) return;
            const glm::dvec3 c = w.at(px);
            const double span = 1.3 * w.radius;
            glm::ivec3 first, last;
            voxelRange(grid, {px, c.y - span, c.z - span}, {px, c.y + span, c.z + span}, first, last);
            std::vector<float>& out = found.local();
            for (int j = first.y; j <= last.y; ++j)
                for (int k = first.z; k <= last.z; ++k) {
                    const glm::ivec3 v(i, j, k);
                    if (w.distance(voxelCenter(grid, v)) + 0.5 * kSqrt3 * h <= w.radius) out.push_back(index.density(v));
                }
        });
        std::vector<float> d;
        for (const std::vector<float>& part : found) d.insert(d.end(), part.begin(), part.end());
        std::sort(d.begin(), d.end());
        REQUIRE(!d.empty());
        const double p1 = d[std::size_t(std::floor(0.01 * double(d.size() - 1)))];
        const double p99 = d[std::size_t(std::ceil(0.99 * double(d.size() - 1)))];
        const double estimate = interiorEstimate(w.radius / h, (w.length - 6.0 * w.radius) / h);
        INFO("resolution " << res << ": r = " << w.radius / h << " voxels, " << plan.sliceCount << " slices, "
                           << vol.activeVoxelCount() << " active voxels; " << d.size() << " interior voxels (estimate "
                           << estimate << "): min " << d.front() << ", 1st percentile " << p1 << ", 99th " << p99
                           << ", max " << d.back() << "; mass / (pi r^2 L) "
                           << vol.totalMass() / (M_PI * w.radius * w.radius * length));
        CHECK(double(d.size()) >= 0.5 * estimate);
        CHECK(std::abs(p1 - 1.0) <= 0.05);
        CHECK(std::abs(p99 - 1.0) <= 0.05);
    }
}

// =================================================================== 6. backend agreement

TEST_CASE("Fidelity: GL and CPU agree voxel by voxel on a generated garment at default spacing", "[fidelity][gl]") {
    YV_REQUIRE_GL();
    struct Case {
        WeavePattern pattern;
        GarmentShape shape;
        double twist;
        bool disk;
    };
    const Case cases[] = {
        {WeavePattern::Twill, GarmentShape::Cylinder, 2.0, false},
        {WeavePattern::Knit, GarmentShape::Flat, 1.0, true},
    };
    for (const Case& c : cases) {
        GenerateOptions go;
        go.pattern = c.pattern;
        go.shape = c.shape;
        go.crossings = 64;
        go.seed = 3;
        const Garment garment = generateGarment(go);
        const int res = 96;
        const double h = voxelSizeFor(garment, garment.yarnRadius, res, 0.0);
        SliceOptions opt;
        opt.radius = garment.yarnRadius;
        opt.twist = c.twist;
        opt.spacing = defaultSliceSpacing(h, 1);
        const SlicePlan plan = planSlices(garment, opt);
        const VoxelGrid grid = makeGrid(plan, res, 0.0);
        const CrossSection xs = c.disk ? makeDiskCrossSection() : makeFiberCrossSection();
        const Agreement a = agree(voxelize(Backend::Cpu, plan, xs, grid), voxelize(Backend::Gl, plan, xs, grid));
        INFO(toString(c.pattern) << " " << toString(c.shape) << ", twist " << c.twist << ", " << xs.name
                                 << " cross-section, resolution " << res << ", " << plan.sliceCount << " slices");
        checkAgreement(a, 10000);
    }
}

TEST_CASE("Fidelity: GL and CPU agree voxel by voxel on yarns at an exact 45 degree tie", "[fidelity][gl]") {
    YV_REQUIRE_GL();
    const CrossSection xs = makeDiskCrossSection();
    for (glm::dvec3 dir : {glm::dvec3(1, 1, 0), glm::dvec3(0, 1, 1), glm::dvec3(1, 1, 1), glm::dvec3(-1, 1, 1)}) {
        const double r = 1.0 / 3.0, h = r / 5.0;
        const glm::dvec3 axis = glm::normalize(dir);
        SliceOptions opt;
        opt.radius = r;
        opt.spacing = defaultSliceSpacing(h, 1);
        const SlicePlan plan = planSlices(test::straightYarn({0.1, 0.2, 0.3}, axis, 3), opt);
        const VoxelGrid grid = makeGrid(plan, 0, h);
        const Agreement a = agree(voxelize(Backend::Cpu, plan, xs, grid), voxelize(Backend::Gl, plan, xs, grid));
        INFO("axis " << str(dir) << ", r = 5 voxels, " << plan.sliceCount << " slices");
        checkAgreement(a, 2000);
    }
}

