// `yarnvox inspect --render isosurface`, `--mesh` and `--render
// volumetric-triangles`: a straight yarn built in code, checked against the
// cylinder its radius says and against the ray caster.
#include "core/error.h"
#include "cpu/cpu_voxelizer.h"
#include "garment/cross_section.h"
#include "garment/slices.h"
#include "gpu/egl_context.h"
#include "render/brick_atlas.h"
#include "inspect/brick_level.h"
#include "render/render_volume.h"
#include "inspect/isosurface_mesh.h"
#include "inspect/png_image.h"
#include "render/raycast_renderer.h"
#include "inspect/transfer_function.h"
#include "render/volumetric_triangles.h"
#include "run_cli.h"
#include "inspect_test_volumes.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>
#include <unistd.h>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <algorithm>
#include <iterator>
#include <random>

using namespace yv;
namespace fs = std::filesystem;

namespace {

struct Scratch : test::ScratchDir {
    Scratch() : test::ScratchDir("yv_test_surface") {}
};

using StraightYarn = test::StraightYarnVolume;

StraightYarn straightYarnVolume() { return test::straightYarnVolume(5); }

/// The ray through pixel (x, y) (row 0 at the top), as the shaders build it.
void pixelRay(const Camera& c, int x, int y, glm::dvec3& origin, glm::dvec3& dir) {
    const glm::dmat4 inv = glm::inverse(c.viewProjection());
    const glm::dvec2 ndc(2.0 * (x + 0.5) / c.width - 1.0, 2.0 * (c.height - 1 - y + 0.5) / c.height - 1.0);
    const glm::dvec4 a = inv * glm::dvec4(ndc, -1.0, 1.0), b = inv * glm::dvec4(ndc, 1.0, 1.0);
    origin = glm::dvec3(a) / a.w;
    dir = glm::normalize(glm::dvec3(b) / b.w - origin);
}

/// Where a pixel's ray passes the yarn: `along` the axis from its start,
/// `distance` from it, and `above` (+z) or below it.
struct AxisPass {
    double along = 0.0, distance = 0.0, height = 0.0;
};

AxisPass passOf(const Camera& camera, const StraightYarn& yarn, int x, int y) {
    glm::dvec3 o, d;
    pixelRay(camera, x, y, o, d);
    const glm::dvec3 axis = glm::normalize(yarn.end - yarn.start);
    const glm::dvec3 w = o - yarn.start;
    const double b = glm::dot(d, axis), den = 1.0 - b * b;
    const double s = (glm::dot(w, axis) - b * glm::dot(w, d)) / den;
    const double t = (b * glm::dot(w, axis) - glm::dot(w, d)) / den;
    const glm::dvec3 gap = w + t * d - s * axis;
    return {s, glm::length(gap), gap.z};
}

double brightness(const RgbImage& im, int x, int y) {
    const std::uint8_t* p = im.at(x, y);
    return (double(p[0]) + double(p[1]) + double(p[2])) / 3.0;
}

/// A binary PLY as writeMesh writes it, read back.
IsosurfaceMesh readPly(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    REQUIRE(in);
    std::string line;
    std::size_t vertices = 0, faces = 0;
    while (std::getline(in, line) && line != "end_header") {
        if (line.rfind("element vertex ", 0) == 0) vertices = std::stoul(line.substr(15));
        if (line.rfind("element face ", 0) == 0) faces = std::stoul(line.substr(13));
    }
    REQUIRE(line == "end_header");
    IsosurfaceMesh mesh;
    mesh.vertices.resize(vertices);
    in.read(reinterpret_cast<char*>(mesh.vertices.data()), std::streamsize(vertices * sizeof(glm::vec3)));
    for (std::size_t i = 0; i < faces; ++i) {
        unsigned char n = 0;
        std::int32_t idx[3];
        in.read(reinterpret_cast<char*>(&n), 1);
        REQUIRE(n == 3);
        in.read(reinterpret_cast<char*>(idx), sizeof idx);
        mesh.triangles.push_back({std::uint32_t(idx[0]), std::uint32_t(idx[1]), std::uint32_t(idx[2])});
    }
    REQUIRE(in);
    in.peek();
    REQUIRE(in.eof());
    return mesh;
}

} // namespace

