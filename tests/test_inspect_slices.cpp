// `yarnvox inspect --render slices` and `--regions`: the garment's slices
// drawn from the volume renders' camera, their back-to-front sort, and the
// zoom regions' outlines, checked against what the camera says they must show.
#include "core/error.h"
#include "cpu/cpu_voxelizer.h"
#include "garment/cross_section.h"
#include "garment/slices.h"
#include "gpu/egl_context.h"
#include "render/brick_atlas.h"
#include "inspect/brick_level.h"
#include "render/render_volume.h"
#include "render/raycast_renderer.h"
#include "inspect/region_outlines.h"
#include "render/slice_renderer.h"
#include "inspect/transfer_function.h"
#include "inspect_test_volumes.h"
#include "run_cli.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>
#include <unistd.h>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <random>

using namespace yv;
namespace fs = std::filesystem;

namespace {

bool covered(const RgbImage& im, int x, int y) {
    const std::uint8_t* p = im.at(x, y);
    return p[0] || p[1] || p[2];
}

/// The ray through pixel (x, y) (row 0 at the top), as the shaders build it.
void pixelRay(const Camera& c, int x, int y, glm::dvec3& origin, glm::dvec3& dir) {
    const glm::dmat4 inv = glm::inverse(c.viewProjection());
    const glm::dvec2 ndc(2.0 * (x + 0.5) / c.width - 1.0, 2.0 * (c.height - 1 - y + 0.5) / c.height - 1.0);
    const glm::dvec4 a = inv * glm::dvec4(ndc, -1.0, 1.0), b = inv * glm::dvec4(ndc, 1.0, 1.0);
    origin = glm::dvec3(a) / a.w;
    dir = glm::normalize(glm::dvec3(b) / b.w - origin);
}

glm::dvec2 projectToPixel(const Camera& c, glm::dvec3 p) {
    const glm::dvec4 clip = c.viewProjection() * glm::dvec4(p, 1.0);
    return {(clip.x / clip.w + 1.0) * 0.5 * c.width, (1.0 - clip.y / clip.w) * 0.5 * c.height};
}

} // namespace

TEST_CASE("inspect slices: the parallel sort orders slices back to front", "[inspect]") {
    SliceInstances slices;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 500.0f);
    const std::size_t n = 200000; // enough for TBB to split the sort
    for (std::size_t i = 0; i < n; ++i) {
        slices.records.push_back(glm::vec4(u(rng), u(rng), u(rng), 1.0f));
        slices.records.push_back(glm::vec4(0.0f, 0.0f, 1.0f, 2.0f));
    }
    // Equal distances too: the same centre twice.
    slices.records[2] = slices.records[0];
    const glm::dvec3 eye(-300.0, 250.0, 900.0);
    std::vector<std::uint32_t> order;
    sortBackToFront(slices, eye, order);
    REQUIRE(order.size() == n);
    std::vector<char> seen(n, 0);
    int repeated = 0, outOfOrder = 0;
    float previous = std::numeric_limits<float>::max();
    for (std::uint32_t i : order) {
        repeated += seen[i]++ != 0;
        const glm::vec3 d = slices.center(i) - glm::vec3(eye);
        const float dist = glm::dot(d, d);
        outOfOrder += dist > previous;
        previous = dist;
    }
    CHECK(repeated == 0);
    CHECK(outOfOrder == 0);
    // The farthest first, the nearest last.
    const glm::vec3 first = slices.center(order.front()) - glm::vec3(eye), last = slices.center(order.back()) - glm::vec3(eye);
    CHECK(glm::dot(first, first) > glm::dot(last, last));
}

