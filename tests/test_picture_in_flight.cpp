// The live view queues a frame's two pictures before it reads either
// (PictureInFlight): each must be the picture drawFrames draws on its own,
// whichever renderer drew before it, and a ray cast that leaves its samples
// on the GPU the same picture as one that reads them.
#include "cpu/cpu_voxelizer.h"
#include "garment/cross_section.h"
#include "gpu/egl_context.h"
#include "inspect/brick_level.h"
#include "inspect/camera.h"
#include "inspect/slice_instances.h"
#include "inspect/volume_source.h"
#include "render/brick_atlas.h"
#include "render/raycast_renderer.h"
#include "render/renderer.h"
#include "render/slice_renderer.h"
#include "inspect_test_volumes.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>

using namespace yv;

TEST_CASE("pictures queued back to back are the pictures drawn one at a time", "[inspect][gl][view]") {
    YV_REQUIRE_GL();
    GlContext context;
    const test::GeneratedRun run = test::generatedRun(WeavePattern::Knit, GarmentShape::Cylinder, 120, 0.0, 48);
    const BrickVolume volume = voxelizeCpu(run.plan, makeFiberCrossSection(), run.grid, VoxelizeSettings{});
    const auto source = memorySource(volume);
    const VoxelBox box = source->bounds();
    const LevelPlan plan = planLevel(*source, box, 1ull << 30, atlasBytesPerVoxel(false), context.info().max3dTextureSize);
    BrickAtlas atlas(plan, false, context.info().max3dTextureSize);
    streamLevelBricks(*source, box, plan, false, [&](const LevelBrick& b) { atlas.upload(b); });
    atlas.finish();
    const SliceInstances instances = sliceInstances(run.plan, run.grid);

    RaycastSettings leaving, counting;
    leaving.countSamples = false;
    RaycastRenderer rayLeaving(atlas, RenderMode::Raycast, leaving), rayCounting(atlas, RenderMode::Raycast, counting);
    SliceSettings every;
    every.lodPixels = 0.0;
    SliceRenderer slices(instances, every);

    for (const ViewAngles& view : {ViewAngles{35.0, 25.0, 3.0}, ViewAngles{-120.0, -10.0, 1.8}}) {
        const Camera camera = frameBox(box, view, 96, 72);
        RenderReport slicesAlone, rayAlone, rayWithSamples;
        drawFrames(slices, camera, 1, slicesAlone);
        drawFrames(rayLeaving, camera, 1, rayAlone);
        drawFrames(rayCounting, camera, 1, rayWithSamples);
        INFO("view " << view.azimuth << ", " << view.elevation << ", " << view.distance);
        CHECK(test::nonBlackPixels(slicesAlone.image) > 96 * 72 / 10);
        CHECK(test::nonBlackPixels(rayAlone.image) > 96 * 72 / 10);
        CHECK(rayAlone.image.pixels == rayWithSamples.image.pixels);
        CHECK(rayAlone.meanSamples == 0.0);
        CHECK(rayWithSamples.meanSamples > 0.0);

        // Both queued, then both read, in the view's order and the other way round.
        PictureInFlight first(slices, camera, context.info().hardware()), second(rayLeaving, camera, context.info().hardware());
        const RenderReport slicesQueued = first.finish(), rayQueued = second.finish();
        CHECK(slicesQueued.image.pixels == slicesAlone.image.pixels);
        CHECK(rayQueued.image.pixels == rayAlone.image.pixels);
        CHECK(slicesQueued.slices == slicesAlone.slices);
        CHECK(slicesQueued.slicePrimitive == slicesAlone.slicePrimitive);
        CHECK(slicesQueued.frameSeconds > 0.0);
        PictureInFlight rayFirst(rayLeaving, camera, context.info().hardware()), slicesSecond(slices, camera, context.info().hardware());
        const RenderReport rayQueuedFirst = rayFirst.finish(), slicesQueuedSecond = slicesSecond.finish();
        CHECK(rayQueuedFirst.image.pixels == rayAlone.image.pixels);
        CHECK(slicesQueuedSecond.image.pixels == slicesAlone.image.pixels);
    }
}