TEST_CASE("isosurface: a straight yarn seen side-on covers its silhouette and is lit from above", "[inspect][gl]") {
    YV_REQUIRE_GL();
    const StraightYarn yarn = straightYarnVolume();
    const auto source = memorySource(yarn.volume);
    const VoxelBox box = source->bounds();
    GlContext context;
    const LevelPlan plan = planLevel(*source, box, 1ull << 30, atlasBytesPerVoxel(false), context.info().max3dTextureSize);
    REQUIRE(plan.level == 0);
    BrickAtlas atlas(plan, false, context.info().max3dTextureSize);
    streamLevelBricks(*source, box, plan, false, [&](const LevelBrick& b) { atlas.upload(b); });
    atlas.finish();
    RaycastSettings settings;
    settings.isoValue = 0.5;
    const Camera camera = frameBox(box, ViewAngles{90.0, 0.0, 2.5}, 96, 64); // from +y, z up: the yarn runs across
    const test::RayCast r = test::rayCast(atlas, RenderMode::Isosurface, camera, settings);

    int inside = 0, outside = 0, wrongInside = 0, wrongOutside = 0;
    double upper = 0.0, lower = 0.0;
    int upperCount = 0, lowerCount = 0;
    for (int y = 0; y < camera.height; ++y)
        for (int x = 0; x < camera.width; ++x) {
            const AxisPass p = passOf(camera, yarn, x, y);
            const double length = glm::length(yarn.end - yarn.start);
            const bool lit = brightness(r.image, x, y) > 0.0;
            if (p.along > 2.0 && p.along < length - 2.0 && p.distance < yarn.radiusVoxels - 1.5) {
                ++inside;
                wrongInside += !lit;
                // The outer half of each side: normals there point well up or well down.
                if (p.distance > 0.4 * yarn.radiusVoxels) {
                    if (p.height > 0.0) upper += brightness(r.image, x, y), ++upperCount;
                    else lower += brightness(r.image, x, y), ++lowerCount;
                }
            } else if (p.distance > yarn.radiusVoxels + 1.5 || p.along < -yarn.radiusVoxels - 2.0 ||
                       p.along > length + yarn.radiusVoxels + 2.0) {
                ++outside;
                wrongOutside += lit;
            }
        }
    INFO(inside << " pixels inside the silhouette, " << outside << " outside");
    CHECK(inside > 500);
    CHECK(outside > 2000);
    CHECK(wrongInside == 0);
    CHECK(wrongOutside == 0);
    // The light comes from above the eye: the upper side of the yarn, whose
    // normals face it, is brighter than the lower side, which faces away.
    REQUIRE(upperCount > 50);
    REQUIRE(lowerCount > 50);
    INFO("mean brightness above the axis " << upper / upperCount << ", below " << lower / lowerCount);
    CHECK(upper / upperCount > 1.5 * (lower / lowerCount));
}

TEST_CASE("isosurface: a higher iso value draws a thinner yarn", "[inspect][gl]") {
    YV_REQUIRE_GL();
    RenderContext context;
    const StraightYarn yarn = straightYarnVolume();
    const auto source = memorySource(yarn.volume);
    RenderRequest request;
    request.kind = RenderKind::Isosurface;
    request.view = ViewAngles{90.0, 0.0, 2.5};
    request.width = 96;
    request.height = 64;
    const auto coveredPixels = [&](double iso) {
        request.isoValue = iso;
        const RenderReport rep = renderVolume(context, *source, request);
        int n = 0;
        for (int y = 0; y < rep.image.height; ++y)
            for (int x = 0; x < rep.image.width; ++x) n += brightness(rep.image, x, y) > 0.0;
        return n;
    };
    const int wide = coveredPixels(0.05), thin = coveredPixels(0.95);
    CHECK(thin > 0);
    CHECK(thin < wide);
    // No voxel is denser than 1: nothing reaches 1.5, and an empty picture is refused, naming the densities.
    CHECK_THROWS_WITH(coveredPixels(1.5), Catch::Contains("--iso 1.5: no voxel drawn reaches it") &&
                                              Catch::Contains("are at most 1"));
}

