// `yarnvox inspect --render`: pictures of volumes built in code, checked per
// pixel against what the camera and the voxels say they must show.
#include "core/error.h"
#include "cpu/cpu_voxelizer.h"
#include "garment/cross_section.h"
#include "garment/generate.h"
#include "garment/slices.h"
#include "gpu/egl_context.h"
#include "render/brick_atlas.h"
#include "inspect/brick_level.h"
#include "render/render_volume.h"
#include "inspect/proxy_geometry.h"
#include "render/raycast_renderer.h"
#include "inspect/transfer_function.h"
#include "run_cli.h"
#include "store/brick_store.h"
#include "inspect_test_volumes.h"
#include "test_helpers.h"
#include "vdb/vdb_writer.h"

#include <catch2/catch.hpp>

#include <Imath/half.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <set>
#include <unistd.h>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <thread>

using namespace yv;
namespace fs = std::filesystem;

namespace {

struct Scratch : test::ScratchDir {
    Scratch() : test::ScratchDir("yv_test_render") {}
};

using StraightYarn = test::StraightYarnVolume;

StraightYarn straightYarnVolume() { return test::straightYarnVolume(5); }

BrickVolume garmentVolume(int resolution) { return test::knitCylinderVolume(resolution); }

/// The ray through pixel (x, y) (row 0 at the top), as the shaders build it.
void pixelRay(const Camera& c, int x, int y, glm::dvec3& origin, glm::dvec3& dir) {
    const glm::dmat4 inv = glm::inverse(c.viewProjection());
    const glm::dvec2 ndc(2.0 * (x + 0.5) / c.width - 1.0, 2.0 * (c.height - 1 - y + 0.5) / c.height - 1.0);
    const glm::dvec4 a = inv * glm::dvec4(ndc, -1.0, 1.0), b = inv * glm::dvec4(ndc, 1.0, 1.0);
    origin = glm::dvec3(a) / a.w;
    dir = glm::normalize(glm::dvec3(b) / b.w - origin);
}

bool covered(const RgbImage& im, int x, int y) {
    const std::uint8_t* p = im.at(x, y);
    return p[0] || p[1] || p[2];
}

/// GL work for one volume: its atlas at the level the budget allows.
struct GlVolume {
    GlContext context;
    LevelPlan plan;
    std::unique_ptr<BrickAtlas> atlas;
    GlVolume(const VolumeSource& source, const VoxelBox& box, bool orientation, std::uint64_t budget = 1ull << 30) {
        plan = planLevel(source, box, budget, atlasBytesPerVoxel(orientation), context.info().max3dTextureSize);
        atlas = std::make_unique<BrickAtlas>(plan, orientation, context.info().max3dTextureSize);
        streamLevelBricks(source, box, plan, orientation, [&](const LevelBrick& b) { atlas->upload(b); });
        atlas->finish();
    }
};


/// An atlas's textures read back: per plan brick, its 512 density halves and colours, in texture order.
struct AtlasTexels {
    std::map<std::uint64_t, std::vector<std::uint16_t>> density;
    std::map<std::uint64_t, std::vector<std::uint8_t>> colour;
    std::map<std::uint64_t, std::uint32_t> slot; ///< the indirection's entry (slot + 1)
};

AtlasTexels readAtlas(const BrickAtlas& atlas, const LevelPlan& plan, bool orientation) {
    const glm::ivec3 texels = atlas.slotsPerAxis() * kBrickSize;
    const std::size_t count = std::size_t(texels.x) * std::size_t(texels.y) * std::size_t(texels.z);
    std::vector<std::uint16_t> density(count);
    std::vector<std::uint8_t> colour(4 * count);
    std::vector<std::uint32_t> slots(std::size_t(plan.brickDims.x) * plan.brickDims.y * plan.brickDims.z);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(atlas.densityTexture(), 0, GL_RED, GL_HALF_FLOAT, GLsizei(density.size() * 2), density.data());
    if (orientation)
        glGetTextureImage(atlas.orientationTexture(), 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(colour.size()), colour.data());
    glGetTextureImage(atlas.indirectionTexture(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, GLsizei(slots.size() * 4), slots.data());
    REQUIRE(glGetError() == GL_NO_ERROR);
    AtlasTexels out;
    const glm::ivec3 slotsPerAxis = atlas.slotsPerAxis();
    for (const glm::ivec3& c : plan.bricks) {
        const std::uint32_t slot = slots[std::size_t(c.x + plan.brickDims.x * (c.y + plan.brickDims.y * c.z))];
        REQUIRE(slot >= 1);
        out.slot[brickKey(c)] = slot;
        const std::uint32_t s = slot - 1;
        const glm::ivec3 at = glm::ivec3(int(s % std::uint32_t(slotsPerAxis.x)),
                                         int(s / std::uint32_t(slotsPerAxis.x) % std::uint32_t(slotsPerAxis.y)),
                                         int(s / std::uint32_t(slotsPerAxis.x * slotsPerAxis.y))) * kBrickSize;
        std::vector<std::uint16_t>& d = out.density[brickKey(c)];
        std::vector<std::uint8_t>& rgba = out.colour[brickKey(c)];
        for (int v = 0; v < 512; ++v) {
            const glm::ivec3 p = at + glm::ivec3(v % 8, v / 8 % 8, v / 64);
            const std::size_t t = std::size_t(p.x) + std::size_t(texels.x) * (std::size_t(p.y) + std::size_t(texels.y) * std::size_t(p.z));
            d.push_back(density[t]);
            if (orientation)
                for (int k = 0; k < 4; ++k) rgba.push_back(colour[4 * t + std::size_t(k)]);
        }
    }
    return out;
}

} // namespace

TEST_CASE("inspect render: the brick atlas holds every brick where its indirection says, over rows of slots and a last row "
          "partly filled",
          "[inspect][gl]") {
    YV_REQUIRE_GL();
    GlContext context;
    // 8 slots a row (a 64-texel atlas side): 150 bricks fill 18 rows and 6 slots of a 19th.
    LevelPlan plan;
    plan.brickDims = {10, 5, 4};
    std::mt19937 rng(5);
    std::vector<LevelBrick> bricks;
    for (int z = 0; z < 4; ++z)
        for (int y = 0; y < 5; ++y)
            for (int x = 0; x < 10; ++x) {
                if ((x + 2 * y + 3 * z) % 4 == 3) continue;
                plan.bricks.push_back({x, y, z});
                LevelBrick b;
                b.coord = {x, y, z};
                std::uniform_real_distribution<float> u(0.0f, 1.5f);
                for (int v = 0; v < 512; ++v) {
                    b.density[std::size_t(v)] = u(rng);
                    b.axisColour[std::size_t(v)] = glm::vec3(u(rng), u(rng), u(rng)) * 0.7f;
                }
                bricks.push_back(b);
            }
    REQUIRE(bricks.size() == 150);
    for (bool orientation : {false, true}) {
        INFO("orientation " << orientation);
        BrickAtlas atlas(plan, orientation, 64);
        REQUIRE(atlas.slotsPerAxis().x == 8);
        std::shuffle(bricks.begin(), bricks.end(), rng); // in any order
        for (const LevelBrick& b : bricks) atlas.upload(b);
        atlas.finish();
        const AtlasTexels read = readAtlas(atlas, plan, orientation);
        std::set<std::uint32_t> used;
        std::size_t wrongDensity = 0, wrongColour = 0;
        for (const LevelBrick& b : bricks) {
            const std::uint64_t key = brickKey(b.coord);
            REQUIRE(read.slot.at(key) <= 150);
            used.insert(read.slot.at(key));
            for (int v = 0; v < 512; ++v) {
                wrongDensity += read.density.at(key)[std::size_t(v)] != imath_float_to_half(b.density[std::size_t(v)]);
                if (orientation)
                    for (int c = 0; c < 3; ++c)
                        wrongColour += read.colour.at(key)[4 * std::size_t(v) + std::size_t(c)] !=
                                       std::uint8_t(std::lround(255.0f * std::clamp(b.axisColour[std::size_t(v)][c], 0.0f, 1.0f)));
            }
        }
        CHECK(used.size() == 150); // every brick a slot of its own
        CHECK(wrongDensity == 0);
        CHECK(wrongColour == 0);
        float expectedMax = 0.0f;
        for (const LevelBrick& b : bricks) expectedMax = std::max(expectedMax, *std::max_element(b.density.begin(), b.density.end()));
        CHECK(atlas.densityMax() == expectedMax);
    }
}

TEST_CASE("inspect render: level 0 loaded at once, on the source's threads, gives the atlas brick-by-brick loading gives",
          "[inspect][gl]") {
    YV_REQUIRE_GL();
    GlContext context;
    // 150 random bricks, some voxels inactive, in an atlas 8 slots a row (a 64-texel side): 19 rows over 3 layers.
    BrickVolume volume;
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(0.0f, 1.2f);
    for (int z = 0; z < 4; ++z)
        for (int y = 0; y < 5; ++y)
            for (int x = 0; x < 10; ++x) {
                if ((x + 2 * y + 3 * z) % 4 == 3) continue;
                VoxelBrick b;
                b.key = brickKey({x + 3, y, z + 1});
                for (int v = 0; v < 512; ++v) {
                    if (u(rng) < 0.3f) continue;
                    b.density[std::size_t(v)] = u(rng);
                    b.orientation[std::size_t(v)] = glm::normalize(glm::vec3(u(rng) - 0.6f, u(rng) - 0.6f, u(rng) + 0.1f));
                    b.activeMask[std::size_t(v) / 64] |= std::uint64_t(1) << (v % 64);
                }
                volume.bricks.push_back(b);
            }
    std::sort(volume.bricks.begin(), volume.bricks.end(), [](const VoxelBrick& a, const VoxelBrick& b) { return a.key < b.key; });
    const auto source = memorySource(volume);
    const VoxelBox box = source->bounds();
    for (bool orientation : {false, true}) {
        INFO("orientation " << orientation);
        const LevelPlan plan = planLevel(*source, box, 1ull << 30, atlasBytesPerVoxel(orientation), 64);
        REQUIRE(plan.level == 0);
        REQUIRE(plan.bricks.size() == 150);
        BrickAtlas oneByOne(plan, orientation, 64), atOnce(plan, orientation, 64);
        REQUIRE(atOnce.slotsPerAxis() == glm::ivec3(8, 8, 3));
        streamLevelBricks(*source, box, plan, orientation, [&](const LevelBrick& b) { oneByOne.upload(b); });
        oneByOne.finish();
        atOnce.uploadLevelZero(*source, box);
        CHECK(atOnce.bricksUploaded() == 150);
        CHECK(atOnce.densityMax() == oneByOne.densityMax());
        const AtlasTexels a = readAtlas(oneByOne, plan, orientation), b = readAtlas(atOnce, plan, orientation);
        REQUIRE(a.density.size() == 150);
        std::size_t wrongDensity = 0, colourOff = 0;
        for (const auto& [key, texels] : a.density) {
            wrongDensity += texels != b.density.at(key);
            const std::vector<std::uint8_t>& ca = a.colour.at(key);
            const std::vector<std::uint8_t>& cb = b.colour.at(key);
            REQUIRE(ca.size() == cb.size());
            // |axis| against (density |axis|) / density: a level apart at most where the quotient rounds across.
            for (std::size_t i = 0; i < ca.size(); ++i) colourOff += std::abs(int(ca[i]) - int(cb[i])) > 1;
        }
        CHECK(wrongDensity == 0);
        CHECK(colourOff == 0);
        // And the voxels are there: the densities of one brick, as halves.
        const VoxelBrick& first = volume.bricks.front();
        const std::vector<std::uint16_t>& texels = b.density.at(brickKey(brickCoord(first.key) - plan.originVoxel / kBrickSize));
        for (int v = 0; v < 512; ++v)
            CHECK(texels[std::size_t(v % 8 * 64 + v / 8 % 8 * 8 + v / 64)] ==
                  imath_float_to_half(first.isActive(v) ? first.density[std::size_t(v)] : 0.0f));
    }
}

TEST_CASE("inspect render: the ray cast of a straight yarn seen side-on covers the pixels its radius says", "[inspect][gl]") {
    YV_REQUIRE_GL();
    const StraightYarn yarn = straightYarnVolume();
    const auto source = memorySource(yarn.volume);
    const VoxelBox box = source->bounds();
    GlVolume gl(*source, box, false);
    REQUIRE(gl.plan.level == 0);
    RaycastSettings settings;
    settings.transferFunction = loadTransferFunction("fibre");
    const Camera camera = frameBox(box, ViewAngles{90.0, 0.0, 2.5}, 96, 64); // from +y: the yarn runs across
    const test::RayCast r = test::rayCast(*gl.atlas, RenderMode::Raycast, camera, settings);

    // Distance between the pixel's ray and the yarn's axis, where their
    // closest points lie inside the yarn's length (away from the caps).
    const glm::dvec3 axis = glm::normalize(yarn.end - yarn.start);
    const double length = glm::length(yarn.end - yarn.start);
    int inside = 0, outside = 0, wrongInside = 0, wrongOutside = 0;
    for (int y = 0; y < camera.height; ++y)
        for (int x = 0; x < camera.width; ++x) {
            glm::dvec3 o, d;
            pixelRay(camera, x, y, o, d);
            const glm::dvec3 w = o - yarn.start;
            const double b = glm::dot(d, axis), den = 1.0 - b * b;
            const double s = (glm::dot(w, axis) - b * glm::dot(w, d)) / den; // along the axis
            const double t = (b * glm::dot(w, axis) - glm::dot(w, d)) / den; // along the ray
            const double dist = glm::length(w + t * d - s * axis);
            if (s > 2.0 && s < length - 2.0 && dist < yarn.radiusVoxels - 1.5) {
                ++inside;
                wrongInside += !covered(r.image, x, y);
            } else if (dist > yarn.radiusVoxels + 1.5 || s < -yarn.radiusVoxels - 2.0 || s > length + yarn.radiusVoxels + 2.0) {
                ++outside;
                wrongOutside += covered(r.image, x, y);
            }
        }
    INFO(inside << " pixels inside the yarn's silhouette, " << outside << " outside");
    CHECK(inside > 500);
    CHECK(outside > 2000);
    CHECK(wrongInside == 0);
    CHECK(wrongOutside == 0);
}

TEST_CASE("inspect render: empty-space skipping takes fewer samples and draws the same picture", "[inspect][gl]") {
    YV_REQUIRE_GL();
    const BrickVolume volume = garmentVolume(192);
    const auto source = memorySource(volume);
    const VoxelBox box = source->bounds();
    GlVolume gl(*source, box, true);
    // The second view puts the eye inside the volume's box: rays start at the near plane.
    for (const double distance : {3.0, 0.3})
    for (RenderMode mode : {RenderMode::Raycast, RenderMode::Mip, RenderMode::Orientation}) {
        RaycastSettings settings;
        settings.transferFunction = loadTransferFunction("fibre");
        const Camera camera = frameBox(box, ViewAngles{30.0, 20.0, distance}, 96, 72);
        settings.skipEmpty = false;
        const test::RayCast full = test::rayCast(*gl.atlas, mode, camera, settings);
        settings.skipEmpty = true;
        const test::RayCast skipped = test::rayCast(*gl.atlas, mode, camera, settings);

        int worst = 0, coveredPixels = 0, fewer = 0, more = 0, muchMore = 0;
        for (int y = 0; y < camera.height; ++y)
            for (int x = 0; x < camera.width; ++x) {
                for (int k = 0; k < 3; ++k)
                    worst = std::max(worst, std::abs(int(full.image.at(x, y)[k]) - int(skipped.image.at(x, y)[k])));
                coveredPixels += covered(full.image, x, y);
                const std::size_t i = std::size_t(y) * std::size_t(camera.width) + std::size_t(x);
                fewer += skipped.samples[i] < full.samples[i];
                more += skipped.samples[i] > full.samples[i];
                muchMore += skipped.samples[i] > full.samples[i] + 1.0f;
            }
        const double factor = full.meanSamples / skipped.meanSamples;
        std::printf("empty-space skipping, mode %d, distance %.1f: %.2f -> %.2f samples per pixel (%.2fx fewer), %llu proxy triangles\n",
                    int(mode), distance, full.meanSamples, skipped.meanSamples, factor,
                    static_cast<unsigned long long>(skipped.proxyTriangles));
        INFO("mode " << int(mode) << ": largest channel difference " << worst << ", samples " << full.meanSamples
                     << " without skipping, " << skipped.meanSamples << " with");
        CHECK(coveredPixels > camera.width * camera.height / 10);
        CHECK(worst <= 3);
        // Skipping never adds a sample, but where the proxy's entry equals the
        // box's to rounding, one sample may lie either side of it.
        CHECK(more <= camera.width * camera.height / 100);
        CHECK(muchMore == 0);
        CHECK(fewer > 0);
        CHECK(factor > (distance > 1.0 ? 1.5 : 1.1));
    }
}

TEST_CASE("inspect render: MIP seen from above is each voxel column's largest density, from memory and from a .vdb", "[inspect][gl]") {
    YV_REQUIRE_GL();
    // 4x4x3 bricks; a brick is left out where (bx + by) % 3 == 0, and density
    // is a hash of the voxel, so each column's maximum is known and varies.
    BrickVolume volume;
    volume.grid.dims = {32, 32, 24};
    const auto value = [](glm::ivec3 v) { return float((v.x * 7 + v.y * 13 + v.z * 29) % 97) / 96.0f; };
    for (int bx = 0; bx < 4; ++bx)
        for (int by = 0; by < 4; ++by)
            for (int bz = 0; bz < 3; ++bz) {
                if ((bx + by) % 3 == 0 || (bz == 1 && bx == 2)) continue;
                VoxelBrick b;
                b.key = brickKey({bx, by, bz});
                for (int x = 0; x < 8; ++x)
                    for (int y = 0; y < 8; ++y)
                        for (int z = 0; z < 8; ++z) {
                            const int v = brickOffset(x, y, z);
                            b.density[std::size_t(v)] = value(glm::ivec3(bx, by, bz) * 8 + glm::ivec3(x, y, z));
                            b.orientation[std::size_t(v)] = {0, 0, 1};
                            if (b.density[std::size_t(v)] > 0.0f) b.activeMask[std::size_t(v >> 6)] |= 1ull << (v & 63);
                        }
                volume.bricks.push_back(b);
            }
    std::sort(volume.bricks.begin(), volume.bricks.end(), [](const VoxelBrick& a, const VoxelBrick& b) { return a.key < b.key; });
    test::VolumeIndex index(volume);
    Scratch scratch;
    const std::string vdb = (scratch.path / "known.vdb").string();
    writeVdb(vdb, volume, VolumeMetadata{});

    const Camera camera = topDownOrthographic(0, 32, 0, 32, 0, 24, 32, 32); // one pixel a voxel column
    std::vector<RgbImage> images;
    for (const auto& source : {memorySource(volume), openVdbSource(vdb)}) {
        const VoxelBox box = source->bounds();
        CHECK(box.min == glm::ivec3(0));
        CHECK(box.max == glm::ivec3(32, 32, 24));
        GlVolume gl(*source, box, false);
        const test::RayCast r = test::rayCast(*gl.atlas, RenderMode::Mip, camera);
        int wrong = 0;
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) {
                float highest = 0.0f;
                for (int z = 0; z < 24; ++z) highest = std::max(highest, index.density({x, 31 - y, z}));
                const int expected = int(std::lround(255.0f * highest));
                const int got = r.image.at(x, y)[0];
                if (std::abs(got - expected) > 1) {
                    if (++wrong < 5) WARN("pixel " << x << "," << y << ": " << got << ", expected " << expected);
                }
            }
        CHECK(wrong == 0);
        images.push_back(r.image);
    }
    CHECK(images[0].pixels == images[1].pixels);
}