TEST_CASE("inspect slices: a straight yarn seen side-on covers the pixels its radius says and what the ray cast covers", "[inspect][gl]") {
    YV_REQUIRE_GL();
    RenderContext context;
    const double radius = 0.3, h = radius / 8.0;
    const glm::dvec3 start(0.1, 0.2, 0.3);
    const int length = 5;
    SliceOptions opt;
    opt.radius = radius;
    opt.spacing = h;
    const SlicePlan plan = planSlices(test::straightYarn(start, {1, 0, 0}, length), opt);
    const VoxelGrid grid = makeGrid(plan, 0, h);
    const BrickVolume volume = voxelizeCpu(plan, makeDiskCrossSection(), grid, VoxelizeSettings{});
    const auto source = memorySource(volume);
    const VoxelBox box = source->bounds();
    const glm::dvec3 a = (start - grid.origin) / h, b = (start + glm::dvec3(length, 0, 0) - grid.origin) / h;
    const double radiusVoxels = radius / h;

    RenderRequest request;
    request.kind = RenderKind::Slices;
    request.view = ViewAngles{90.0, 0.0, 2.5}; // from +y: the yarn runs across
    request.width = 96, request.height = 64;
    const SliceInstances slices = sliceInstances(plan, grid);
    REQUIRE(slices.count() == plan.sliceCount);
    request.slices = &slices;
    const RenderReport rep = renderVolume(context, *source, request);
    CHECK(rep.slices == plan.sliceCount);
    CHECK(rep.sortSeconds >= 0.0);
    const Camera camera = frameBox(box, request.view, request.width, request.height);

    const glm::dvec3 axis = glm::normalize(b - a);
    const double span = glm::length(b - a);
    int inside = 0, outside = 0, wrongInside = 0, wrongOutside = 0;
    for (int y = 0; y < camera.height; ++y)
        for (int x = 0; x < camera.width; ++x) {
            glm::dvec3 o, d;
            pixelRay(camera, x, y, o, d);
            const glm::dvec3 w = o - a;
            const double bd = glm::dot(d, axis), den = 1.0 - bd * bd;
            const double s = (glm::dot(w, axis) - bd * glm::dot(w, d)) / den;
            const double t = (bd * glm::dot(w, axis) - glm::dot(w, d)) / den;
            const double dist = glm::length(w + t * d - s * axis);
            if (s > 2.0 && s < span - 2.0 && dist < radiusVoxels - 1.0) {
                ++inside;
                wrongInside += !covered(rep.image, x, y);
            } else if (dist > radiusVoxels + 1.0 || s < -2.0 || s > span + 2.0) {
                ++outside;
                wrongOutside += covered(rep.image, x, y);
            }
        }
    INFO(inside << " pixels inside the yarn's silhouette, " << outside << " outside");
    CHECK(inside > 500);
    CHECK(outside > 2000);
    CHECK(wrongInside == 0);
    CHECK(wrongOutside == 0);

    // The same camera's ray cast covers the same pixels, give or take the edge.
    request.kind = RenderKind::Raycast;
    const RenderReport ray = renderVolume(context, *source, request);
    int both = 0, either = 0;
    for (int y = 0; y < camera.height; ++y)
        for (int x = 0; x < camera.width; ++x) {
            both += covered(ray.image, x, y) && covered(rep.image, x, y);
            either += covered(ray.image, x, y) || covered(rep.image, x, y);
        }
    INFO("slices and ray cast agree on " << both << " of " << either << " pixels");
    CHECK(either > 500);
    CHECK(double(both) / double(either) > 0.9);

    // Seen along the yarn the slabs are disks: the picture is a disk too, not empty.
    request.kind = RenderKind::Slices;
    request.view = ViewAngles{0.0, 0.0, 2.5};
    const RenderReport endOn = renderVolume(context, *source, request);
    int endOnCovered = 0;
    for (int y = 0; y < request.height; ++y)
        for (int x = 0; x < request.width; ++x) endOnCovered += covered(endOn.image, x, y);
    CHECK(endOnCovered > 100);
}

