// `yarnvox inspect --render texture-slicing|half-angle|splatting`: the slice
// geometry, and each mode's picture of volumes built in code against what the
// geometry says and what the ray caster draws of the same atlas.
#include "cpu/cpu_voxelizer.h"
#include "garment/cross_section.h"
#include "garment/generate.h"
#include "garment/slices.h"
#include "gpu/egl_context.h"
#include "render/render_volume.h"
#include "inspect/slice_stack.h"
#include "render/slicing_renderer.h"
#include "run_cli.h"
#include "inspect_test_volumes.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>
#include <unistd.h>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>

using namespace yv;

namespace fs = std::filesystem;

namespace {

struct Scratch : test::ScratchDir {
    Scratch() : test::ScratchDir("yv_test_modes") {}
};

const RenderKind kModes[] = {RenderKind::TextureSlicing, RenderKind::HalfAngle, RenderKind::Splatting};

const char* modeName(RenderKind k) {
    return k == RenderKind::TextureSlicing ? "texture-slicing" : k == RenderKind::HalfAngle ? "half-angle" : "splatting";
}

using StraightYarn = test::StraightYarnVolume;

StraightYarn straightYarnVolume() { return test::straightYarnVolume(4); }

BrickVolume garmentVolume(int resolution) { return test::knitCylinderVolume(resolution); }

RenderReport render(const VolumeSource& source, RenderKind kind, const ViewAngles& view, int w, int h,
                    std::uint64_t budget = 1ull << 30) {
    RenderRequest r;
    r.kind = kind;
    r.view = view;
    r.width = w, r.height = h;
    r.gpuBudgetBytes = budget;
    RenderContext context; // as the command makes one for its pictures
    return renderVolume(context, source, r);
}

/// Pixels brighter than a faint trace (the splat kernel's far tail, a slice's rounding).
bool covered(const RgbImage& im, int x, int y) {
    const std::uint8_t* p = im.at(x, y);
    return int(p[0]) + int(p[1]) + int(p[2]) > 12;
}

int coveredPixels(const RgbImage& im) {
    int n = 0;
    for (int y = 0; y < im.height; ++y)
        for (int x = 0; x < im.width; ++x) n += covered(im, x, y);
    return n;
}

/// Intersection over union of two pictures' covered pixels.
double coverageIoU(const RgbImage& a, const RgbImage& b) {
    int both = 0, either = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            both += covered(a, x, y) && covered(b, x, y);
            either += covered(a, x, y) || covered(b, x, y);
        }
    return either ? double(both) / double(either) : 0.0;
}

/// Mean absolute difference of all channels, in 0..255.
double meanDifference(const RgbImage& a, const RgbImage& b) {
    double sum = 0.0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            for (int k = 0; k < 3; ++k) sum += std::abs(int(a.at(x, y)[k]) - int(b.at(x, y)[k]));
    return sum / (3.0 * a.width * a.height);
}

double meanBrightness(const RgbImage& im) {
    double sum = 0.0;
    for (int y = 0; y < im.height; ++y)
        for (int x = 0; x < im.width; ++x)
            for (int k = 0; k < 3; ++k) sum += im.at(x, y)[k];
    return sum / (3.0 * im.width * im.height);
}

/// The ray through pixel (x, y) (row 0 at the top), as the shaders build it.
void pixelRay(const Camera& c, int x, int y, glm::dvec3& origin, glm::dvec3& dir) {
    const glm::dmat4 inv = glm::inverse(c.viewProjection());
    const glm::dvec2 ndc(2.0 * (x + 0.5) / c.width - 1.0, 2.0 * (c.height - 1 - y + 0.5) / c.height - 1.0);
    const glm::dvec4 a = inv * glm::dvec4(ndc, -1.0, 1.0), b = inv * glm::dvec4(ndc, 1.0, 1.0);
    origin = glm::dvec3(a) / a.w;
    dir = glm::normalize(glm::dvec3(b) / b.w - origin);
}

double polygonArea(const std::vector<glm::dvec3>& p) {
    glm::dvec3 sum(0.0);
    for (std::size_t i = 1; i + 1 < p.size(); ++i) sum += glm::cross(p[i] - p[0], p[i + 1] - p[0]);
    return 0.5 * glm::length(sum);
}

} // namespace

