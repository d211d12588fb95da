// Cusps: knots where a curve stops and turns straight back (the knot's
// neighbours coincide, so the Catmull-Rom tangent there is zero). Real knits
// have them and renderers draw them; yarnvox voxelizes them with each side's
// own tangent, says so in one line, and leaves the rest of the yarn as it
// was. Every garment is built here, in code. docs/reliability.md lists them.
#include "bcc.h"

#include "core/error.h"
#include "cpu/cpu_voxelizer.h"
#include "garment/catmull_rom.h"
#include "garment/cross_section.h"
#include "garment/curve_check.h"
#include "gpu/gl_voxelizer.h"
#include "run_cli.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using namespace yv;

namespace {

/// Lines of `s` that hold `word`.
std::size_t linesWith(const std::string& s, const std::string& word) {
    std::size_t n = 0;
    for (std::size_t at = s.find(word); at != std::string::npos; at = s.find(word, s.find('\n', at)))
        ++n;
    return n;
}

/// A yarn along x that goes up a spike at x = 2 and comes straight back down:
/// point 3 (2, 1, 0) has the neighbours (2, 0, 0) and (2, 0, 0).
Yarn spikedYarn() { return Yarn{{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}, {5, 0, 0}}, false}; }
/// The same yarn without its spike.
Yarn plainYarn() { return Yarn{{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}, {5, 0, 0}}, false}; }

Garment garmentOf(std::vector<Yarn> yarns, double radius = 0.2) {
    Garment g;
    g.yarns = std::move(yarns);
    g.yarnRadius = radius;
    return g;
}

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

} // namespace

TEST_CASE("bad input: a cusp's tangent is the one each side has there, and elsewhere the derivative's", "[bad-input][curves]") {
    const Yarn spiked = spikedYarn();
    // Segment 3 leaves the cusp (2, 1, 0): zero derivative, so the direction is
    // the second derivative's, pointing back down towards (2, 0, 0).
    bool cusp = false;
    const SegmentPoints leaving = segmentPoints(spiked, 3, CurveType::CatmullRom);
    REQUIRE(glm::length(evalCatmullRomDerivative(leaving, 0.0)) == 0.0);
    const glm::dvec3 out = knotDirection(leaving, false, &cusp);
    CHECK(cusp);
    CHECK(out == evalCatmullRomSecondDerivative(leaving, 0.0));
    CHECK(glm::normalize(out).y < -0.9);
    // Segment 2 arrives at it going up: -C''(1).
    const SegmentPoints arriving = segmentPoints(spiked, 2, CurveType::CatmullRom);
    const glm::dvec3 in = knotDirection(arriving, true, &cusp);
    CHECK(cusp);
    CHECK(glm::normalize(in).y > 0.9);
    // The limits are the tangents just beside the knot.
    CHECK(glm::dot(glm::normalize(out), glm::normalize(evalCatmullRomDerivative(leaving, 1e-6))) > 0.999999);
    CHECK(glm::dot(glm::normalize(in), glm::normalize(evalCatmullRomDerivative(arriving, 1.0 - 1e-6))) > 0.999999);
    // Elsewhere: the first derivative, the same numbers.
    for (std::size_t s : {0, 1, 4, 5, 6}) {
        const SegmentPoints p = segmentPoints(spiked, s, CurveType::CatmullRom);
        CHECK(knotDirection(p, false, &cusp) == evalCatmullRomDerivative(p, 0.0));
        CHECK_FALSE(cusp);
    }
    // A B-spline's triple point: first and second derivatives vanish, the third leads.
    const Yarn triple{{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 0, 0}, {2, 0, 0}, {3, 1, 0}}, false};
    const SegmentPoints t = segmentPoints(triple, 2, CurveType::BSpline);
    CHECK(glm::length(knotDirection(t, false, &cusp) - evalCatmullRomThirdDerivative(t)) < 1e-12);
    CHECK(cusp);
    // A segment that does not move has no direction at all.
    const Yarn still{{{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0}, {2, 0, 0}}, false};
    CHECK(knotDirection(segmentPoints(still, 1, CurveType::BSpline), false) == glm::dvec3(0.0));
}