TEST_CASE("inspect regions: outlines appear at the projected box edges in the colour of each region's heat", "[inspect][gl]") {
    YV_REQUIRE_GL();
    RenderContext context;
    const BrickVolume volume = test::knitCylinderVolume(64);
    const VoxelBox all = memorySource(volume)->bounds();
    // Three boxes apart from each other (no shared edges), hot, cool and between.
    const glm::ivec3 e = all.max - all.min;
    std::vector<RegionHeat> regions;
    for (int i = 0; i < 3; ++i) {
        VoxelBox b;
        b.min = all.min + glm::ivec3(e.x * i / 3 + 2, 2 + i, 2 + 2 * i);
        b.max = all.min + glm::ivec3(e.x * (i + 1) / 3 - 2, e.y - 2 - i, e.z - 3 - 2 * i);
        regions.push_back(RegionHeat{std::uint64_t(i), b, double(100 * (i == 1 ? 9 : i))});
    }
    RenderRequest request;
    request.kind = RenderKind::Mip;
    request.width = 160, request.height = 120;
    request.view = ViewAngles{35.0, 25.0, 3.5};
    const RenderReport plain = renderVolume(context, *memorySource(volume), request);
    request.outlines = regions;
    const RenderReport outlined = renderVolume(context, *memorySource(volume), request);
    const Camera camera = frameBox(all, request.view, request.width, request.height);

    const auto colourAt = [&](int x, int y) {
        const std::uint8_t* p = outlined.image.at(x, y);
        return glm::ivec3(p[0], p[1], p[2]);
    };
    const auto expected = [&](const RegionHeat& r) {
        return glm::ivec3(glm::round(255.0f * heatColour(r.heat / 900.0)));
    };
    // The middle of every edge has the region's colour.
    int edges = 0, rightColour = 0;
    std::vector<std::pair<glm::dvec2, glm::dvec2>> segments;
    for (const RegionHeat& r : regions) {
        const auto corner = [&](int c) {
            return glm::dvec3(c & 1 ? r.box.max.x : r.box.min.x, c & 2 ? r.box.max.y : r.box.min.y, c & 4 ? r.box.max.z : r.box.min.z);
        };
        for (int c = 0; c < 8; ++c)
            for (int axis = 0; axis < 3; ++axis) {
                if (c & (1 << axis)) continue;
                const glm::dvec2 p = projectToPixel(camera, corner(c)), q = projectToPixel(camera, corner(c | (1 << axis)));
                segments.emplace_back(p, q);
                const glm::dvec2 mid = 0.5 * (p + q);
                const int x = int(std::floor(mid.x)), y = int(std::floor(mid.y));
                if (x < 0 || y < 0 || x >= request.width || y >= request.height) continue;
                ++edges;
                // The line's pixels step by at most one: the middle's pixel or a neighbour is on it.
                bool found = false;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx)
                        if (x + dx >= 0 && y + dy >= 0 && x + dx < request.width && y + dy < request.height)
                            found = found || colourAt(x + dx, y + dy) == expected(r);
                rightColour += found;
            }
    }
    INFO(rightColour << " of " << edges << " edge midpoints in their region's colour");
    CHECK(edges >= 30);
    CHECK(rightColour >= edges - 1); // a crossing edge of another box may overwrite a middle
    // Every pixel that changed lies on a projected edge, or in the legend bar.
    int changed = 0, stray = 0;
    const int legendTop = request.height - 3 - std::max(2, request.height / 60);
    for (int y = 0; y < request.height; ++y)
        for (int x = 0; x < request.width; ++x) {
            const std::uint8_t *p = plain.image.at(x, y), *q = outlined.image.at(x, y);
            if (p[0] == q[0] && p[1] == q[1] && p[2] == q[2]) continue;
            if (y >= legendTop && x < 2 + request.width / 3) continue;
            ++changed;
            const glm::dvec2 c(x + 0.5, y + 0.5);
            double nearest = 1e9;
            for (const auto& [s0, s1] : segments) {
                const glm::dvec2 d = s1 - s0;
                const double t = glm::clamp(glm::dot(c - s0, d) / std::max(glm::dot(d, d), 1e-12), 0.0, 1.0);
                nearest = std::min(nearest, glm::length(s0 + t * d - c));
            }
            stray += nearest > 1.0;
        }
    CHECK(changed > 200);
    CHECK(stray == 0);
}