TEST_CASE("slice stack: planes cut a box into the polygons and volume they must", "[inspect]") {
    const glm::dvec3 lo(1, 2, 3), hi(5, 8, 4);
    // Across an axis: the box's face.
    const auto square = boxSlice(lo, hi, {1, 0, 0}, 2.5);
    REQUIRE(square.size() == 4);
    CHECK(polygonArea(square) == Approx(6.0));
    // Through a cube's centre along its diagonal: a regular hexagon of side sqrt(2)/2 * edge.
    const auto hexagon = boxSlice({0, 0, 0}, {2, 2, 2}, {1, 1, 1}, glm::dot(glm::normalize(glm::dvec3(1, 1, 1)), glm::dvec3(1.0)));
    REQUIRE(hexagon.size() == 6);
    CHECK(polygonArea(hexagon) == Approx(3.0 * std::sqrt(3.0) / 2.0 * 2.0).epsilon(1e-9));
    CHECK(boxSlice(lo, hi, {0, 0, 1}, 4.5).empty());
    // The corners go round the normal: every fan triangle faces the same way.
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
    const auto polygon = boxSlice(lo, hi, n, glm::dot(n, 0.5 * (lo + hi)));
    REQUIRE(polygon.size() >= 3);
    for (std::size_t i = 1; i + 1 < polygon.size(); ++i)
        CHECK(glm::dot(glm::cross(polygon[i] - polygon[0], polygon[i + 1] - polygon[0]), n) > 0.0);
    // The slices' areas times their spacing add up to the box's volume.
    const SliceStack stack = sliceStack(lo, hi, n, 0.05);
    CHECK(int(stack.first.size()) == int(std::ceil(boxDepth(lo, hi, n) / 0.05)));
    double volume = 0.0;
    for (std::size_t k = 0; k < stack.first.size(); ++k)
        for (int i = 0; i < stack.count[k]; i += 3) {
            const glm::dvec3 a(stack.triangles[std::size_t(stack.first[k] + i)]), b(stack.triangles[std::size_t(stack.first[k] + i + 1)]),
                c(stack.triangles[std::size_t(stack.first[k] + i + 2)]);
            volume += 0.5 * glm::length(glm::cross(b - a, c - a)) * stack.spacing;
        }
    CHECK(volume == Approx(24.0).epsilon(0.01));
}

TEST_CASE("inspect modes: each mode covers the pixels a straight yarn's radius says", "[inspect][gl]") {
    YV_REQUIRE_GL();
    const StraightYarn yarn = straightYarnVolume();
    const auto source = memorySource(yarn.volume);
    const ViewAngles side{90.0, 0.0, 2.5}; // from +y: the yarn runs across
    const int w = 96, h = 64;
    const Camera camera = frameBox(source->bounds(), side, w, h);
    const glm::dvec3 axis = glm::normalize(yarn.end - yarn.start);
    const double length = glm::length(yarn.end - yarn.start);
    for (RenderKind kind : kModes) {
        const RenderReport r = render(*source, kind, side, w, h);
        REQUIRE(r.level == 0);
        // A splat reaches past its voxel by up to its kernel's cut (1.2 voxels).
        const double margin = kind == RenderKind::Splatting ? 2.5 : 1.5;
        int inside = 0, outside = 0, wrongInside = 0, wrongOutside = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                glm::dvec3 o, d;
                pixelRay(camera, x, y, o, d);
                const glm::dvec3 wv = o - yarn.start;
                const double b = glm::dot(d, axis), den = 1.0 - b * b;
                const double s = (glm::dot(wv, axis) - b * glm::dot(wv, d)) / den;
                const double t = (b * glm::dot(wv, axis) - glm::dot(wv, d)) / den;
                const double dist = glm::length(wv + t * d - s * axis);
                if (s > 2.0 && s < length - 2.0 && dist < yarn.radiusVoxels - margin) {
                    ++inside;
                    wrongInside += !covered(r.image, x, y);
                } else if (dist > yarn.radiusVoxels + margin || s < -yarn.radiusVoxels - 2.0 ||
                           s > length + yarn.radiusVoxels + 2.0) {
                    ++outside;
                    wrongOutside += covered(r.image, x, y);
                }
            }
        INFO(modeName(kind) << ": " << inside << " pixels inside the silhouette (" << wrongInside << " uncovered), "
                            << outside << " outside (" << wrongOutside << " covered)");
        CHECK(inside > 300);
        CHECK(outside > 1500);
        CHECK(wrongInside == 0);
        CHECK(wrongOutside == 0);
    }
}

TEST_CASE("inspect modes: each mode agrees with the ray caster on a knit cylinder", "[inspect][gl]") {
    YV_REQUIRE_GL();
    const BrickVolume volume = garmentVolume(96);
    const auto source = memorySource(volume);
    const ViewAngles view{30.0, 20.0, 3.0};
    const int w = 96, h = 72;
    const RenderReport ray = render(*source, RenderKind::Raycast, view, w, h);
    // The ray caster from a quarter turn away: what a wrong framing would show.
    const RenderReport turned = render(*source, RenderKind::Raycast, ViewAngles{120.0, 60.0, 3.0}, w, h);
    REQUIRE(coveredPixels(ray.image) > w * h / 10);
    REQUIRE(coverageIoU(ray.image, turned.image) < 0.75);
    for (RenderKind kind : kModes) {
        const RenderReport r = render(*source, kind, view, w, h);
        const double iou = coverageIoU(r.image, ray.image), diff = meanDifference(r.image, ray.image);
        std::printf("%s against raycast: coverage IoU %.3f, mean difference %.2f of 255, frame %.3f s\n", modeName(kind), iou,
                    diff, r.frameSeconds);
        INFO(modeName(kind) << ": coverage IoU " << iou << ", mean difference " << diff);
        CHECK(iou > 0.85);
        CHECK(coverageIoU(r.image, turned.image) < iou - 0.15);
        // Texture slicing samples the same voxels with the same transfer function, only at other depths.
        if (kind == RenderKind::TextureSlicing) CHECK(diff < 4.0);
        if (kind == RenderKind::Splatting) CHECK(diff < 12.0);
    }
}