TEST_CASE("isosurface: an iso value above every density is refused in one line, with no picture", "[inspect][gl][cli]") {
    YV_REQUIRE_GL();
    test::ScratchDir scratch("yv_iso_above");
    const std::string bcc = (scratch.path / "g.bcc").string(), vdb = (scratch.path / "g.vdb").string(),
                      png = (scratch.path / "iso.png").string();
    REQUIRE(test::runYarnvox("gen --crossings 40 --quiet -o " + bcc).exitCode == 0);
    REQUIRE(test::runYarnvox("voxelize " + bcc + " -o " + vdb + " --backend cpu --resolution 64 --quiet").exitCode == 0);
    const auto r = test::runYarnvox("inspect " + vdb + " --render isosurface --iso 50 --size 32x32 -o " + png);
    INFO(r.output);
    CHECK(r.exitCode == 1);
    CHECK_THAT(r.output, Catch::StartsWith("yarnvox: error: --iso 50: no voxel drawn reaches it"));
    CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(png));
    CHECK(test::runYarnvox("inspect " + vdb + " --render isosurface --iso 0.05 --size 32x32 -o " + png).exitCode == 0);
}

TEST_CASE("isosurface mesh: a straight yarn's mesh lies on its cylinder with the cylinder's area", "[inspect]") {
    const StraightYarn yarn = straightYarnVolume();
    const auto source = memorySource(yarn.volume);
    Scratch scratch;
    const fs::path ply = scratch.path / "yarn.ply";
    writeMesh(ply.string(), extractIsosurface(*source, source->bounds(), 0.5, 0));
    const IsosurfaceMesh mesh = readPly(ply);
    REQUIRE(mesh.triangles.size() > 100);

    const glm::dvec3 axis = glm::normalize(yarn.end - yarn.start);
    const double length = glm::length(yarn.end - yarn.start), r = yarn.radiusVoxels;
    int side = 0, off = 0;
    for (const glm::vec3& v : mesh.vertices) {
        const glm::dvec3 w = glm::dvec3(v) - yarn.start;
        const double s = glm::dot(w, axis);
        if (s < 2.0 || s > length - 2.0) continue; // the caps
        ++side;
        off += std::abs(glm::length(w - s * axis) - r) > 1.0;
    }
    CHECK(side > 100);
    CHECK(off == 0);

    // Area and enclosed volume (divergence theorem: positive only when every
    // triangle faces outwards) against the capped cylinder's.
    double area = 0.0, volume = 0.0;
    for (const auto& t : mesh.triangles) {
        REQUIRE(std::max({t[0], t[1], t[2]}) < mesh.vertices.size());
        const glm::dvec3 a(mesh.vertices[t[0]]), b(mesh.vertices[t[1]]), c(mesh.vertices[t[2]]);
        area += 0.5 * glm::length(glm::cross(b - a, c - a));
        volume += glm::dot(a, glm::cross(b, c)) / 6.0;
    }
    const double pi = 3.14159265358979;
    const double cylinderArea = 2.0 * pi * r * length + 2.0 * pi * r * r, cylinderVolume = pi * r * r * length;
    INFO("mesh area " << area << " (cylinder " << cylinderArea << "), volume " << volume << " (" << cylinderVolume << ")");
    CHECK(std::abs(area - cylinderArea) < 0.06 * cylinderArea);
    CHECK(std::abs(volume - cylinderVolume) < 0.06 * cylinderVolume);

    // A coarser level: fewer triangles, the same cylinder within its coarser voxel.
    const IsosurfaceMesh coarse = extractIsosurface(*source, source->bounds(), 0.5, 1);
    CHECK(coarse.triangles.size() < mesh.triangles.size() / 2);
    CHECK(estimateMeshTriangles(*source, source->bounds(), 1) < estimateMeshTriangles(*source, source->bounds(), 0));
    CHECK_THROWS_AS(extractIsosurface(*source, source->bounds(), 1.5, 0), Error);
}

