// `yarnvox inspect`: numbers about what a run produced, from its work
// directory or from any .vdb with a float density grid, as text or JSON; its
// pictures (--render), isosurface meshes (--mesh) and HTML reports (--html).
// The command only parses its options into typed requests and prints what
// the inspect and render layers return for them; it makes the GL context
// (once, where a picture needs it) and lends it to whatever draws.
#include "cli/commands.h"
#include "cli/interruptible.h"
#include "cli/option_checks.h"
#include "core/error.h"
#include "core/output_path.h"
#include "core/world_units.h"
#include "inspect/mesh_report.h"
#include "inspect/render_request.h"
#include "inspect/store_report.h"
#include "inspect/transfer_function.h"
#include "inspect/vdb_report.h"
#include "vdb/vdb_file_check.h"
#include "pipeline/preview_slices.h"
#include "render/html_report.h"
#include "render/render_context.h"
#include "render/render_picture.h"

#include <CLI/CLI.hpp>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <tuple>

namespace yv {
namespace {

/// The options as given on the command line, before they are parsed into a request.
struct InspectArgs {
    std::string path, sort = "id";
    bool json = false, verify = false;
    std::size_t limit = 20;
    std::string render, output, view = "30,20,4", size = "800x600", tf = "fibre", cut, budget = "512M", garment, light,
        mesh;
    std::int64_t region = -1;
    int slices = 0;
    double iso = 0.5;
    int meshLevel = -1;
    PreviewSliceOptions preview; ///< volumetric-triangles: how the garment is sliced
    bool noSkip = false, showSamples = false, regions = false;
    int device = -1, repeat = 1;
    double yarnRadius = 0.0;
    double sliceLod = -1.0; ///< --slice-lod; below 0: not given
    std::string slicePrimitive; ///< --slice-primitive; empty: not given
    std::string html;            ///< --html DIR
    std::size_t htmlRenders = 8; ///< --html-renders N
};

/// "512M", "2G", "65536": bytes, with an optional K, M or G (powers of 1024);
/// at least one byte ("0.5" was a budget of 0 bytes).
std::uint64_t parseBytes(const std::string& text, const char* option) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    std::string unit(end);
    double scale = 1.0;
    if (unit == "K" || unit == "k") scale = 1024.0;
    else if (unit == "M" || unit == "m") scale = 1024.0 * 1024.0;
    else if (unit == "G" || unit == "g") scale = 1024.0 * 1024.0 * 1024.0;
    else if (!unit.empty()) scale = -1.0;
    if (end == text.c_str() || scale < 0.0 || !(v * scale >= 1.0) || v * scale > 1e15)
        throw Error(std::string(option) + " '" + text + "': expected a positive size in bytes, with K, M or G");
    return std::uint64_t(v * scale);
}

/// "WxH", each from 1 to 16384.
std::pair<int, int> parseSize(const std::string& text) {
    int w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || x != 'x' || w < 1 || h < 1 || w > 16384 ||
        h > 16384)
        throw Error("--size '" + text + "': expected WIDTHxHEIGHT, each from 1 to 16384 pixels");
    return {w, h};
}

/// The modes' names, as --render takes them.
std::vector<std::string> renderKindNames() {
    std::vector<std::string> names;
    for (const RenderKind kind : renderKinds()) names.push_back(renderKindName(kind));
    return names;
}

/// The options as requests, each checked as the old command checked them, in the same order (so that
/// the first of several mistakes is the one named).
StoreReportRequest storeRequest(const InspectArgs& a) {
    StoreReportRequest r;
    r.dir = a.path;
    r.json = a.json;
    r.verify = a.verify;
    for (const RegionColumn c : regionColumns())
        if (a.sort == regionColumnName(c)) r.sort = c;
    r.limit = a.limit;
    return r;
}

MeshRequest meshRequest(const InspectArgs& a) {
    MeshRequest r;
    r.input = a.path;
    r.mesh = a.mesh;
    r.iso = a.iso;
    if (a.meshLevel >= 0) r.level = a.meshLevel;
    if (a.region >= 0) r.region = std::uint64_t(a.region);
    r.json = a.json && a.render.empty(); // with --render, the picture's JSON is the one printed
    return r;
}

