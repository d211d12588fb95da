// `yarnvox export`: an existing .vdb to renderer formats (Mitsuba .vol,
// NanoVDB .nvdb), whole or a box of it, from the leaves already written.
#include "cli/commands.h"
#include "cli/interruptible.h"
#include "cli/option_checks.h"
#include "cli/output_format.h"
#include "core/error.h"
#include "core/output_path.h"
#include "core/text.h"
#include "core/world_units.h"
#include "export/fiber_grids.h"
#include "store/brick_store.h"
#include "vdb/vdb_file_check.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <sstream>

namespace yv {
namespace {

struct ExportArgs {
    std::string input, output, format, bbox, bboxWorld, workDir, volType = "float32", orientationVolType,
        volBox = "corners";
    std::int64_t region = -1;
    double sggx = 0.0;
    bool quiet = false;
};

/// Six comma-separated numbers, e.g. "0,0,0,64,64,32"; throws naming the option.
std::array<double, 6> parseSix(const std::string& text, const std::string& option) {
    const std::optional<std::vector<double>> numbers = parseNumberList(text, 6);
    if (!numbers) throw Error(option + " " + text + ": expected six numbers x0,y0,z0,x1,y1,z1");
    std::array<double, 6> v{};
    std::copy(numbers->begin(), numbers->end(), v.begin());
    return v;
}

/// The box asked for, if any: voxel indices, world units, or a work directory's region.
std::optional<VoxelBox> requestedBox(const ExportArgs& a, const FiberGrids& grids) {
    if (!a.bbox.empty()) {
        const std::array<double, 6> v = parseSix(a.bbox, "--bbox");
        VoxelBox box;
        for (int i = 0; i < 6; ++i)
            if (v[i] != std::floor(v[i]) || std::abs(v[i]) > 2e9)
                throw Error("--bbox " + a.bbox + ": voxel indices are whole numbers (use --bbox-world for world units)");
        box.min = {int(v[0]), int(v[1]), int(v[2])};
        box.max = {int(v[3]), int(v[4]), int(v[5])};
        if (box.empty())
            throw Error("--bbox " + a.bbox + ": holds no voxel (the maximum is exclusive and must exceed the minimum)");
        return box;
    }
    if (!a.bboxWorld.empty()) {
        const std::array<double, 6> v = parseSix(a.bboxWorld, "--bbox-world");
        for (double x : v)
            if (const std::string p = coordinateProblem(x); !p.empty()) throw Error("--bbox-world " + a.bboxWorld + ": a coordinate " + p);
        try {
            return voxelBoxFromWorld(grids.density->transform(), {v[0], v[1], v[2]}, {v[3], v[4], v[5]});
        } catch (const Error& e) {
            throw Error("--bbox-world " + a.bboxWorld + ": " + e.what());
        }
    }
    if (a.region >= 0) {
        // Zoom regions are recorded in the work directory, not in the .vdb.
        const BrickStore store(a.workDir);
        bool known = false;
        for (std::uint64_t id : store.regionIds()) known |= id == std::uint64_t(a.region);
        if (!known) throw Error("--region " + std::to_string(a.region) + ": " + a.workDir + " has no such region (yarnvox inspect " + a.workDir + " lists them)");
        const RegionInfo r = store.regionInfo(std::uint64_t(a.region));
        // The work directory must be the one this .vdb was made from.
        const VoxelGrid& g = store.manifest().grid;
        const openvdb::Vec3d centre0 = grids.density->indexToWorld(openvdb::Coord(0, 0, 0));
        const double h = grids.density->voxelSize()[0];
        bool same = std::abs(h - g.voxelSize) <= 1e-9 * g.voxelSize;
        for (int i = 0; i < 3; ++i) same = same && std::abs(centre0[i] - (g.origin[i] + 0.5 * g.voxelSize)) <= 1e-6 * g.voxelSize;
        if (!same)
            throw Error("--region: " + a.workDir + " holds a grid of voxel size " + numberText(g.voxelSize) + " and another origin than " +
                        a.input + " (voxel size " + numberText(h) + "): not the run that made it");
        return VoxelBox{r.min, r.max};
    }
    return std::nullopt;
}

/// "[x0, x1) x [y0, y1) x [z0, z1)", as the export's summary prints boxes.
std::string boxText(glm::ivec3 lo, glm::ivec3 hi) {
    std::string s;
    for (int i = 0; i < 3; ++i)
        s += (i ? " x [" : "[") + std::to_string(lo[i]) + ", " + std::to_string(hi[i]) + ")";
    return s;
}

/// Refuses a box that holds none of the volume's active voxels: its export
/// was a box of zeros, with exit 0. `asked` is the option as typed.
void checkBoxMeetsVolume(const VoxelBox& box, const FiberGrids& grids, const std::string& asked) {
    if (grids.density->activeVoxelCount() == 0) throw Error(asked + ": the volume has no active voxels: nothing to export");
    const openvdb::CoordBBox active = grids.density->evalActiveVoxelBoundingBox();
    const glm::ivec3 lo(active.min().x(), active.min().y(), active.min().z());
    const glm::ivec3 hi = glm::ivec3(active.max().x(), active.max().y(), active.max().z()) + 1;
    for (int i = 0; i < 3; ++i)
        if (box.max[i] <= lo[i] || box.min[i] >= hi[i])
            throw Error(asked + ": holds voxels " + boxText(box.min, box.max) + ", none of the volume's, which lie in " +
                        boxText(lo, hi) + ": nothing to export");
}

void runExport(const ExportArgs& a) {
    const OutputFormat format = resolveOutputFormat(a.format, a.output, false);
    VolExportOptions vol;
    vol.densityEncoding = parseVolEncoding(a.volType);
    vol.orientationEncoding = parseVolEncoding(a.orientationVolType.empty() ? a.volType : a.orientationVolType);
    vol.albedoEncoding = vol.densityEncoding; // colours lie in [0, 1] like densities
    vol.boxConvention = parseVolBoxConvention(a.volBox);
    vol.sggxRoughness = a.sggx;
    const bool cropped = !a.bbox.empty() || !a.bboxWorld.empty() || a.region >= 0;
    if (format == OutputFormat::Nvdb && (cropped || a.sggx > 0.0))
        throw Error("--bbox, --bbox-world, --region and --sggx apply to .vol exports; a .nvdb holds the whole sparse volume");
    if (a.region >= 0 && a.workDir.empty())
        throw Error("--region " + std::to_string(a.region) + " needs --work-dir DIR: zoom regions are recorded in the run's work directory, not in the .vdb");
    // OpenVDB reads a damaged file into a wrong volume (or a crash): a yarnvox file is checked whole first.
    checkVdbFile(a.input);
    const FiberGrids grids = readFiberGrids(a.input);
    vol.box = requestedBox(a, grids);
    if (vol.box && a.region < 0)
        checkBoxMeetsVolume(*vol.box, grids, a.bbox.empty() ? "--bbox-world " + a.bboxWorld : "--bbox " + a.bbox);
    for (const std::string& p : exportPaths(format, a.output, bool(grids.orientation), vol, bool(grids.albedo)))
        checkOutputPath(p, "-o", {a.input});
    convertVdb(a.input, format, a.output, vol, a.quiet);
}

} // namespace

void addExportCommand(CLI::App& app) {
    auto a = std::make_shared<ExportArgs>();
    CLI::App* cmd = app.add_subcommand(
        "export", "Convert a .vdb (density, orientation) to Mitsuba .vol files or NanoVDB, whole or a box of it");
    cmd->add_option("input", a->input, "The .vdb to convert (yarnvox's, or any with a float 'density' grid)")->required();
    cmd->add_option("-o,--output", a->output,
                    "OUT.vol (density; orientation at OUT.orientation.vol and, from an --albedo run, the linear RGB "
                    "albedo at OUT.albedo.vol (--vol-type) beside it) or OUT.nvdb (every grid)")
        ->required();
    cmd->add_option("--format", a->format, "vol or nvdb (default: from the output's extension)")
        ->check(CLI::IsMember({"vol", "nvdb"}));
    auto* bbox = cmd->add_option("--bbox", a->bbox,
                                 "i0,j0,k0,i1,j1,k1: voxel index box, min inclusive, max exclusive (as `yarnvox inspect` "
                                 "prints region bounds; default: the bounds of the active voxels and one voxel around them)");
    auto* world = cmd->add_option("--bbox-world", a->bboxWorld,
                                  "x0,y0,z0,x1,y1,z1: world-unit box; every voxel whose cell overlaps it is exported")
                      ->excludes(bbox);
    auto* region = cmd->add_option("--region", a->region, "Zoom region id from the run's work directory (needs --work-dir)")
                       ->check(wholeNumber<std::int64_t>(0, std::int64_t(1) << 62))
                       ->excludes(bbox)
                       ->excludes(world);
    cmd->add_option("--work-dir", a->workDir, "The voxelize run's work directory (--work-dir or --keep-work-dir), for --region")
        ->check(CLI::ExistingDirectory)
        ->needs(region);
    cmd->add_option("--vol-type", a->volType,
                    ".vol value type: float32 (Mitsuba 0.6 and 3), float16, or uint8 (one byte a voxel: density * 255; "
                    "axis components 128 + 127 c; albedo 255 c)")
        ->capture_default_str()
        ->check(CLI::IsMember({"float32", "float16", "uint8"}));
    cmd->add_option("--orientation-vol-type", a->orientationVolType, "Value type of OUT.orientation.vol (default: --vol-type)")
        ->check(CLI::IsMember({"float32", "float16", "uint8"}));
    cmd->add_option("--vol-bbox", a->volBox,
                    "What the .vol header's box spans: corners (the voxels' outer faces; Mitsuba 3) or centres (the first "
                    "and last voxel centres; Mitsuba 0.6)")
        ->capture_default_str()
        ->check(CLI::IsMember({"corners", "centres"}));
    cmd->add_option("--sggx", a->sggx,
                    "Also write OUT.sggx.vol: SGGX matrices of fibre-like microflakes of this roughness (0 to 1] along "
                    "each voxel's fibre axis, for Mitsuba 3's sggx phase function")
        ->check(finiteRange(1e-6, 1.0));
    cmd->add_flag("-q,--quiet", a->quiet, "Print nothing on success");
    cmd->callback([a] { runInterruptible("every file of " + a->output + " is whole", [&] { runExport(*a); }); });
}

} // namespace yv