TEST_CASE("isosurface mesh: the command line writes .ply and .obj and refuses bad requests", "[inspect][cli]") {
    Scratch scratch;
    const fs::path bcc = scratch.path / "cloth.bcc", vdb = scratch.path / "cloth.vdb";
    auto run = test::runYarnvox("gen --crossings 40 -q -o " + bcc.string());
    REQUIRE(run.exitCode == 0);
    run = test::runYarnvox("voxelize " + bcc.string() + " --backend cpu --resolution 48 -q -o " + vdb.string());
    INFO(run.output);
    REQUIRE(run.exitCode == 0);
    const fs::path ply = scratch.path / "cloth.ply", obj = scratch.path / "cloth.obj";
    run = test::runYarnvox("inspect " + vdb.string() + " --mesh " + ply.string() + " --iso 0.3");
    INFO(run.output);
    REQUIRE(run.exitCode == 0);
    CHECK(readPly(ply).triangles.size() > 100);
    run = test::runYarnvox("inspect " + vdb.string() + " --mesh " + obj.string() + " --mesh-level 1 --iso 0.3");
    REQUIRE(run.exitCode == 0);
    std::ifstream in(obj);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    CHECK(text.find("\nv ") != std::string::npos);
    CHECK(text.find("\nf ") != std::string::npos);

    run = test::runYarnvox("inspect " + vdb.string() + " --mesh " + (scratch.path / "cloth.stl").string());
    CHECK(run.exitCode != 0);
    CHECK(run.output.find(".ply or .obj") != std::string::npos);
    run = test::runYarnvox("inspect " + vdb.string() + " --mesh-level 2");
    CHECK(run.exitCode != 0);
    CHECK(run.output.find("--mesh-level goes with --mesh") != std::string::npos);
    const fs::path none = scratch.path / "none.ply";
    run = test::runYarnvox("inspect " + vdb.string() + " --mesh " + none.string() + " --iso 5");
    CHECK(run.exitCode != 0);
    CHECK(run.output.find("isosurface is empty") != std::string::npos);
    CHECK_FALSE(fs::exists(none));
}

TEST_CASE("volumetric triangles: a straight yarn covers its band and agrees with the ray caster", "[inspect][gl]") {
    YV_REQUIRE_GL();
    RenderContext context;
    const StraightYarn yarn = straightYarnVolume();
    const auto source = memorySource(yarn.volume);
    RenderRequest request;
    request.view = ViewAngles{90.0, 0.0, 2.5}; // from +y: the yarn runs across
    request.width = 96;
    request.height = 64;
    request.kind = RenderKind::Raycast;
    const RenderReport raycast = renderVolume(context, *source, request);
    request.kind = RenderKind::VolumetricTriangles;
    const RenderReport soft = renderVolumetricTriangles(context, yarn.plan, yarn.grid, source->bounds(), request);
    const Camera camera = frameBox(source->bounds(), request.view, request.width, request.height);

    const double length = glm::length(yarn.end - yarn.start);
    int inside = 0, outside = 0, wrongInside = 0, wrongOutside = 0, disagree = 0, rayCovered = 0;
    for (int y = 0; y < camera.height; ++y)
        for (int x = 0; x < camera.width; ++x) {
            const AxisPass p = passOf(camera, yarn, x, y);
            const bool lit = brightness(soft.image, x, y) >= 10.0;
            const bool rayLit = brightness(raycast.image, x, y) > 0.0;
            rayCovered += rayLit;
            disagree += lit != rayLit;
            if (p.along > 2.0 && p.along < length - 2.0 && p.distance < yarn.radiusVoxels - 1.5) {
                ++inside;
                wrongInside += !lit;
            } else if (p.distance > yarn.radiusVoxels + 3.0 || p.along < -yarn.radiusVoxels - 3.0 ||
                       p.along > length + yarn.radiusVoxels + 3.0) {
                ++outside;
                wrongOutside += lit;
            }
        }
    INFO(inside << " pixels inside the band, " << outside << " outside, " << rayCovered << " covered by the ray cast, "
                << disagree << " disagree");
    CHECK(inside > 500);
    CHECK(outside > 2000);
    CHECK(wrongInside == 0);
    CHECK(wrongOutside == 0);
    // The two differ only along the silhouette's edge, where the blur and
    // the voxels' partial densities fade differently: the band is as wide
    // in both, within a pixel a side (1.3 voxels here, about the blur's
    // deviation), in every column away from the caps.
    CHECK(disagree < rayCovered / 5);
    int columns = 0;
    for (int x = 0; x < camera.width; ++x) {
        const AxisPass p = passOf(camera, yarn, x, camera.height / 2);
        if (p.along < 4.0 || p.along > length - 4.0) continue;
        int softHeight = 0, rayHeight = 0;
        for (int y = 0; y < camera.height; ++y) {
            softHeight += brightness(soft.image, x, y) >= 10.0;
            rayHeight += brightness(raycast.image, x, y) > 0.0;
        }
        ++columns;
        INFO("column " << x << ": " << softHeight << " pixels high, the ray cast " << rayHeight);
        CHECK(std::abs(softHeight - rayHeight) <= 2);
    }
    CHECK(columns > 40);
    // Thicker through the middle than near the edge: more fibre on the ray.
    const int cx = camera.width / 2;
    int top = -1, bottom = -1;
    for (int y = 0; y < camera.height; ++y)
        if (brightness(soft.image, cx, y) >= 10.0) {
            if (top < 0) top = y;
            bottom = y;
        }
    REQUIRE(bottom - top > 4);
    CHECK(brightness(soft.image, cx, (top + bottom) / 2) > brightness(soft.image, cx, top) + 10.0);
}