TEST_CASE("bad input: cusps are kept, counted and named in one line by checkCurves", "[bad-input][curves]") {
    // One cusp: named by curve and point.
    Garment one = garmentOf({plainYarn(), spikedYarn()});
    CurveCheckReport report = checkCurves(one, "spike.bcc");
    CHECK(report.cusps == 1);
    REQUIRE(report.warnings.size() == 1);
    CHECK_THAT(report.warnings[0], Contains("spike.bcc: curve 1 point 3: the curve stops there and turns straight back") &&
                                       Contains("voxelized as a cusp"));
    CHECK(one.yarns[1].points.size() == 8); // nothing dropped, nothing moved

    // Named by the file's index, after repeated points are dropped.
    Garment repeated = garmentOf({Yarn{{{0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1, 0, 0}, {1, 1, 0}}, false}});
    report = checkCurves(repeated, "idx.bcc");
    CHECK(report.cusps == 1);
    CHECK_THAT(report.warnings.at(0), Contains("idx.bcc: curve 0 point 4:"));

    // Many, on many curves (checked side by side): one line, the count and the first in file order.
    std::vector<Yarn> yarns(300, plainYarn());
    for (std::size_t i : {17, 40, 299}) yarns[i] = spikedYarn();
    yarns[40].points.insert(yarns[40].points.end(), {{6, 0, 0}, {7, 0, 0}, {6, 0, 0}, {5, 1, 0}}); // a second one at point 9
    Garment many = garmentOf(yarns);
    report = checkCurves(many, "many.bcc");
    CHECK(report.cusps == 4);
    REQUIRE(report.warnings.size() == 1);
    CHECK_THAT(report.warnings[0], Contains("many.bcc: 4 points where a curve stops and turns straight back") &&
                                       Contains("the first at curve 17 point 3") && Contains("voxelized as cusps"));

    // A closed curve whose cusp is its first point (its neighbours: the last point and point 1), counted once.
    Garment closed = garmentOf({Yarn{{{0, 1, 0}, {0, 0, 0}, {1, -1, 0}, {2, 0, 0}, {1, 1, 0}, {0, 0, 0}}, true}});
    report = checkCurves(closed, "loop.bcc");
    CHECK(report.cusps == 1);
    CHECK_THAT(report.warnings.at(0), Contains("loop.bcc: curve 0 point 0:"));

    // B-splines and Bezier curves whose derivative vanishes at a knot are cusps too.
    Garment bspline = garmentOf({Yarn{{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 0, 0}, {2, 0, 0}, {3, 1, 0}}, false}});
    bspline.curveType = CurveType::BSpline;
    CHECK(checkCurves(bspline, "bs.bcc").cusps == 1);
    Garment bezier = garmentOf({Yarn{{{0, 0, 0}, {0, 0, 0}, {2, 1, 0}, {3, 0, 0}}, false}});
    bezier.curveType = CurveType::Bezier;
    CHECK_THAT(checkCurves(bezier, "bz.bcc").warnings.at(0), Contains("bz.bcc: curve 0 point 0:"));

    // Without cusps: no line.
    Garment plain = garmentOf({plainYarn()});
    CHECK(checkCurves(plain, "plain.bcc").warnings.empty());

    // A segment that does not move at all (a B-spline's quadruple point) is still no curve.
    Garment still = garmentOf({Yarn{{{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0}, {2, 0, 0}}, false}});
    still.curveType = CurveType::BSpline;
    CHECK_THROWS_WITH(checkCurves(still, "still.bcc"), Contains("still.bcc: curve 0 point") && Contains("does not move") &&
                                                           Contains("not a curve"));
}

