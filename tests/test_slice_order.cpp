// `--render slices` ordered on the GPU: the radix sort against
// std::stable_sort, the slices' back-to-front order against the host's
// sortBackToFront slice for slice, and the picture against the host-sorted one.
#include "gpu/egl_context.h"
#include "gpu/gl_buffer.h"
#include "gpu/gpu_scan.h"
#include "gpu/radix_sort.h"
#include "inspect/camera.h"
#include "inspect/slice_instances.h"
#include "render/render_context.h"
#include "render/renderer.h"
#include "render/slice_renderer.h"
#include "render/volumetric_triangles.h"
#include "inspect_test_volumes.h"
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

/// Channel values of `a` more than `levels` from `b`'s.
std::uint64_t bytesOffBy(const RgbImage& a, const RgbImage& b, int levels) {
    std::uint64_t n = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) n += std::abs(int(a.pixels[i]) - int(b.pixels[i])) > levels;
    return n;
}


/// The work groups a dispatch may have (the context must be current).
GLuint maxComputeGroups() {
    GLint groups = 0;
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &groups);
    return GLuint(std::max(groups, 1));
}

/// Every slice drawn (no level of detail), each slab as `primitive` says.
SliceSettings everySlice(SlicePrimitive primitive) {
    SliceSettings settings;
    settings.lodPixels = 0.0;
    settings.primitive = primitive;
    return settings;
}

} // namespace