TEST_CASE("inspect modes: splatting agrees with the ray caster on a coarse level", "[inspect][gl]") {
    YV_REQUIRE_GL();
    const BrickVolume volume = garmentVolume(128);
    const auto source = memorySource(volume);
    const ViewAngles view{30.0, 20.0, 3.0};
    const std::uint64_t budget = 256u << 10; // a level of 2x2x2 or more voxels each
    const RenderReport ray = render(*source, RenderKind::Raycast, view, 96, 72, budget);
    const RenderReport splats = render(*source, RenderKind::Splatting, view, 96, 72, budget);
    REQUIRE(ray.level >= 1);
    REQUIRE(splats.level == ray.level);
    const double iou = coverageIoU(splats.image, ray.image);
    std::printf("splatting at level %d against raycast: coverage IoU %.3f, mean difference %.2f of 255\n", splats.level, iou,
                meanDifference(splats.image, ray.image));
    CHECK(coveredPixels(ray.image) > 96 * 72 / 10);
    CHECK(iou > 0.8);
}

TEST_CASE("inspect modes: half-angle is brighter lit from the eye's side than from behind", "[inspect][gl]") {
    YV_REQUIRE_GL();
    RenderContext context;
    const BrickVolume volume = garmentVolume(96);
    const auto source = memorySource(volume);
    RenderRequest r;
    r.kind = RenderKind::HalfAngle;
    r.view = ViewAngles{30.0, 20.0, 3.0};
    r.width = 96, r.height = 72;
    r.light = LightAngles{30.0, 20.0}; // over the eye's shoulder: lit faces seen
    const RenderReport front = renderVolume(context, *source, r);
    r.light = LightAngles{210.0, -20.0}; // behind the garment: the eye sees the shadowed side
    const RenderReport back = renderVolume(context, *source, r);
    const RenderReport ray = render(*source, RenderKind::Raycast, r.view, r.width, r.height);
    std::printf("half-angle: brightness %.2f lit from the front, %.2f from behind\n", meanBrightness(front.image),
                meanBrightness(back.image));
    CHECK(meanBrightness(front.image) > 1.3 * meanBrightness(back.image));
    // The ambient share keeps the shadowed side visible: the same shape.
    CHECK(coverageIoU(back.image, ray.image) > 0.8);
    CHECK(coverageIoU(front.image, ray.image) > 0.85);
}

TEST_CASE("inspect modes: an empty volume and misplaced options fail with one clear line", "[inspect][gl]") {
    YV_REQUIRE_GL();
    const auto empty = memorySource(BrickVolume{});
    for (RenderKind kind : kModes)
        CHECK_THROWS_WITH(render(*empty, kind, ViewAngles{}, 32, 32), Catch::Contains("no active voxels"));
    CHECK_THROWS_WITH(parseLight("30"), Catch::Contains("--light '30'"));
    CHECK_THROWS_WITH(parseLight("30,100"), Catch::Contains("elevation"));
    CHECK_THROWS_WITH(parseRenderKind("slicing"), Catch::Contains("texture-slicing"));

    const Scratch scratch;
    const std::string dir = scratch.path.string();
    REQUIRE(test::runYarnvox("gen --pattern knit --crossings 20 --shape cylinder --seed 3 -o " + dir + "/g.bcc").exitCode == 0);
    REQUIRE(test::runYarnvox("voxelize " + dir + "/g.bcc -o " + dir + "/g.vdb --resolution 48 --quiet").exitCode == 0);
    const test::RunResult light = test::runYarnvox("inspect " + dir + "/g.vdb --render texture-slicing --light 10,10 -o " + dir + "/a.png");
    CHECK(light.exitCode != 0);
    CHECK_THAT(light.output, Catch::Contains("--light goes with --render half-angle"));
    const test::RunResult slices = test::runYarnvox("inspect " + dir + "/g.vdb --render raycast --slices 10 -o " + dir + "/b.png");
    CHECK(slices.exitCode != 0);
    CHECK_THAT(slices.output, Catch::Contains("--slices goes with"));
    const test::RunResult ok = test::runYarnvox("inspect " + dir + "/g.vdb --render half-angle --light 0,90 --slices 40 --size 64x48 -o " +
                                    dir + "/c.png --json");
    CHECK(ok.exitCode == 0);
    CHECK_THAT(ok.output, Catch::Contains("\"slices\": 40"));
}