TEST_CASE("volumetric triangles: the command line draws a garment and the volume made from it", "[inspect][gl][cli]") {
    YV_REQUIRE_GL();
    Scratch scratch;
    const fs::path bcc = scratch.path / "cloth.bcc", vdb = scratch.path / "cloth.vdb";
    REQUIRE(test::runYarnvox("gen --crossings 40 -q -o " + bcc.string()).exitCode == 0);
    REQUIRE(test::runYarnvox("voxelize " + bcc.string() + " --backend cpu --resolution 48 -q -o " + vdb.string()).exitCode == 0);
    const fs::path fromGarment = scratch.path / "garment.png", fromVolume = scratch.path / "volume.png",
                   raycast = scratch.path / "raycast.png";
    auto run = test::runYarnvox("inspect " + bcc.string() + " --render volumetric-triangles --resolution 48 --size 80x60 -o " +
                                fromGarment.string());
    INFO(run.output);
    REQUIRE(run.exitCode == 0);
    run = test::runYarnvox("inspect " + vdb.string() + " --render volumetric-triangles --size 80x60 -o " + fromVolume.string());
    INFO(run.output);
    REQUIRE(run.exitCode == 0);
    REQUIRE(test::runYarnvox("inspect " + vdb.string() + " --render raycast --size 80x60 -o " + raycast.string()).exitCode == 0);
    const auto coverage = [](const RgbImage& image, double threshold) {
        std::vector<bool> c;
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x) c.push_back(brightness(image, x, y) > threshold);
        return c;
    };
    const std::vector<bool> garment = coverage(readPng(fromGarment.string()), 10.0),
                            soft = coverage(readPng(fromVolume.string()), 10.0),
                            voxels = coverage(readPng(raycast.string()), 0.0);
    CHECK(std::count(garment.begin(), garment.end(), true) > 200);
    // Drawn from the volume's garment on the volume's grid and box, the
    // preview lines up with the ray cast of the volume.
    int softCount = 0, voxelCount = 0, both = 0;
    for (std::size_t i = 0; i < soft.size(); ++i) softCount += soft[i], voxelCount += voxels[i], both += soft[i] && voxels[i];
    INFO(softCount << " pixels covered by the preview, " << voxelCount << " by the ray cast, " << both << " by both");
    CHECK(voxelCount > 200);
    CHECK(both > 0.8 * std::max(softCount, voxelCount));

    // Without its garment, a volume cannot be previewed so: a clear error, no picture.
    fs::remove(bcc);
    const fs::path none = scratch.path / "none.png";
    run = test::runYarnvox("inspect " + vdb.string() + " --render volumetric-triangles -o " + none.string());
    CHECK(run.exitCode != 0);
    CHECK(run.output.find("give the garment") != std::string::npos);
    CHECK_FALSE(fs::exists(none));
}
