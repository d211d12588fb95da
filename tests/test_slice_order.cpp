// `--render slices` ordered on the GPU: the radix sort against
// std::stable_sort, the slices' back-to-front order against the host's
// sortBackToFront slice for slice, and the picture against the host-sorted one.
#include "gpu/egl_context.h"
#include "gpu/gl_buffer.h"
#include "gpu/radix_sort.h"
#include "inspect/camera.h"
#include "inspect/slice_instances.h"
#include "render/render_context.h"
#include "render/renderer.h"
#include "render/slice_renderer.h"
#include "render/volumetric_triangles.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <random>

using namespace yv;

namespace {

/// A knit cylinder's slices on a grid of `resolution`, with `copies` of
/// them appended again (the same centres at other indices: ties in distance
/// whatever the eye), and the box they lie in.
struct TestSlices {
    SliceInstances slices;
    VoxelBox box;
};
TestSlices knitSlices(int crossings, int resolution, std::size_t copies) {
    const test::GeneratedRun run = test::generatedRun(WeavePattern::Knit, GarmentShape::Cylinder, crossings, 0.0, resolution);
    TestSlices t{sliceInstances(run.plan, run.grid), sliceBox(run.plan, run.grid)};
    std::mt19937 rng(11);
    const std::size_t n = t.slices.count();
    for (std::size_t c = 0; c < copies; ++c) {
        const std::size_t i = rng() % n;
        t.slices.records.push_back(t.slices.records[2 * i]);
        t.slices.records.push_back(t.slices.records[2 * i + 1]);
    }
    return t;
}

/// Pairs whose keys tie with the next pair's in `order` (by squared distance from `eye`).
int tiesIn(const SliceInstances& slices, const std::vector<std::uint32_t>& order, glm::vec3 eye) {
    int ties = 0;
    for (std::size_t i = 1; i < order.size(); ++i) {
        const glm::vec3 a = slices.center(order[i - 1]) - eye, b = slices.center(order[i]) - eye;
        ties += glm::dot(a, a) == glm::dot(b, b);
    }
    return ties;
}

std::uint64_t differingBytes(const RgbImage& a, const RgbImage& b) {
    std::uint64_t n = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) n += a.pixels[i] != b.pixels[i];
    return n;
}

std::uint64_t coveredPixels(const RgbImage& im) {
    std::uint64_t n = 0;
    for (std::size_t i = 0; i < im.pixels.size(); i += 3) n += (im.pixels[i] | im.pixels[i + 1] | im.pixels[i + 2]) != 0;
    return n;
}

} // namespace