TEST_CASE("inspect render: a cut at a known index is the voxels' densities", "[inspect]") {
    const BrickVolume volume = garmentVolume(64);
    test::VolumeIndex index(volume);
    const auto source = memorySource(volume);
    const VoxelBox box = source->bounds();
    for (int axis = 0; axis < 3; ++axis) {
        const CutPlane cut{axis, (box.min[axis] + box.max[axis]) / 2 + 1};
        const RgbImage image = renderCut(*source, box, cut);
        const int u = axis == 0 ? 1 : 0, v = axis == 2 ? 1 : 2;
        REQUIRE(image.width == box.max[u] - box.min[u]);
        REQUIRE(image.height == box.max[v] - box.min[v]);
        int wrong = 0, nonzero = 0;
        for (int py = 0; py < image.height; ++py)
            for (int px = 0; px < image.width; ++px) {
                glm::ivec3 voxel;
                voxel[axis] = cut.index, voxel[u] = box.min[u] + px, voxel[v] = box.max[v] - 1 - py;
                const int expected = int(std::lround(255.0f * std::clamp(index.density(voxel), 0.0f, 1.0f)));
                const std::uint8_t* p = image.at(px, py);
                wrong += p[0] != expected || p[1] != expected || p[2] != expected;
                nonzero += expected > 0;
            }
        CHECK(nonzero > 50);
        CHECK(wrong == 0);
    }
    CHECK_THROWS_AS(renderCut(*source, box, CutPlane{2, box.max.z}), Error);
    CHECK(parseCut("y:12").axis == 1);
    CHECK(parseCut("y:12").index == 12);
    CHECK_THROWS_AS(parseCut("w:3"), Error);
    CHECK_THROWS_AS(parseCut("x:3.5"), Error);
}