TEST_CASE("inspect slices: the command line finds the run's garment from a work directory and a .vdb", "[inspect][gl][cli]") {
    YV_REQUIRE_GL();
    const fs::path dir = fs::temp_directory_path() /
                         ("yv_test_slices_" + std::to_string(::getpid()) + "_" + std::to_string(std::random_device{}()));
    fs::create_directories(dir);
    struct Cleanup {
        fs::path p;
        ~Cleanup() { fs::remove_all(p); }
    } cleanup{dir};
    const std::string bcc = (dir / "g.bcc").string(), vdb = (dir / "g.vdb").string(), work = (dir / "work").string();
    const std::string png = (dir / "s.png").string();
    REQUIRE(test::runYarnvox("gen --pattern knit --crossings 40 --shape cylinder --seed 3 --quiet -o " + bcc).exitCode == 0);
    const auto v = test::runYarnvox("voxelize " + bcc + " -o " + vdb + " --resolution 48 --backend cpu --quiet --work-dir " + work);
    INFO(v.output);
    REQUIRE(v.exitCode == 0);
    for (const std::string& input : {work, vdb}) {
        const auto r = test::runYarnvox("inspect " + input + " --render slices --size 64x48 --repeat 2 --json -o " + png);
        INFO(input << ": " << r.output);
        CHECK(r.exitCode == 0);
        CHECK(r.output.find("\"sort_seconds_median\"") != std::string::npos);
        CHECK(r.output.find("\"slices\": 0") == std::string::npos);
        int drawn = 0;
        const RgbImage image = readPng(png);
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x) drawn += covered(image, x, y);
        CHECK(drawn > 64 * 48 / 20);
        fs::remove(png);
    }
    // The level of detail goes with the slices only.
    const auto lodElsewhere = test::runYarnvox("inspect " + vdb + " --render mip --slice-lod 2 -o " + png);
    INFO(lodElsewhere.output);
    CHECK(lodElsewhere.exitCode != 0);
    CHECK(lodElsewhere.output.find("--slice-lod goes with --render slices") != std::string::npos);
    CHECK(!fs::exists(png));
    // Each way of drawing the slabs by name, as the report says it drew them; a wrong name is one line.
    for (const std::string primitive : {"tiles", "points", "boxes"}) {
        const auto r = test::runYarnvox("inspect " + vdb + " --render slices --slice-lod 0 --slice-primitive " +
                                        primitive + " --size 64x48 --json -o " + png);
        INFO(primitive << ": " << r.output);
        CHECK(r.exitCode == 0);
        CHECK(r.output.find("\"slice_primitive\": \"" + primitive + "\"") != std::string::npos);
        fs::remove(png);
    }
    const auto badPrimitive = test::runYarnvox("inspect " + vdb + " --render slices --slice-primitive quads -o " + png);
    INFO(badPrimitive.output);
    CHECK(badPrimitive.exitCode != 0);
    CHECK(badPrimitive.output.find("expected auto, tiles, points or boxes") != std::string::npos);
    CHECK(!fs::exists(png));
    const auto outlines = test::runYarnvox("inspect " + work + " --render mip --regions --size 64x48 --json -o " + png);
    INFO(outlines.output);
    CHECK(outlines.exitCode == 0);
    CHECK(outlines.output.find("\"region_heat\"") != std::string::npos);
    fs::remove(png);

    // The garment moved: one line naming the way out; --garment gives it back.
    const std::string moved = (dir / "moved.bcc").string();
    fs::rename(bcc, moved);
    for (const std::string& args : {vdb + " --render slices", work + " --render cut --cut z:3 --regions",
                                    work + " --render mip --garment " + moved}) {
        const auto bad = test::runYarnvox("inspect " + args + " -o " + png);
        INFO(args << ": " << bad.output);
        CHECK(bad.exitCode != 0);
        CHECK(!fs::exists(png));
        CHECK(std::count(bad.output.begin(), bad.output.end(), '\n') <= 2);
    }
    const auto given = test::runYarnvox("inspect " + vdb + " --render slices --size 32x24 --garment " + moved + " -o " + png);
    INFO(given.output);
    CHECK(given.exitCode == 0);
    CHECK(given.output.find("slices of " + moved) != std::string::npos);
}