TEST_CASE("radix sort on the GPU: stable by key, the dropped pairs left out, as std::stable_sort", "[gpu][gl]") {
    YV_REQUIRE_GL();
    RenderContext context;
    context.gl();
    GLint groups = 0;
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &groups);
    // Several tiles and scan blocks; keys from a narrow range (many equal)
    // and from the whole range (every byte a digit); one in 7 dropped.
    const std::uint32_t n = 20000;
    for (const std::uint32_t range : {97u, 0xffffffffu}) {
        std::mt19937 rng(range);
        std::vector<std::uint32_t> keys(n), values(n);
        for (std::uint32_t i = 0; i < n; ++i) {
            keys[i] = range == 0xffffffffu ? std::uint32_t(rng()) : std::uint32_t(rng() % range) * 0x01010101u;
            values[i] = rng() % 7 == 0 ? RadixSort::kDropped : i;
        }
        RadixSort sort(n, GLuint(std::max(groups, 1)));
        glNamedBufferSubData(sort.keys().id(), 0, n * 4, keys.data());
        glNamedBufferSubData(sort.values().id(), 0, n * 4, values.data());
        GlBuffer out;
        out.reserve(n * 4, nullptr);
        sort.sort(n, out);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        ReadbackBuffer readback;
        GLuint kept = 0;
        std::memcpy(&kept, readback.read(sort.kept().id(), 4, nullptr), 4);
        std::vector<std::uint32_t> got(kept);
        if (kept) std::memcpy(got.data(), readback.read(out.id(), std::uint64_t(kept) * 4, nullptr), std::size_t(kept) * 4);

        std::vector<std::uint32_t> expected;
        for (std::uint32_t i = 0; i < n; ++i)
            if (values[i] != RadixSort::kDropped) expected.push_back(i);
        std::stable_sort(expected.begin(), expected.end(), [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
        INFO("keys below " << range);
        REQUIRE(kept == expected.size());
        std::size_t wrong = 0, firstWrong = kept;
        for (std::size_t i = 0; i < kept; ++i)
            if (got[i] != expected[i]) wrong++, firstWrong = std::min(firstWrong, i);
        INFO("first wrong at " << firstWrong);
        CHECK(wrong == 0);
    }
}

TEST_CASE("slices on the GPU: the back-to-front order is sortBackToFront's, ties included, and so is the picture", "[inspect][gl]") {
    YV_REQUIRE_GL();
    RenderContext context;
    context.gl();
    const TestSlices t = knitSlices(120, 48, 2000);
    const std::uint64_t n = t.slices.count();
    INFO(n << " slices");
    REQUIRE(n > 5000);
    const Camera camera = frameBox(t.box, ViewAngles{35.0, 25.0, 3.0}, 96, 72);

    SliceRenderer gpu(t.slices);
    gpu.prepare(camera);
    std::vector<std::uint32_t> expected;
    sortBackToFront(t.slices, camera.eye, expected);
    const std::vector<std::uint32_t> got = gpu.drawOrder();
    REQUIRE(got.size() == n);
    std::size_t wrong = 0, firstWrong = n;
    for (std::size_t i = 0; i < n; ++i)
        if (got[i] != expected[i]) wrong++, firstWrong = std::min(firstWrong, i);
    INFO("first difference at " << firstWrong);
    CHECK(wrong == 0);
    CHECK(tiesIn(t.slices, expected, glm::vec3(camera.eye)) >= 1000);

    // The same picture as the order sorted on the host and uploaded.
    SliceSettings host;
    host.sortOnHost = true;
    SliceRenderer reference(t.slices, host);
    RenderReport fromGpu, fromHost;
    drawFrames(gpu, camera, 1, fromGpu);
    drawFrames(reference, camera, 1, fromHost);
    CHECK(fromGpu.slices == n);
    CHECK(fromHost.slices == n);
    CHECK(coveredPixels(fromHost.image) > 96 * 72 / 10);
    CHECK(differingBytes(fromGpu.image, fromHost.image) == 0);
}

TEST_CASE("slices on the GPU: a close-up draws only the slices in view, and the same picture as drawing all", "[inspect][gl]") {
    YV_REQUIRE_GL();
    RenderContext context;
    context.gl();
    const TestSlices t = knitSlices(120, 48, 0);
    const std::uint64_t n = t.slices.count();
    // Close enough that the near plane and the picture's sides cut the cylinder.
    const Camera camera = frameBox(t.box, ViewAngles{35.0, 25.0, 1.2}, 96, 72);
    SliceSettings every;
    every.cull = false;
    SliceRenderer culled(t.slices), all(t.slices, every);
    RenderReport fromCulled, fromAll;
    drawFrames(culled, camera, 1, fromCulled);
    drawFrames(all, camera, 1, fromAll);
    INFO(fromCulled.slices << " of " << n << " slices drawn");
    CHECK(fromAll.slices == n);
    CHECK(fromCulled.slices < n * 3 / 4);
    CHECK(fromCulled.slices > n / 10);
    CHECK(coveredPixels(fromAll.image) > 96 * 72 / 4);
    CHECK(differingBytes(fromCulled.image, fromAll.image) == 0);

    // The order kept is the host's with the culled slices left out; every
    // slice well inside the picture is kept, every one well outside dropped.
    const std::vector<std::uint32_t> kept = culled.drawOrder();
    REQUIRE(kept.size() == fromCulled.slices);
    std::vector<std::uint32_t> expected;
    sortBackToFront(t.slices, camera.eye, expected);
    std::vector<char> isKept(n, 0);
    for (std::uint32_t i : kept) isKept[i] = 1;
    std::vector<std::uint32_t> expectedKept;
    for (std::uint32_t i : expected)
        if (isKept[i]) expectedKept.push_back(i);
    CHECK(expectedKept == kept);
    const glm::dmat4 vp = camera.viewProjection();
    int wellInside = 0, wellOutside = 0, insideDropped = 0, outsideKept = 0;
    for (std::uint64_t i = 0; i < n; ++i) {
        const glm::dvec4 clip = vp * glm::dvec4(glm::dvec3(t.slices.center(i)), 1.0);
        const double reach = std::sqrt(2.0) * t.slices.records[2 * i + 1].w + t.slices.records[2 * i].w;
        if (clip.w <= reach) continue; // near the eye's plane: neither
        const double rx = reach * camera.projection[0][0] / clip.w, ry = reach * camera.projection[1][1] / clip.w;
        const double x = std::abs(clip.x / clip.w), y = std::abs(clip.y / clip.w), z = clip.z / clip.w;
        if (x + rx < 0.95 && y + ry < 0.95 && z > -0.9 && z < 0.9) {
            ++wellInside;
            insideDropped += !isKept[i];
        } else if (x - rx > 1.05 || y - ry > 1.05) {
            ++wellOutside;
            outsideKept += isKept[i];
        }
    }
    INFO(wellInside << " slices well inside the picture, " << wellOutside << " well outside");
    CHECK(wellInside > int(n / 10));
    CHECK(wellOutside > int(n / 10));
    CHECK(insideDropped == 0);
    CHECK(outsideKept == 0);
}