TEST_CASE("radix sort on the GPU: stable by key, the dropped pairs left out, as std::stable_sort", "[gpu][gl]") {
    YV_REQUIRE_GL();
    RenderContext context;
    context.gl();
    const GLuint maxGroups = maxComputeGroups();
    // Several tiles and scan blocks; keys from a narrow range (many equal),
    // from the whole range (every byte a digit), and with all bytes but the
    // second the same for all (tiles of one digit); one in 7 dropped.
    const std::uint32_t n = 20000;
    for (const std::uint32_t range : {97u, 0xffffffffu, 0x100u}) {
        std::mt19937 rng(range);
        std::vector<std::uint32_t> keys(n), values(n);
        for (std::uint32_t i = 0; i < n; ++i) {
            keys[i] = range == 0xffffffffu ? std::uint32_t(rng())
                      : range == 0x100u    ? 0xbe7f003cu | std::uint32_t(rng() % range) << 8
                                           : std::uint32_t(rng() % range) * 0x01010101u;
            values[i] = rng() % 7 == 0 ? RadixSort::kDropped : i;
        }
        RadixSort sort(n, maxGroups);
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

TEST_CASE("the GPU's exclusive scan, and a radix sort that grows and keeps its sorted keys", "[gpu][gl]") {
    YV_REQUIRE_GL();
    RenderContext context;
    context.gl();
    const GLuint maxGroups = maxComputeGroups();
    std::mt19937 rng(5);
    // Counts over several blocks of 1024 and a part block, as the slices' tiles make.
    const std::uint32_t n = 3 * 1024 * 256 + 77;
    std::vector<std::uint32_t> counts(n);
    for (std::uint32_t& c : counts) c = rng() % 9 == 0 ? 0 : rng() % 25;
    GlBuffer buffer, total;
    buffer.upload(counts.data(), std::uint64_t(n) * 4, nullptr);
    total.reserve(16, nullptr);
    total.clear(16);
    GpuScan scan(1000, maxGroups);
    scan.reserve(n);
    scan.run(buffer, n, &total);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    ReadbackBuffer readback;
    std::vector<std::uint32_t> got(n);
    std::memcpy(got.data(), readback.read(buffer.id(), std::uint64_t(n) * 4, nullptr), std::size_t(n) * 4);
    GLuint sum = 0;
    std::memcpy(&sum, readback.read(total.id(), 4, nullptr), 4);
    std::vector<std::uint32_t> expected(n);
    std::exclusive_scan(counts.begin(), counts.end(), expected.begin(), 0u);
    CHECK(got == expected);
    CHECK(sum == expected.back() + counts.back());

    // A sort made small, grown, then sorting with its keys kept.
    const std::uint32_t pairs = 30000;
    std::vector<std::uint32_t> keys(pairs), values(pairs);
    for (std::uint32_t i = 0; i < pairs; ++i) keys[i] = rng() % 5000 << 12 | rng() % 4096, values[i] = i;
    RadixSort sort(100, maxGroups);
    sort.reserve(pairs);
    glNamedBufferSubData(sort.keys().id(), 0, pairs * 4, keys.data());
    glNamedBufferSubData(sort.values().id(), 0, pairs * 4, values.data());
    GlBuffer out;
    out.reserve(pairs * 4, nullptr);
    sort.sort(pairs, out, /*withKeys=*/true);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<std::uint32_t> order(pairs), sortedKeys(pairs);
    std::memcpy(order.data(), readback.read(out.id(), pairs * 4, nullptr), pairs * 4);
    std::memcpy(sortedKeys.data(), readback.read(sort.keys().id(), pairs * 4, nullptr), pairs * 4);
    std::vector<std::uint32_t> expectedOrder(values);
    std::stable_sort(expectedOrder.begin(), expectedOrder.end(), [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
    CHECK(order == expectedOrder);
    std::size_t wrongKeys = 0;
    for (std::uint32_t i = 0; i < pairs; ++i) wrongKeys += sortedKeys[i] != keys[expectedOrder[i]];
    CHECK(wrongKeys == 0);
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

    SliceRenderer gpu(t.slices, everySlice(SlicePrimitive::Boxes)); // boxes, as the host's order draws them
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
    CHECK(test::nonBlackPixels(fromHost.image) > 96 * 72 / 10);
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
    SliceSettings inView, every;
    inView.lodPixels = every.lodPixels = 0.0;
    every.cull = false;
    SliceRenderer culled(t.slices, inView), all(t.slices, every);
    RenderReport fromCulled, fromAll;
    drawFrames(culled, camera, 1, fromCulled);
    drawFrames(all, camera, 1, fromAll);
    INFO(fromCulled.slices << " of " << n << " slices drawn");
    CHECK(fromAll.slices == n);
    CHECK(fromCulled.slices < n * 3 / 4);
    CHECK(fromCulled.slices > n / 10);
    CHECK(test::nonBlackPixels(fromAll.image) > 96 * 72 / 4);
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
        const double reach = std::sqrt(2.0) * t.slices.radius + t.slices.records[2 * i].w;
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

TEST_CASE("slice instances: each slice knows its place in its segment's run, and a cut box starts new runs", "[inspect]") {
    const test::GeneratedRun run = test::generatedRun(WeavePattern::Twill, GarmentShape::Flat, 40, 0.0, 48);
    SliceInstances slices = sliceInstances(run.plan, run.grid);
    REQUIRE(slices.count() == run.plan.sliceCount);
    CHECK(slices.radius == Approx(run.radius / run.grid.voxelSize));
    int wrongPlace = 0;
    for (const SegmentRecord& seg : run.plan.segments)
        for (std::uint32_t k = 0; k < seg.sliceCount; ++k) wrongPlace += slices.place(seg.firstSlice + k) != k;
    CHECK(wrongPlace == 0);

    // Half the garment's box: runs the box cuts restart where the slices kept resume.
    const SliceInstances all = slices;
    glm::dvec3 lo(1e30), hi(-1e30);
    for (std::uint64_t i = 0; i < all.count(); ++i) {
        lo = glm::min(lo, glm::dvec3(all.center(i)));
        hi = glm::max(hi, glm::dvec3(all.center(i)));
    }
    const glm::dvec3 mid = 0.5 * (lo + hi);
    keepSlicesWithin(slices, glm::dvec3(mid.x, lo.y, lo.z), glm::dvec3(hi.x + 1.0, mid.y, hi.z + 1.0));
    REQUIRE(slices.count() > 0);
    REQUIRE(slices.count() < all.count() / 2);
    // Each kept slice is found in the original (its centre), so its neighbour there is known.
    std::vector<std::uint64_t> original(slices.count());
    for (std::uint64_t j = 0, i = 0; j < slices.count(); ++j) {
        while (i < all.count() && all.records[2 * i] != slices.records[2 * j]) ++i;
        REQUIRE(i < all.count());
        original[j] = i++;
    }
    int broken = 0, restarts = 0, cutRuns = 0;
    for (std::uint64_t j = 0; j < slices.count(); ++j) {
        const std::uint32_t p = slices.place(j);
        const bool follows = j > 0 && original[j] == original[j - 1] + 1 && all.place(original[j]) == all.place(original[j - 1]) + 1;
        if (p > 0) broken += !follows || slices.place(j - 1) != p - 1;
        else broken += follows;
        restarts += p == 0;
        cutRuns += p == 0 && all.place(original[j]) != 0;
    }
    CHECK(broken == 0);
    CHECK(cutRuns > 0);
    CHECK(restarts > cutRuns);
}

TEST_CASE("slices on the GPU: slices far below a pixel apart are drawn a few as one slab, the picture nearly the same", "[inspect][gl]") {
    YV_REQUIRE_GL();
    RenderContext context;
    context.gl();
    // 40 slices a segment on a grid of 48, seen whole in 96x72 pixels: a
    // fraction of a pixel between slices.
    GenerateOptions g;
    g.pattern = WeavePattern::Knit;
    g.shape = GarmentShape::Cylinder;
    g.crossings = 120;
    const Garment garment = generateGarment(g);
    SliceOptions opt;
    opt.radius = garment.yarnRadius;
    opt.slicesPerSegment = 40;
    const SlicePlan plan = planSlices(garment, opt);
    const VoxelGrid grid = makeGrid(plan, 48, 0.0);
    const SliceInstances slices = sliceInstances(plan, grid);
    const std::uint64_t n = slices.count();
    const Camera camera = frameBox(sliceBox(plan, grid), ViewAngles{35.0, 25.0, 3.0}, 96, 72);

    SliceSettings host, off, on;
    host.sortOnHost = true;
    off.lodPixels = 0.0;
    on.lodPixels = 1.0;
    off.primitive = SlicePrimitive::Boxes; // as the host's order draws them
    off.cull = on.cull = false; // every slice counted in the picture
    SliceRenderer byHost(slices, host), every(slices, off), joined(slices, on);
    RenderReport fromHost, fromEvery, fromJoined;
    drawFrames(byHost, camera, 1, fromHost);
    drawFrames(every, camera, 1, fromEvery);
    drawFrames(joined, camera, 1, fromJoined);
    INFO(fromJoined.slices << " of " << n << " slices drawn at 1 pixel");
    CHECK(fromEvery.slices == n);
    CHECK(differingBytes(fromEvery.image, fromHost.image) == 0); // off: the picture as before
    CHECK(fromJoined.slices < n / 4);
    CHECK(fromJoined.garmentSlices == n);

    // Every slice lies in exactly one slab drawn, and a slab's slices are one run.
    const std::vector<std::uint32_t> order = joined.drawOrder(), spans = joined.spans();
    REQUIRE(order.size() == fromJoined.slices);
    std::vector<int> inSlabs(n, 0);
    int crossesRuns = 0, pastTheEnd = 0, joinedSlabs = 0;
    for (std::uint32_t i : order) {
        joinedSlabs += spans[i] > 1;
        for (std::uint32_t k = 0; k < spans[i]; ++k) {
            if (i + k >= n) {
                ++pastTheEnd;
                break;
            }
            inSlabs[i + k]++;
            crossesRuns += slices.place(i + k) != slices.place(i) + k;
        }
    }
    CHECK(pastTheEnd == 0);
    CHECK(std::count(inSlabs.begin(), inSlabs.end(), 1) == std::ptrdiff_t(n));
    CHECK(crossesRuns == 0);
    CHECK(joinedSlabs > int(order.size() / 2));

    // The picture: the same pixels covered, each colour within a few levels
    // on average. (Not closer: a slab along the chord of a bend, and sorted
    // as one, differs a little from the slices it stands for; on straight
    // yarns the difference is the rounding's, under a level.)
    double difference = 0.0;
    for (std::size_t i = 0; i < fromHost.image.pixels.size(); ++i)
        difference += std::abs(int(fromJoined.image.pixels[i]) - int(fromHost.image.pixels[i]));
    const double covered = double(test::nonBlackPixels(fromHost.image));
    const double meanDifference = difference / (3.0 * covered);
    INFO("mean difference " << meanDifference << " levels a channel over " << covered << " covered pixels");
    CHECK(covered > 96 * 72 / 10);
    CHECK(std::abs(double(test::nonBlackPixels(fromJoined.image)) - covered) < 0.02 * covered);
    CHECK(meanDifference < 4.0);
}

TEST_CASE("slices on the GPU: drawn as point sprites where every slab fits one, the picture the boxes draw", "[inspect][gl]") {
    YV_REQUIRE_GL();
    RenderContext context;
    context.gl();
    const TestSlices t = knitSlices(120, 48, 0);
    SliceRenderer asBoxes(t.slices, everySlice(SlicePrimitive::Boxes)), asChosen(t.slices, everySlice(SlicePrimitive::Points));
    // Whole, turned so that slabs lie every way, and near the picture's
    // sides (a point whose centre is outside the picture still draws its part
    // inside); then so close that slabs are wider than the largest point.
    const std::vector<ViewAngles> views = {{35.0, 25.0, 3.0}, {-70.0, 60.0, 2.0}, {10.0, -40.0, 1.6}};
    for (const ViewAngles& view : views) {
        const Camera camera = frameBox(t.box, view, 128, 96);
        RenderReport fromBoxes, fromPoints;
        drawFrames(asBoxes, camera, 1, fromBoxes);
        drawFrames(asChosen, camera, 1, fromPoints);
        INFO("view " << view.azimuth << ", " << view.elevation << ", " << view.distance << ": "
                     << fromPoints.slices << " slices");
        CHECK(fromBoxes.slicePrimitive == "boxes");
        CHECK(fromPoints.slicePrimitive == "points");
        CHECK(fromPoints.slices == fromBoxes.slices);
        CHECK(test::nonBlackPixels(fromBoxes.image) > 128 * 96 / 10);
        // The ray from the camera's inverse rather than through a face: a
        // level or two apart where rounding differs, a slab's grazing edge
        // at most a few pixels.
        CHECK(bytesOffBy(fromPoints.image, fromBoxes.image, 2) <= 128 * 96 * 3 / 200);
        CHECK(bytesOffBy(fromPoints.image, fromBoxes.image, 24) <= 12);
    }
    const Camera close = frameBox(t.box, ViewAngles{35.0, 25.0, 0.45}, 512, 384);
    RenderReport fromBoxes, fromChosen;
    drawFrames(asBoxes, close, 1, fromBoxes);
    drawFrames(asChosen, close, 1, fromChosen);
    CHECK(fromChosen.slicePrimitive == "boxes");
    CHECK(differingBytes(fromChosen.image, fromBoxes.image) == 0);
}

TEST_CASE("slices on the GPU: composited by tiles in compute, the picture the boxes draw", "[inspect][gl]") {
    YV_REQUIRE_GL();
    RenderContext context;
    context.gl();
    const TestSlices t = knitSlices(120, 48, 0);
    const SliceSettings tiles = everySlice(SlicePrimitive::Tiles);
    SliceRenderer asBoxes(t.slices, everySlice(SlicePrimitive::Boxes)), asTiles(t.slices, tiles);
    // Whole, turned so that slabs lie every way and near the picture's sides;
    // a size that is no multiple of the tiles'; closer; and so close that
    // slabs span many tiles and some reach the eye's plane.
    struct Case {
        ViewAngles view;
        int width, height;
    };
    const std::vector<Case> cases = {{{35.0, 25.0, 3.0}, 128, 96},
                                      {{-70.0, 60.0, 2.0}, 137, 91},
                                      {{10.0, -40.0, 1.2}, 160, 120},
                                      {{30.0, 20.0, 0.3}, 160, 120}};
    for (const Case& c : cases) {
        const Camera camera = frameBox(t.box, c.view, c.width, c.height);
        RenderReport fromBoxes, fromTiles;
        drawFrames(asBoxes, camera, 1, fromBoxes);
        drawFrames(asTiles, camera, 2, fromTiles); // twice: the second frame reuses the first's buffers
        INFO("view " << c.view.azimuth << ", " << c.view.elevation << ", " << c.view.distance << ": "
                     << fromTiles.slices << " slices");
        CHECK(fromBoxes.slicePrimitive == "boxes");
        CHECK(fromTiles.slicePrimitive == "tiles");
        CHECK(fromTiles.slices == fromBoxes.slices);
        const std::uint64_t pixels = std::uint64_t(c.width) * std::uint64_t(c.height);
        CHECK(test::nonBlackPixels(fromBoxes.image) > pixels / 10);
        // Blended in floats rather than the target's bytes, and each ray from
        // the camera's inverse rather than through a face: a level or two
        // apart, a slab's grazing edge at most a few pixels.
        CHECK(bytesOffBy(fromTiles.image, fromBoxes.image, 2) <= pixels / 100);
        CHECK(bytesOffBy(fromTiles.image, fromBoxes.image, 24) <= pixels / 1000);
    }

    // A frame that would make more pairs than the limit is drawn as boxes,
    // the boxes' picture to the byte; one within it still by tiles.
    const Camera camera = frameBox(t.box, ViewAngles{35.0, 25.0, 3.0}, 128, 96);
    RenderReport fromBoxes, fromTiles;
    drawFrames(asBoxes, camera, 1, fromBoxes);
    drawFrames(asTiles, camera, 1, fromTiles);
    REQUIRE(fromTiles.slicePrimitive == "tiles");
    SliceSettings tight = tiles, loose = tiles;
    tight.maxTilePairs = 1;
    loose.maxTilePairs = 4 * fromTiles.slices + 4096; // a slab here spans a tile or two
    SliceRenderer overLimit(t.slices, tight), withinLimit(t.slices, loose);
    RenderReport fromOver, fromWithin;
    drawFrames(overLimit, camera, 1, fromOver);
    drawFrames(withinLimit, camera, 1, fromWithin);
    CHECK(fromOver.slicePrimitive == "boxes");
    CHECK(fromOver.slices == fromBoxes.slices);
    CHECK(differingBytes(fromOver.image, fromBoxes.image) == 0);
    CHECK(fromWithin.slicePrimitive == "tiles");
    CHECK(differingBytes(fromWithin.image, fromTiles.image) == 0);
}