/// The options each mode takes, refused with the others.
void checkModeOptions(const InspectArgs& a, RenderKind kind) {
    if ((a.noSkip || a.showSamples) && !marchesRays(kind))
        throw Error(std::string(a.noSkip ? "--no-skip" : "--show-samples") +
                    " goes with --render raycast, mip, orientation or isosurface");
    if (a.slices > 0 && !drawsPlanes(kind)) throw Error("--slices goes with --render texture-slicing or half-angle");
    if (!a.light.empty() && kind != RenderKind::HalfAngle) throw Error("--light goes with --render half-angle");
}

PictureRequest pictureRequest(const InspectArgs& a) {
    PictureRequest p;
    RenderRequest& r = p.render;
    r.kind = parseRenderKind(a.render);
    r.view = parseView(a.view);
    std::tie(r.width, r.height) = parseSize(a.size);
    if (a.region >= 0) r.region = std::uint64_t(a.region);
    r.skipEmpty = !a.noSkip;
    r.showSamples = a.showSamples;
    r.isoValue = a.iso;
    if (r.kind == RenderKind::Cut) {
        if (a.cut.empty()) throw Error("--render cut needs --cut x|y|z:INDEX");
        r.cut = parseCut(a.cut);
    } else if (!a.cut.empty()) {
        throw Error("--cut goes with --render cut");
    }
    checkModeOptions(a, r.kind);
    r.slicePlanes = a.slices;
    if (!a.light.empty()) r.light = parseLight(a.light);
    r.gpuBudgetBytes = parseBytes(a.budget, "--gpu-budget");
    r.repeat = a.repeat;
    if (a.output.empty()) throw Error("--render needs -o FILE.png");
    if (r.kind != RenderKind::Slices && !a.garment.empty()) throw Error("--garment goes with --render slices");
    if (r.kind != RenderKind::Slices && a.sliceLod >= 0.0) throw Error("--slice-lod goes with --render slices");
    if (a.sliceLod >= 0.0) r.sliceLodPixels = a.sliceLod;
    if (r.kind != RenderKind::Slices && !a.slicePrimitive.empty()) throw Error("--slice-primitive goes with --render slices");
    if (!a.slicePrimitive.empty()) r.slicePrimitive = parseSlicePrimitive(a.slicePrimitive);
    if (r.kind != RenderKind::Slices && r.kind != RenderKind::VolumetricTriangles && a.yarnRadius > 0.0)
        throw Error("--yarn-radius goes with --render slices or volumetric-triangles");
    if (a.regions && r.kind == RenderKind::VolumetricTriangles)
        throw Error("--regions goes with the renders of a volume, not volumetric-triangles");
    if (a.regions && r.kind == RenderKind::Cut) throw Error("--regions goes with the perspective renders, not a cut");
    checkOutputPath(a.output, "-o", {a.path, a.garment});
    if (r.kind != RenderKind::Cut) r.transferFunction = loadTransferFunction(a.tf); // a bad --tf fails before any work
    p.input = a.path;
    p.output = a.output;
    p.viewText = a.view;
    p.cutText = a.cut;
    p.regions = a.regions;
    p.runSlices = RunSlicesOptions{a.garment, a.yarnRadius};
    p.preview = a.preview;
    p.json = a.json;
    return p;
}

HtmlReportRequest htmlRequest(const InspectArgs& a) {
    if (!a.render.empty() || !a.output.empty()) throw Error("--html writes its own renders: leave out --render and -o");
    HtmlReportRequest r;
    r.input = a.path;
    r.dir = a.html;
    r.regionRenders = a.htmlRenders;
    r.view = parseView(a.view);
    std::tie(r.width, r.height) = parseSize(a.size);
    r.transferFunctionName = a.tf;
    r.transferFunction = loadTransferFunction(a.tf); // a bad --tf fails before any work
    r.gpuBudgetBytes = parseBytes(a.budget, "--gpu-budget");
    return r;
}