TEST_CASE("inspect render: a coarse level's voxel is the mean of the 2x2x2 voxels under it", "[inspect]") {
    const BrickVolume volume = garmentVolume(64);
    test::VolumeIndex index(volume);
    const auto source = memorySource(volume);
    const VoxelBox box = source->bounds();
    const LevelPlan full = planLevel(*source, box, 1ull << 30, 2, 2048);
    CHECK(full.level == 0);
    CHECK(full.bricks.size() == volume.bricks.size());
    // A budget of half the full level's atlas forces level 1.
    const LevelPlan coarse = planLevel(*source, box, full.gpuBytes / 2, 2, 2048);
    REQUIRE(coarse.level >= 1);
    CHECK(coarse.gpuBytes <= full.gpuBytes / 2);
    std::size_t seen = 0;
    int wrong = 0;
    streamLevelBricks(*source, box, coarse, true, [&](const LevelBrick& b) {
        ++seen;
        for (int z = 0; z < 8; ++z)
            for (int y = 0; y < 8; ++y)
                for (int x = 0; x < 8; ++x) {
                    const glm::ivec3 q = (b.coord * 8 + glm::ivec3(x, y, z)) * coarse.scale + coarse.originVoxel;
                    double sum = 0.0;
                    for (int i = 0; i < coarse.scale; ++i)
                        for (int j = 0; j < coarse.scale; ++j)
                            for (int k = 0; k < coarse.scale; ++k) sum += index.density(q + glm::ivec3(i, j, k));
                    const double mean = sum / double(coarse.scale * coarse.scale * coarse.scale);
                    wrong += std::abs(mean - double(b.density[std::size_t(x + 8 * y + 64 * z)])) > 1e-5;
                }
    });
    CHECK(seen == coarse.bricks.size());
    CHECK(wrong == 0);
    CHECK_THROWS_AS(planLevel(*source, box, 1000, 2, 2048), Error); // not even one brick
}