TEST_CASE("bad input: a yarn with a cusp is sliced with whole frames, and voxelized the same away from it", "[bad-input][curves]") {
    const Garment spiked = garmentOf({spikedYarn()});
    SliceOptions opt;
    opt.radius = 0.2;
    opt.spacing = 0.05;
    opt.twist = 2.0;
    const SlicePlan plan = planSlices(spiked, opt);
    for (const SegmentRecord& seg : plan.segments)
        for (std::uint32_t k = 0; k < seg.sliceCount; ++k) {
            const Slice s = placeSlice(seg, k);
            INFO("segment " << &seg - plan.segments.data() << " slice " << k);
            REQUIRE((finite(s.center) && finite(s.tangent) && finite(s.right) && finite(s.up) && finite(s.curvature)));
            CHECK(std::abs(glm::length(s.tangent) - 1.0) < 1e-9);
            CHECK(std::abs(glm::dot(s.tangent, s.right)) < 1e-9);
            CHECK(std::abs(glm::dot(s.right, s.up)) < 1e-9);
        }
    // The segment leaving the cusp starts its frame on the tangent it leaves by (down).
    CHECK(plan.segments[3].knotTangent.y < -0.9);

    // Voxels on a grid that holds both: before the spike (x < 0.6, reached only
    // by segment 0, the same in both yarns) the same bits; after it (x > 3.4,
    // the same segments, a frame turned by the cusp) the same within rounding.
    const SlicePlan reference = planSlices(garmentOf({plainYarn()}), opt);
    const VoxelGrid grid = makeGrid(plan, 0, 0.05);
    const CrossSection disk = makeDiskCrossSection();
    const BrickVolume got = voxelizeCpu(plan, disk, grid, VoxelizeSettings{});
    const BrickVolume want = voxelizeCpu(reference, disk, grid, VoxelizeSettings{});
    const test::VolumeIndex gotAt(got), wantAt(want);
    std::size_t before = 0, after = 0;
    for (const VoxelBrick& b : want.bricks)
        for (int i = 0; i < kBrickVoxels; ++i) {
            if (!b.isActive(i)) continue;
            const glm::ivec3 v = 8 * brickCoord(b.key) + glm::ivec3(i >> 6, (i >> 3) & 7, i & 7); // brickOffset's order
            const double x = grid.origin.x + (v.x + 0.5) * grid.voxelSize;
            if (x < 0.6) {
                ++before;
                CHECK(gotAt.density(v) == b.density[i]);
            } else if (x > 3.4) {
                ++after;
                CHECK(std::abs(gotAt.density(v) - b.density[i]) < 1e-6);
            }
        }
    CHECK(before > 100);
    CHECK(after > 100);
    // The spike adds its own length of yarn: two arms of about 1 each.
    const double added = got.totalMass() - want.totalMass();
    const double spikeLength = plan.segments[2].length + plan.segments[3].length;
    INFO("mass added " << added << ", pi r^2 times the spike's length " << M_PI * 0.04 * spikeLength);
    CHECK(added > 0.5 * M_PI * 0.04 * spikeLength);
    CHECK(added < 1.5 * M_PI * 0.04 * spikeLength);
}

TEST_CASE("bad input: a garment with cusps voxelizes, saying so in one line", "[bad-input][cli]") {
    test::ScratchDir dir("yv_cusps");
    const fs::path bcc = dir.path / "knit.bcc", vdb = dir.path / "knit.vdb";
    Garment g = garmentOf({plainYarn(), spikedYarn()});
    for (Yarn& y : g.yarns)
        for (glm::dvec3& p : y.points) p.z += 0.5 * (&y - g.yarns.data());
    writeBcc(bcc.string(), g);
    test::RunResult r = test::runYarnvox("voxelize " + bcc.string() + " -o " + vdb.string() + " --backend cpu --resolution 64");
    INFO(r.output);
    CHECK(r.exitCode == 0);
    CHECK(fs::exists(vdb));
    CHECK_THAT(r.output, Contains("warning: " + bcc.string() + ": curve 1 point 3: the curve stops there"));
    CHECK(linesWith(r.output, "warning") == 1);
    CHECK(linesWith(r.output, " point ") == 1);

    // Many: still one line.
    g.yarns = std::vector<Yarn>(40, spikedYarn());
    for (std::size_t i = 0; i < g.yarns.size(); ++i)
        for (glm::dvec3& p : g.yarns[i].points) p.z += 0.5 * double(i);
    writeBcc(bcc.string(), g);
    fs::remove(vdb);
    r = test::runYarnvox("voxelize " + bcc.string() + " -o " + vdb.string() + " --backend cpu --resolution 64");
    CHECK(r.exitCode == 0);
    CHECK(fs::exists(vdb));
    CHECK_THAT(r.output, Contains(": 40 points where a curve stops and turns straight back") &&
                             Contains("the first at curve 0 point 3"));
    CHECK(linesWith(r.output, "warning") == 1);
    CHECK(linesWith(r.output, " point ") == 1);
}

TEST_CASE("GL agrees with the CPU reference on a yarn with a cusp", "[gl][agreement]") {
    YV_REQUIRE_GL();
    const GlContext context;
    SliceOptions opt;
    opt.radius = 0.2;
    opt.spacing = 0.05;
    opt.twist = 2.0;
    const SlicePlan plan = planSlices(garmentOf({spikedYarn()}), opt);
    const VoxelGrid grid = makeGrid(plan, 0, 0.05);
    const CrossSection xs = makeFiberCrossSection();
    GlVoxelizeSettings gl;
    gl.brickResolve = BrickResolve::Gpu;
    const test::VolumeComparison cmp =
        test::compareVolumes(voxelizeCpu(plan, xs, grid, VoxelizeSettings{}), voxelizeGl(plan, xs, grid, gl, context));
    INFO("IoU " << cmp.iou << " mass ratio " << cmp.massRatio << " angle " << cmp.meanAngleDeg);
    CHECK(cmp.iou >= 0.999);
    CHECK(std::abs(cmp.massRatio - 1.0) <= 1e-4);
    CHECK(cmp.meanAngleDeg < 2.0);
}