void print(const std::string& text) { std::fputs(text.c_str(), stdout); }

/// What --verify of a .vdb found, when it found nothing wrong.
std::string verifiedLine(const std::string& path, const VdbFileCheck& check) {
    if (check.gridsChecked > 0)
        return "verified: the bytes of all " + std::to_string(check.gridsChecked) + " grids match their checksums";
    return "verified: the structure only: " + path +
           (check.yarnvox ? " records no checksums (written by a yarnvox before them)" : " was not written by yarnvox");
}

/// --mesh and --render: a mesh and a picture may go together.
void drawAndMesh(const InspectArgs& a) {
    if (!a.mesh.empty()) print(meshToFile(meshRequest(a)));
    if (!a.render.empty()) {
        const PictureRequest request = pictureRequest(a);
        RenderContext context(a.device);
        print(renderPicture(context, request));
    }
}

/// What `yarnvox inspect` does with its options: one report, picture or mesh
/// (a mesh and a picture may go together), each printed as it is done.
void runInspect(const InspectArgs& a) {
    if (!a.html.empty()) {
        const HtmlReportRequest request = htmlRequest(a);
        runInterruptible("the report " + a.html + " is whole", [&] {
            RenderContext context(a.device);
            saysWhatWasKept("while the report was built",
                            "the report " + a.html + " was not written (an earlier one there is as it was); run the command again",
                            [&] { print(writeHtmlReport(context, request)); });
        });
        return;
    }
    if (a.meshLevel >= 0 && a.mesh.empty()) throw Error("--mesh-level goes with --mesh");
    if (!a.mesh.empty() || !a.render.empty()) {
        // Pictures and meshes are written whole or not at all: a signal stops before the next one.
        runInterruptible("every file asked for is whole", [&] { drawAndMesh(a); });
        return;
    }
    if (!a.output.empty()) throw Error("-o goes with --render");
    if (!std::filesystem::is_directory(a.path)) {
        // Checked before the report, which would read damaged values as they are.
        const VdbFileCheck check = a.verify ? checkVdbFile(a.path) : VdbFileCheck{};
        print(vdbReport(a.path, a.json, a.verify));
        if (a.verify) std::fprintf(a.json ? stderr : stdout, "%s\n", verifiedLine(a.path, check).c_str());
        return;
    }
    const StoreReport report = storeReport(storeRequest(a));
    print(report.text);
    if (!report.failure.empty()) throw Error(report.failure);
}