TEST_CASE("inspect render: proxy geometry is the boundary of the occupied bricks", "[inspect]") {
    LevelPlan plan;
    plan.scale = 2;
    plan.originVoxel = {16, 0, 0};
    plan.brickDims = {3, 1, 1};
    plan.bricks = {{0, 0, 0}, {1, 0, 0}}; // two bricks side by side: 10 faces
    const std::vector<glm::vec3> t = proxyTriangles(plan);
    REQUIRE(t.size() == 10 * 6);
    for (const glm::vec3& p : t) {
        CHECK(p.x >= 16.0f);
        CHECK(p.x <= 16.0f + 32.0f);
        CHECK((p.y == 0.0f || p.y == 16.0f));
    }
    // No face lies on the shared plane x = 16 + 16.
    int onShared = 0;
    for (std::size_t i = 0; i < t.size(); i += 3) onShared += t[i].x == 32.0f && t[i + 1].x == 32.0f && t[i + 2].x == 32.0f;
    CHECK(onShared == 0);
}

TEST_CASE("inspect render: colour map files", "[inspect]") {
    const TransferFunction tf = parseColourMap("# density r g b opacity\n0 0 0 0 0\n1 1 0.5 0 1\n", "map.txt");
    CHECK(tf[0].r == Approx(0.0f));
    CHECK(tf[255].g == Approx(0.5f));
    CHECK(tf[51].a == Approx(0.2f).margin(1e-6));
    CHECK_THROWS_WITH(parseColourMap("0 0 0 0 0\n0.5 1 1\n", "map.txt"), Catch::Contains("map.txt line 2"));
    CHECK_THROWS_WITH(parseColourMap("0.5 0 0 0 0\n0.2 1 1 1 1\n", "map.txt"), Catch::Contains("rise"));
    CHECK_THROWS_WITH(parseColourMap("0 0 0 0 0\n", "map.txt"), Catch::Contains("two lines"));
    CHECK_THROWS_WITH(parseColourMap("0 0 0 0 0\n1 2 0 0 0\n", "map.txt"), Catch::Contains("[0, 1]"));
}

