#include "render/render_picture.h"

#include "core/error.h"
#include "core/stats.h"
#include "core/world_units.h"
#include "inspect/region_heat.h"
#include "inspect/report_text.h"
#include "render/render_volume.h"
#include "render/volumetric_triangles.h"

#include <filesystem>
#include <memory>

namespace yv {
namespace {

/// What the picture came from beside the report: the notes on the run's
/// slices (what was assumed to find them).
struct Drawn {
    RenderReport report;
    std::vector<std::string> notes;
};

/// A garment is sliced as voxelize slices it; a volume's slices come from
/// the garment it was made from, framed by the volume's own box.
RenderReport drawGarmentSlices(RenderContext& context, const PictureRequest& p) {
    const RenderRequest& r = p.render;
    PreviewSliceOptions preview = p.preview;
    preview.yarnRadius = p.runSlices.yarnRadius;
    const bool garment = !std::filesystem::is_directory(p.input) && std::filesystem::path(p.input).extension() != ".vdb";
    const PreviewSlices slices = garment ? garmentPreviewSlices(p.input, preview) : volumePreviewSlices(p.input, preview);
    VoxelBox box = sliceBox(slices.plan, slices.grid);
    if (!garment) {
        const std::unique_ptr<VolumeSource> source = openVolumeSource(p.input);
        box = r.region ? source->regionBounds(*r.region) : source->bounds();
    } else if (r.region) {
        throw Error("--region needs a work directory, not a garment");
    }
    return renderVolumetricTriangles(context, slices.plan, slices.grid, box, r, slices.yarnDensity);
}

Drawn draw(RenderContext& context, PictureRequest& p) {
    RenderRequest& r = p.render;
    if (r.kind == RenderKind::VolumetricTriangles) return Drawn{drawGarmentSlices(context, p), {}};
    const std::unique_ptr<VolumeSource> source = openVolumeSource(p.input);
    if (p.regions) r.outlines = loadRegionHeat(p.input);
    if (r.kind != RenderKind::Slices) return Drawn{renderVolume(context, *source, r), {}};
    const RunSlices run = loadRunSlices(p.input, p.runSlices);
    SliceInstances slices = sliceInstances(run.plan, run.grid);
    // A framed region shows its own slices, not the ones in front of it.
    if (r.region) {
        const VoxelBox box = source->regionBounds(*r.region);
        keepSlicesWithin(slices, glm::dvec3(box.min), glm::dvec3(box.max));
    }
    r.slices = &slices;
    Drawn drawn{renderVolume(context, *source, r), run.notes};
    r.slices = nullptr;
    drawn.notes.insert(drawn.notes.begin(), "slices of " + run.garmentPath);
    return drawn;
}

std::string pictureJson(const PictureRequest& p, const Drawn& d) {
    const RenderRequest& r = p.render;
    const RenderReport& rep = d.report;
    JsonObject out;
    out.set("path", p.input).set("output", p.output).set("render", renderKindName(r.kind)).set("width", rep.image.width)
        .set("height", rep.image.height);
    if (!r.outlines.empty()) out.set("region_heat", regionHeatJson(r.outlines));
    if (r.kind == RenderKind::VolumetricTriangles) {
        out.set("view", p.viewText)
            .set("renderer", rep.renderer)
            .set("frames", r.repeat)
            .set("frame_seconds_median", rep.frameSeconds)
            .set("frame_seconds_best", rep.bestFrameSeconds);
    } else if (r.kind == RenderKind::Slices) {
        std::string joined;
        for (const std::string& n : d.notes) joined += (joined.empty() ? "" : "; ") + n;
        out.set("view", p.viewText)
            .set("renderer", rep.renderer)
            .set("slices", rep.slices)
            .set("garment_slices", rep.garmentSlices)
            .set("slice_lod_pixels", r.sliceLodPixels)
            .set("slice_primitive", rep.slicePrimitive)
            .set("frames", r.repeat)
            .set("sort_seconds_median", rep.sortSeconds)
            .set("sort_seconds_best", rep.bestSortSeconds)
            .set("frame_seconds_median", rep.frameSeconds)
            .set("frame_seconds_best", rep.bestFrameSeconds)
            .set("load_seconds", rep.loadSeconds)
            .set("notes", joined);
    } else if (r.kind != RenderKind::Cut)
        out.set("view", p.viewText)
            .set("renderer", rep.renderer)
            .set("skip_empty", r.skipEmpty && marchesRays(r.kind))
            .set("gpu_budget_bytes", rep.budgetBytes)
            .set("level", rep.level)
            .set("level_stored", rep.storedLevel)
            .set("fine_bricks", rep.fineBricks)
            .set("level_bricks", rep.levelBricks)
            .set("gpu_bytes", rep.gpuBytes)
            .set("proxy_triangles", rep.proxyTriangles)
            .set("mean_samples_per_pixel", rep.meanSamples)
            .set("frames", r.repeat)
            .set("frame_seconds_median", rep.frameSeconds)
            .set("frame_seconds_best", rep.bestFrameSeconds)
            .set("load_seconds", rep.loadSeconds);
    if (rep.slices) out.set("slices", rep.slices);
    if (rep.splats) out.set("splats", rep.splats);
    return out.dump() + "\n";
}

/// The level drawn, its bricks and bytes, and the frame: what a render of a
/// volume's voxels says after its first line.
std::string volumeText(const PictureRequest& p, const RenderReport& rep) {
    const RenderRequest& r = p.render;
    const char* median = r.repeat > 1 ? " (median)" : "";
    std::string out;
    if (rep.storedLevel)
        appendf(out,
                "  drawn at level %d of the file's level-of-detail grids, the finest within the GPU budget (%s): each "
                "voxel the mean of %dx%dx%d voxels (%llu bricks, %s)\n",
                rep.level, bytesText(double(rep.budgetBytes)).c_str(), 1 << rep.level, 1 << rep.level, 1 << rep.level,
                static_cast<unsigned long long>(rep.levelBricks), bytesText(double(rep.gpuBytes)).c_str());
    else if (rep.level > 0)
        appendf(out,
                "  the %llu occupied bricks exceed the GPU budget (%s): drawn at level %d, each voxel the mean of "
                "%dx%dx%d voxels (%llu bricks, %s)\n",
                static_cast<unsigned long long>(rep.fineBricks), bytesText(double(rep.budgetBytes)).c_str(), rep.level,
                1 << rep.level, 1 << rep.level, 1 << rep.level, static_cast<unsigned long long>(rep.levelBricks),
                bytesText(double(rep.gpuBytes)).c_str());
    else
        appendf(out, "  %llu bricks at full resolution, %s on the GPU\n", static_cast<unsigned long long>(rep.levelBricks),
                bytesText(double(rep.gpuBytes)).c_str());
    if (!marchesRays(r.kind)) {
        const std::string drawn = rep.splats ? std::to_string(rep.splats) + " voxels splatted (the empty ones culled on the GPU)"
                                             : std::to_string(rep.slices) + " slices";
        appendf(out, "  %s; frame %.3f s%s (loading %.3f s)\n", drawn.c_str(), rep.frameSeconds, median, rep.loadSeconds);
        return out;
    }
    const std::string proxy = r.skipEmpty ? " (" + std::to_string(rep.proxyTriangles) + " proxy triangles)" : "";
    appendf(out, "  empty-space skipping %s%s; mean samples per pixel %.2f; frame %.3f s%s (loading %.3f s)\n",
            r.skipEmpty ? "on" : "off", proxy.c_str(), rep.meanSamples, rep.frameSeconds, median, rep.loadSeconds);
    return out;
}

std::string pictureText(const PictureRequest& p, const Drawn& d) {
    const RenderRequest& r = p.render;
    const RenderReport& rep = d.report;
    std::string out;
    if (r.kind == RenderKind::Cut) {
        appendf(out, "%s: cut %s, %dx%d pixels, one a voxel\n", p.output.c_str(), p.cutText.c_str(), rep.image.width,
                rep.image.height);
        return out;
    }
    if (!r.outlines.empty()) out += regionHeatText(r.outlines);
    if (r.kind == RenderKind::VolumetricTriangles) {
        appendf(out, "%s: volumetric-triangles, %dx%d, on %s; frame %.3f s%s (slices placed and drawn)\n", p.output.c_str(),
                r.width, r.height, rep.renderer.c_str(), rep.frameSeconds, r.repeat > 1 ? " (median)" : "");
        return out;
    }
    if (r.kind == RenderKind::Slices) {
        appendf(out, "%s: slices, %dx%d, on %s\n", p.output.c_str(), r.width, r.height, rep.renderer.c_str());
        for (const std::string& n : d.notes) appendf(out, "  %s\n", n.c_str());
        const std::string joined = r.sliceLodPixels > 0.0 ? ", or joined where they lie under " +
                                                                 numberText(r.sliceLodPixels) +
                                                                 (r.sliceLodPixels == 1.0 ? " pixel apart" : " pixels apart")
                                                           : std::string();
        appendf(out, "  %llu of %llu slices drawn (the others outside the view%s); back-to-front sort %.3f s (on the "
                "GPU), draw %.3f s%s (uploading %.3f s)\n",
                static_cast<unsigned long long>(rep.slices), static_cast<unsigned long long>(rep.garmentSlices),
                joined.c_str(), rep.sortSeconds, rep.frameSeconds,
                r.repeat > 1 ? " (medians)" : "", rep.loadSeconds);
        return out;
    }
    appendf(out, "%s: %s, %dx%d, on %s\n", p.output.c_str(), renderKindName(r.kind), r.width, r.height,
            rep.renderer.c_str());
    return out + volumeText(p, rep);
}

} // namespace

std::string renderPicture(RenderContext& context, const PictureRequest& request) {
    PictureRequest p = request;
    const Drawn drawn = draw(context, p);
    writePng(p.output, drawn.report.image);
    return p.json ? pictureJson(p, drawn) : pictureText(p, drawn);
}

} // namespace yv