namespace {

/// The slices' picture worked out on the host, in doubles: per pixel, the
/// ray from the eye through its centre against every slab (the box of
/// SliceRenderer's vertex shader, its frame included), cut with the yarn's
/// cylinder, its opacity from the length crossed, its shade from the fibre
/// where the ray is halfway through (tilted by `twist` radians a voxel), and
/// the slabs blended back to front. The reference for the GPU's picture.
RgbImage referenceSlices(const SliceInstances& slices, const Camera& camera, double twist) {
    const glm::dmat4 inverseView = glm::inverse(camera.view);
    const glm::dvec3 light = glm::normalize(glm::dvec3(inverseView[2]) + 0.5 * glm::dvec3(inverseView[1]));
    const double radius = slices.radius, extinction = kSliceOpacityTimesRadius / radius;
    std::vector<std::uint32_t> order;
    sortBackToFront(slices, camera.eye, order);
    RgbImage out(camera.width, camera.height);
    for (int y = 0; y < camera.height; ++y)
        for (int x = 0; x < camera.width; ++x) {
            glm::dvec3 o, dir;
            pixelRay(camera, x, y, o, dir);
            glm::dvec3 colour(0.0);
            for (std::uint32_t i : order) {
                const glm::dvec3 centre(slices.records[2 * i]);
                const double half = 0.5 * slices.records[2 * i].w;
                const glm::dvec3 t(slices.records[2 * i + 1]);
                const glm::dvec3 helper = std::abs(t.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
                const glm::dvec3 r = glm::normalize(glm::cross(t, helper)), u = glm::cross(t, r);
                const glm::dvec3 e = camera.eye - centre;
                const glm::dvec3 eye(glm::dot(e, r), glm::dot(e, u), glm::dot(e, t));
                const glm::dvec3 d(glm::dot(dir, r), glm::dot(dir, u), glm::dot(dir, t));
                const glm::dvec3 size(radius, radius, half);
                double enter = -HUGE_VAL, leave = HUGE_VAL;
                for (int a = 0; a < 3; ++a) {
                    if (d[a] == 0.0) {
                        if (std::abs(eye[a]) > size[a]) enter = HUGE_VAL;
                        continue;
                    }
                    const double t1 = (-size[a] - eye[a]) / d[a], t2 = (size[a] - eye[a]) / d[a];
                    enter = std::max(enter, std::min(t1, t2));
                    leave = std::min(leave, std::max(t1, t2));
                }
                const double qa = d.x * d.x + d.y * d.y, qb = eye.x * d.x + eye.y * d.y;
                const double qc = eye.x * eye.x + eye.y * eye.y - radius * radius;
                const double disc = qb * qb - qa * qc;
                if (qa < 1e-12 || disc <= 0.0) continue;
                enter = std::max(enter, (-qb - std::sqrt(disc)) / qa);
                leave = std::min(leave, (-qb + std::sqrt(disc)) / qa);
                if (leave <= enter) continue;
                const double alpha = 1.0 - std::exp(-extinction * (leave - enter));
                const glm::dvec3 p = eye + 0.5 * (enter + leave) * d;
                const glm::dvec3 fibre = glm::normalize(-twist * p.y * r + twist * p.x * u + t);
                const double c = glm::dot(fibre, light);
                const glm::dvec3 shade = glm::dvec3(kSliceAlbedo) * (0.25 + 0.75 * std::sqrt(std::max(0.0, 1.0 - c * c)));
                colour = shade * alpha + (1.0 - alpha) * colour;
            }
            for (int ch = 0; ch < 3; ++ch) out.at(x, y)[ch] = std::uint8_t(std::clamp(colour[ch] * 255.0 + 0.5, 0.0, 255.0));
        }
    return out;
}

int coveredPixels(const RgbImage& im) {
    int n = 0;
    for (int y = 0; y < im.height; ++y)
        for (int x = 0; x < im.width; ++x) n += covered(im, x, y);
    return n;
}

/// Pixels whose channels differ by more than `levels`.
int pixelsOff(const RgbImage& a, const RgbImage& b, int levels) {
    int n = 0;
    for (std::size_t i = 0; i < a.pixels.size(); i += 3) {
        bool off = false;
        for (int ch = 0; ch < 3; ++ch) off = off || std::abs(int(a.pixels[i + ch]) - int(b.pixels[i + ch])) > levels;
        n += off;
    }
    return n;
}

} // namespace

TEST_CASE("inspect slices: a twisted yarn's fibres lean as the helix says, pixel by pixel, and a twist set later draws the same",
          "[inspect][gl]") {
    YV_REQUIRE_GL();
    RenderContext context;
    context.gl();
    // A straight yarn, seen from above at an angle; slices 3 voxels apart.
    const double radius = 0.3, h = radius / 8.0, lean = 1.0; // twist times radius: 45 degrees at the surface
    const glm::dvec3 start(0.1, 0.2, 0.3), direction = glm::normalize(glm::dvec3(1.0, 0.6, 0.2));
    const int length = 3;
    SliceOptions opt;
    opt.radius = radius;
    opt.spacing = 3.0 * h;
    opt.twist = lean / radius;
    const SlicePlan twistedPlan = planSlices(test::straightYarn(start, direction, length), opt);
    opt.twist = 0.0;
    const SlicePlan straightPlan = planSlices(test::straightYarn(start, direction, length), opt);
    const VoxelGrid grid = makeGrid(straightPlan, 0, h);
    const SliceInstances twisted = sliceInstances(twistedPlan, grid), straight = sliceInstances(straightPlan, grid);
    REQUIRE(twisted.twist == Approx(lean / radius * h));
    REQUIRE(straight.twist == 0.0f);

    const VoxelBox box{{0, 0, 0}, grid.dims};
    const Camera camera = frameBox(box, ViewAngles{35.0, 50.0, 2.0}, 96, 72);
    SliceSettings settings;
    settings.lodPixels = 0.0;
    const auto draw = [&](const SliceInstances& slices, std::optional<double> twist) {
        SliceRenderer renderer(slices, settings);
        if (twist) renderer.setTwist(*twist);
        RenderReport report;
        drawFrames(renderer, camera, 1, report);
        return report.image;
    };
    const RgbImage plain = draw(straight, std::nullopt), leaning = draw(twisted, std::nullopt);
    // The twist is the shading's alone: set on the untwisted slices it draws the same picture.
    CHECK(draw(straight, double(twisted.twist)).pixels == leaning.pixels);
    CHECK(draw(twisted, 0.0).pixels == plain.pixels);

    const int covered = int(coveredPixels(plain));
    INFO(covered << " pixels of yarn");
    REQUIRE(covered > 800);
    // Each picture is the reference's, but for a few pixels at slab edges (floats against doubles).
    const RgbImage plainReference = referenceSlices(straight, camera, 0.0);
    const RgbImage leaningReference = referenceSlices(straight, camera, twisted.twist);
    const RgbImage mirroredReference = referenceSlices(straight, camera, -twisted.twist);
    const int plainOff = pixelsOff(plain, plainReference, 3), leaningOff = pixelsOff(leaning, leaningReference, 3);
    INFO("off the reference by more than 3 levels: " << plainOff << " untwisted, " << leaningOff << " twisted");
    CHECK(plainOff <= covered / 50);
    CHECK(leaningOff <= covered / 50);
    // The test tells the twist and its sign: the other pictures are off in many pixels.
    const int againstPlain = pixelsOff(leaning, plainReference, 3), againstMirror = pixelsOff(leaning, mirroredReference, 3);
    INFO("the twisted picture against the untwisted reference: " << againstPlain << " off; against the opposite twist: "
                                                                << againstMirror);
    CHECK(againstPlain > covered / 5);
    CHECK(againstMirror > covered / 10);
}