TEST_CASE("inspect render: scaling a transfer function's opacity is what a voxel that many times as long would block", "[inspect]") {
    const TransferFunction tf = parseColourMap("0 0.2 0.4 0.6 0\n0.5 1 1 1 0.5\n1 1 0.5 0 1\n", "map.txt");
    const TransferFunction same = withOpacityScale(tf, 1.0);
    CHECK(std::memcmp(same.data(), tf.data(), sizeof tf) == 0);
    const TransferFunction twice = withOpacityScale(tf, 2.0), half = withOpacityScale(tf, 0.5);
    for (std::size_t i = 0; i < tf.size(); ++i) {
        INFO("entry " << i << " opacity " << tf[i].a);
        // Two voxels' worth: light through both, (1 - a)^2, is what passes.
        CHECK(1.0 - twice[i].a == Approx((1.0 - tf[i].a) * (1.0 - tf[i].a)).margin(1e-6));
        CHECK(withOpacityScale(half, 2.0)[i].a == Approx(tf[i].a).margin(1e-6));
        CHECK(twice[i].r == tf[i].r); // colours unchanged
        CHECK(half[i].b == tf[i].b);
    }
    CHECK(twice[0].a == 0.0f);   // nothing stays nothing
    CHECK(half[255].a == 1.0f);  // opaque stays opaque
    CHECK(twice[128].a > tf[128].a);
    CHECK(half[128].a < tf[128].a);
}