/// The input and the options of the text and JSON reports.
void addReportOptions(CLI::App* cmd, InspectArgs& a) {
    cmd->add_option("path", a.path, "A work directory (--work-dir, --keep-work-dir) or an OpenVDB file with a float 'density' grid (or, "
                    "for --render volumetric-triangles, a .bcc garment)")
        ->required()
        ->check(CLI::ExistingPath);
    cmd->add_flag("--json", a.json, "Print JSON instead of text");
    cmd->add_flag("--verify", a.verify,
                  "Work directory: read every region in full, check its checksums, and exit 1 naming the damaged ones; "
                  "a yarnvox .vdb: check its structure and every grid's checksum, and exit 1 naming the grid whose "
                  "bytes changed; count every voxel rather than use the statistics the file records, and compare");
    std::vector<std::string> columns;
    for (const RegionColumn c : regionColumns()) columns.push_back(regionColumnName(c));
    cmd->add_option("--sort", a.sort, "Work directory: order the region table by this column (largest first)")
        ->capture_default_str()
        ->check(CLI::IsMember(columns));
    cmd->add_option("--limit", a.limit, "Work directory: rows of the region table to print (0: all; JSON has all)")
        ->capture_default_str()
        ->check(wholeNumber<std::size_t>(0, 1'000'000'000));
}

/// --render and the options every picture takes.
void addPictureOptions(CLI::App* cmd, InspectArgs& a) {
    cmd->add_option("--render", a.render,
                    "Draw a picture to -o instead of printing numbers: raycast (transfer function), mip (maximum "
                    "density along each ray), cut (one plane of voxels, --cut), orientation (|axis| as RGB), slices "
                    "(the run's garment as alpha-blended slices shaded by fibre orientation, sorted back to front on "
                    "the GPU; the garment and slice options the run recorded, or --garment), texture-slicing "
                    "(view-aligned planes blended back to front, --slices), half-angle (planes lit by a directional "
                    "light, --light, with shadows), splatting (each voxel a Gaussian splat, for comparing coarse "
                    "levels with raycast), isosurface (the surface at density --iso, shaded by the density gradient) "
                    "or volumetric-triangles (the garment's slices as blurred volumetric triangles, no voxelizing; the "
                    "path may be a .bcc garment, or a volume whose recorded garment is still there)")
        ->check(CLI::IsMember(renderKindNames()));
    cmd->add_option("-o,--output", a.output, "--render: the PNG to write (replaced atomically)");
    cmd->add_option("--view", a.view,
                    "--render: azimuth,elevation,distance: degrees about +z from +x, degrees above the xy plane, "
                    "bounding-sphere radii from the centre (4 fits the volume)")
        ->capture_default_str();
    cmd->add_option("--size", a.size, "--render: picture size WIDTHxHEIGHT")->capture_default_str();
    cmd->add_option("--region", a.region,
                    "--render: frame and draw only this zoom region of a work directory or of a .vdb that records its "
                    "regions (yarnvox voxelize and merge write them)")
        ->check(wholeNumber<std::int64_t>(0, std::int64_t(1) << 62));
    cmd->add_flag("--regions", a.regions,
                  "--render (not cut): draw the zoom-region boxes of the work directory or of the .vdb over the "
                  "picture, coloured by "
                  "heat (active voxels: blue, red, yellow; legend bar at the bottom left, scale printed)");
    cmd->add_option("--garment", a.garment,
                    "--render slices: the garment (.bcc) to draw, instead of the one the run recorded (needed for a "
                    ".vdb not made by yarnvox or a garment that moved)")
        ->check(CLI::ExistingFile);
    cmd->add_option("--slice-lod", a.sliceLod,
                    "--render slices: level of detail, in pixels: where a yarn's slices lie closer on screen, one "
                    "slab is drawn for 2, 4, ... 64 consecutive slices, none longer than this (0: every slice; "
                    "default " + numberText(kDefaultSliceLodPixels) + ")")
        ->check(finiteRange(0.0, 1e6));
    cmd->add_option("--slice-primitive", a.slicePrimitive,
                    "--render slices: how each slab is drawn: tiles (composited in compute, tile by tile of the "
                    "picture, where no slab spans too many tiles), points (one point sprite a slab where every slab "
                    "in view fits one), boxes (always), or auto (default: tiles, else points, else boxes); the "
                    "picture is the same");
    cmd->add_option("--yarn-radius", a.yarnRadius,
                    "--render slices|volumetric-triangles: yarn radius in world units, instead of the one the run "
                    "recorded (a bare garment: the garment file's, else estimated)")
        ->check(worldLength());
    std::string presets;
    for (const std::string& n : transferFunctionPresets()) presets += (presets.empty() ? "" : ", ") + n;
    cmd->add_option("--tf", a.tf,
                    "--render raycast|orientation|texture-slicing|half-angle|splatting: transfer function, a preset (" + presets +
                        ") or a colour map file (lines 'density r g b opacity', formats/transfer-function.md)")
        ->capture_default_str();
}

/// The options of single modes, the mesh and the garment previews.
void addModeOptions(CLI::App* cmd, InspectArgs& a) {
    cmd->add_option("--slices", a.slices,
                    "--render texture-slicing|half-angle: slices through the box (0: one per voxel of the drawn "
                    "level across the box's depth)")
        ->check(wholeNumber(0, 100000))
        ->capture_default_str();
    cmd->add_option("--light", a.light,
                    "--render half-angle: azimuth,elevation the light comes from, degrees as in --view (default 75,45)");
    cmd->add_flag("--no-skip", a.noSkip, "--render raycast|mip|orientation|isosurface: march every ray through the whole box (no empty-space skipping)");
    cmd->add_flag("--show-samples", a.showSamples, "--render raycast|mip|orientation|isosurface: picture the samples taken per pixel instead");
    cmd->add_option("--iso", a.iso, "--render isosurface and --mesh: the density the surface lies at")
        ->check(finiteRange(1e-6, 1e6))
        ->capture_default_str();
    cmd->add_option("--mesh", a.mesh,
                    "Write the isosurface at --iso as a mesh (.ply binary or .obj, voxel coordinates), extracted by "
                    "OpenVDB's volumeToMesh; refused when larger than about 100 million triangles unless --mesh-level");
    cmd->add_option("--mesh-level", a.meshLevel,
                    "--mesh: extract at this level of detail (0: full resolution; L: each voxel the mean of 2^L a side)")
        ->check(wholeNumber(0, 20));
    cmd->add_option("--resolution", a.preview.resolution,
                    "--render volumetric-triangles of a garment: voxels on the longest axis of the grid it is drawn on "
                    "(sets the blur and the slice spacing; default " + std::to_string(kPreviewResolution) + ")")
        ->check(wholeNumber(8, 1 << 20));
    cmd->add_option("--slice-spacing", a.preview.spacing,
                    "--render volumetric-triangles: distance between slices along a yarn, world units (default: one "
                    "voxel, as voxelize)")
        ->check(worldLength());
    cmd->add_option("--cross-section", a.preview.crossSection,
                    "--render volumetric-triangles: fibre density on each slice, fibers, disk or FILE.png; its mean "
                    "over the yarn's disk is the preview's density (default: the volume's, else fibers)");
    cmd->add_option("--slices-per-segment", a.preview.slicesPerSegment,
                    "--render volumetric-triangles: slices per curve segment, instead of --slice-spacing")
        ->check(wholeNumber(1, 100000));
    cmd->add_option("--cut", a.cut, "--render cut: the plane, x|y|z:INDEX (voxel index)");
}

/// The GPU's budget and device, timing, and the HTML report.
void addDeviceAndReportOptions(CLI::App* cmd, InspectArgs& a) {
    cmd->add_option("--gpu-budget", a.budget,
                    "--render: GPU memory for the brick atlas (K, M, G); a volume that needs more is drawn at a "
                    "coarser level")
        ->capture_default_str();
    cmd->add_option("--repeat", a.repeat, "--render: draw the frame this many times and report the median time")
        ->check(wholeNumber(1, 1000))
        ->capture_default_str();
    cmd->add_option("--device", a.device, "--render: EGL device index (-1: the first GPU, else llvmpipe)")
        ->capture_default_str()
        ->check(wholeNumber(-1, 1023));
    cmd->add_option("--html", a.html,
                    "Write a report to this directory, for a browser without a server: summary, density histogram, "
                    "time per stage, regions coloured by heat linked to their table rows, and renders (PNG files) of "
                    "the whole volume and the hottest regions (--view, --size, --tf, --gpu-budget apply). The "
                    "directory is replaced whole at the end; an existing one must be empty or an earlier report");
    cmd->add_option("--html-renders", a.htmlRenders, "--html: render this many regions, those with the most active voxels")
        ->capture_default_str()
        ->check(wholeNumber<std::size_t>(0, 10000));
}

} // namespace

void addInspectCommand(CLI::App& app) {
    auto args = std::make_shared<InspectArgs>();
    CLI::App* cmd = app.add_subcommand(
        "inspect", "Numbers about a voxelization: a work directory's regions, or a .vdb's grids and voxels");
    addReportOptions(cmd, *args);
    addPictureOptions(cmd, *args);
    addModeOptions(cmd, *args);
    addDeviceAndReportOptions(cmd, *args);
    cmd->callback([args] { runInspect(*args); });
}

} // namespace yv