TEST_CASE("inspect render: --region frames one zoom region and draws only its bricks", "[inspect][gl]") {
    YV_REQUIRE_GL();
    RenderContext context;
    const BrickVolume volume = garmentVolume(64);
    const auto whole = memorySource(volume);
    const VoxelBox all = whole->bounds();
    // Two regions: the halves of the volume along x, on a brick boundary.
    const int mid = (all.min.x + all.max.x) / 16 * 8;
    std::vector<VoxelBox> regions = {{all.min, {mid, all.max.y, all.max.z}}, {{mid, all.min.y, all.min.z}, all.max}};
    const auto source = memorySource(volume, regions);
    for (std::uint64_t id = 0; id < 2; ++id) {
        RenderRequest request;
        request.region = id;
        request.width = 80, request.height = 60;
        request.view = ViewAngles{-60.0, 25.0, 4.0};
        const RenderReport rep = renderVolume(context, *source, request);
        // The region's box, projected: every drawn pixel lies inside it.
        const Camera camera = frameBox(regions[id], request.view, request.width, request.height);
        glm::dvec2 lo(1e9), hi(-1e9);
        for (int c = 0; c < 8; ++c) {
            const glm::dvec3 p((c & 1 ? regions[id].max : regions[id].min).x, (c & 2 ? regions[id].max : regions[id].min).y,
                               (c & 4 ? regions[id].max : regions[id].min).z);
            const glm::dvec4 clip = camera.viewProjection() * glm::dvec4(p, 1.0);
            const glm::dvec2 px((clip.x / clip.w + 1.0) * 0.5 * camera.width, (1.0 - clip.y / clip.w) * 0.5 * camera.height);
            lo = glm::min(lo, px), hi = glm::max(hi, px);
        }
        int drawn = 0, outside = 0;
        for (int y = 0; y < request.height; ++y)
            for (int x = 0; x < request.width; ++x) {
                if (!covered(rep.image, x, y)) continue;
                ++drawn;
                outside += x + 0.5 < lo.x - 0.5 || x + 0.5 > hi.x + 0.5 || y + 0.5 < lo.y - 0.5 || y + 0.5 > hi.y + 0.5;
            }
        INFO("region " << id << ": projected box " << lo.x << "," << lo.y << " to " << hi.x << "," << hi.y);
        CHECK(drawn > request.width * request.height / 20);
        CHECK(outside == 0);
        // The framed box fills a good part of the picture (it is framed, not the whole volume's view).
        CHECK((hi.x - lo.x) * (hi.y - lo.y) > 0.25 * request.width * request.height);
        CHECK(rep.fineBricks < volume.bricks.size());
    }
    RenderRequest bad;
    bad.region = 7;
    CHECK_THROWS_AS(renderVolume(context, *source, bad), Error);
}

TEST_CASE("inspect render: a budget too small for full resolution renders a coarser level, the same silhouette", "[inspect][gl]") {
    YV_REQUIRE_GL();
    RenderContext context;
    const BrickVolume volume = garmentVolume(96);
    const auto source = memorySource(volume);
    RenderRequest request;
    request.width = 64, request.height = 48;
    request.view = ViewAngles{20.0, 10.0, 3.0};
    request.kind = RenderKind::Mip;
    const RenderReport full = renderVolume(context, *source, request);
    REQUIRE(full.level == 0);
    request.gpuBudgetBytes = full.gpuBytes / 3;
    const RenderReport coarse = renderVolume(context, *source, request);
    CHECK(coarse.level >= 1);
    CHECK(coarse.gpuBytes <= request.gpuBudgetBytes);
    CHECK(coarse.levelBricks < full.levelBricks);
    int both = 0, either = 0;
    for (int y = 0; y < request.height; ++y)
        for (int x = 0; x < request.width; ++x) {
            both += covered(full.image, x, y) && covered(coarse.image, x, y);
            either += covered(full.image, x, y) || covered(coarse.image, x, y);
        }
    INFO("coverage: " << both << " of " << either << " pixels agree");
    CHECK(either > 200);
    CHECK(double(both) / double(either) > 0.8);
}

TEST_CASE("inspect render: the command line writes PNGs from a work directory and refuses bad requests", "[inspect][gl][cli]") {
    YV_REQUIRE_GL();
    Scratch scratch;
    const std::string dir = (scratch.path / "work").string();
    const BrickVolume volume = garmentVolume(64);
    {
        StoreManifest manifest;
        manifest.fingerprint = 7;
        manifest.grid = volume.grid;
        BrickStore store(dir, manifest, false);
        std::vector<VoxelBrick> low, high;
        for (const VoxelBrick& b : volume.bricks) (brickCoord(b.key).x < 4 ? low : high).push_back(b);
        const glm::ivec3 size = (volume.grid.dims + 7) / 8 * 8;
        store.writeRegion(0, {0, 0, 0}, {32, size.y, size.z}, low);
        store.writeRegion(1, {32, 0, 0}, {std::max(size.x, 40), size.y, size.z}, high);
        store.markComplete(2);
    }
    test::VolumeIndex index(volume);
    const std::string png = (scratch.path / "cut.png").string();
    const auto cut = test::runYarnvox("inspect " + dir + " --render cut --cut z:30 -o " + png);
    INFO(cut.output);
    REQUIRE(cut.exitCode == 0);
    const RgbImage image = readPng(png);
    const VoxelBox box = memorySource(volume)->bounds();
    REQUIRE(image.width == box.max.x - box.min.x);
    int wrong = 0;
    for (int py = 0; py < image.height; ++py)
        for (int px = 0; px < image.width; ++px) {
            const float d = index.density({box.min.x + px, box.max.y - 1 - py, 30});
            wrong += image.at(px, py)[0] != int(std::lround(255.0f * std::clamp(d, 0.0f, 1.0f)));
        }
    CHECK(wrong == 0);

    const std::string ray = (scratch.path / "ray.png").string();
    const auto r = test::runYarnvox("inspect " + dir + " --render raycast --size 48x32 --view 10,30,3 -o " + ray);
    INFO(r.output);
    CHECK(r.exitCode == 0);
    CHECK(r.output.find("mean samples per pixel") != std::string::npos);
    CHECK(readPng(ray).width == 48);

    // JSON for scripts: fewer samples with skipping than without, one region framed.
    const auto meanSamples = [](const std::string& out) {
        const std::size_t at = out.find("\"mean_samples_per_pixel\":");
        return at == std::string::npos ? -1.0 : std::atof(out.c_str() + at + 25);
    };
    const auto skip = test::runYarnvox("inspect " + dir + " --render mip --size 40x30 --json --show-samples -o " + ray);
    const auto noSkip = test::runYarnvox("inspect " + dir + " --render mip --size 40x30 --json --no-skip -o " + ray);
    INFO(skip.output << noSkip.output);
    REQUIRE(skip.exitCode == 0);
    REQUIRE(noSkip.exitCode == 0);
    CHECK(meanSamples(skip.output) > 0.0);
    CHECK(meanSamples(noSkip.output) > meanSamples(skip.output));
    const auto region = test::runYarnvox("inspect " + dir + " --render raycast --region 1 --size 40x30 --json -o " + ray);
    INFO(region.output);
    CHECK(region.exitCode == 0);
    CHECK(region.output.find("\"fine_bricks\": " + std::to_string(std::count_if(volume.bricks.begin(), volume.bricks.end(),
        [](const VoxelBrick& b) { return brickCoord(b.key).x >= 4; }))) != std::string::npos);

    // Bad requests: one line, exit 1, no file.
    const std::string none = (scratch.path / "none.png").string();
    for (const char* args : {" --render cut -o ", " --render mip --size 0x5 -o ", " --render mip --tf nosuch -o ",
                                    " --render raycast --region 9 -o ", " --render mip --view 1,2 -o ",
                                    " --render cut --cut z:100000 -o "}) {
        const auto bad = test::runYarnvox("inspect " + dir + std::string(args) + none);
        INFO(args << ": " << bad.output);
        CHECK(bad.exitCode != 0);
        CHECK(!fs::exists(none));
        CHECK(std::count(bad.output.begin(), bad.output.end(), '\n') <= 2);
    }
}

TEST_CASE("inspect render: an 8192-voxel domain renders within the default budget at a coarse level", "[inspect][gl]") {
    YV_REQUIRE_GL();
    // Solid bricks along the main diagonal of an 8192^3 grid: the
    // indirection grid alone would take 4 GiB at full resolution, 512 MiB at
    // level 1; level 2 (64 MiB) fits the default 512 MiB.
    BrickVolume volume;
    for (int i = 0; i < 1024; ++i) {
        VoxelBrick b;
        b.key = brickKey({i, i, i});
        b.density.fill(1.0f);
        b.orientation.fill({1, 0, 0});
        b.activeMask.fill(~0ull);
        volume.bricks.push_back(b);
    }
    const auto source = memorySource(volume);
    const VoxelBox box = source->bounds();
    REQUIRE(box.max == glm::ivec3(8192));
    GlVolume gl(*source, box, false, RenderRequest{}.gpuBudgetBytes);
    CHECK(gl.plan.level == 2);
    CHECK(gl.plan.gpuBytes <= RenderRequest{}.gpuBudgetBytes);
    // From above, 32 voxels a pixel, shifted by 4 so that ray centres fall
    // inside bricks, never on their faces: the ray through pixel column k
    // (x = 32k + 20) meets brick 4k + 2, which lies under the same row from
    // the bottom only: a MIP of 1 on the diagonal, 0 elsewhere.
    const test::RayCast r = test::rayCast(*gl.atlas, RenderMode::Mip, topDownOrthographic(4, 8196, 4, 8196, 0, 8192, 256, 256));
    int wrong = 0;
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) wrong += r.image.at(x, y)[0] != (x == 255 - y ? 255 : 0);
    CHECK(wrong == 0);
}

TEST_CASE("inspect render: work directories and .vdb files hand over the bricks and voxels that were written", "[inspect]") {
    Scratch scratch;
    const BrickVolume volume = garmentVolume(64);
    const std::string dir = (scratch.path / "work").string(), vdb = (scratch.path / "v.vdb").string();
    {
        StoreManifest manifest;
        manifest.fingerprint = 9;
        manifest.grid = volume.grid;
        BrickStore store(dir, manifest, false);
        std::vector<VoxelBrick> low, high;
        for (const VoxelBrick& b : volume.bricks) (brickCoord(b.key).z < 4 ? low : high).push_back(b);
        const glm::ivec3 size = (volume.grid.dims + 7) / 8 * 8;
        store.writeRegion(0, {0, 0, 0}, {size.x, size.y, 32}, low);
        store.writeRegion(1, {0, 0, 32}, {size.x, size.y, std::max(size.z, 40)}, high);
        store.markComplete(2);
    }
    writeVdb(vdb, volume, VolumeMetadata{});
    test::VolumeIndex index(volume);
    std::vector<glm::ivec3> expected;
    for (const VoxelBrick& b : volume.bricks) expected.push_back(brickCoord(b.key));
    for (const auto& source : {openVolumeSource(dir), openVolumeSource(vdb)}) {
        std::vector<glm::ivec3> listed = source->occupiedBricks();
        const auto order = [](glm::ivec3 a, glm::ivec3 b) { return brickKey(a) < brickKey(b); };
        std::sort(listed.begin(), listed.end(), order);
        CHECK(listed == expected);
        CHECK(source->hasOrientation());
        // Every voxel of the bricks in the lower half along x, and none beyond.
        const glm::ivec3 lo(0), hi(4, 1 << 20, 1 << 20);
        std::size_t visited = 0;
        int wrongDensity = 0, wrongAxis = 0, outside = 0;
        // One visit at a time and on this thread (a visitor may draw: GL
        // calls belong to the thread whose context is current).
        const std::thread::id caller = std::this_thread::get_id();
        int otherThread = 0;
        source->forEachBrick(lo, hi, [&](const SourceBrick& b) {
            ++visited;
            otherThread += std::this_thread::get_id() != caller;
            outside += b.coord.x >= 4;
            const VoxelBrick* mine = index.brick(b.coord * 8);
            REQUIRE(mine);
            for (int v = 0; v < kBrickVoxels; ++v) {
                const float d = mine->isActive(v) ? mine->density[std::size_t(v)] : 0.0f;
                wrongDensity += std::abs(b.density[v] - d) > 1e-6f;
                if (mine->isActive(v)) wrongAxis += glm::length(b.orientation[v] - mine->orientation[std::size_t(v)]) > 1e-6f;
            }
        });
        CHECK(visited == std::size_t(std::count_if(expected.begin(), expected.end(), [](glm::ivec3 c) { return c.x < 4; })));
        CHECK(outside == 0);
        CHECK(otherThread == 0);
        CHECK(wrongDensity == 0);
        CHECK(wrongAxis == 0);
    }
    CHECK(openVolumeSource(dir)->regionBounds(1).min == glm::ivec3(0, 0, 32));
    CHECK_THROWS_AS(openVolumeSource(vdb)->regionBounds(0), Error);
}
