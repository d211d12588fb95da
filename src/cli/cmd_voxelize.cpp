// `yarnvox voxelize`: the options, parsed once into a typed VoxelizeJob for
// the pipeline (src/pipeline/voxelize_run.h), and the summary it prints.
#include "cli/commands.h"
#include "cli/garment_list.h"
#include "cli/interruptible.h"
#include "cli/option_checks.h"
#include "cli/option_words.h"
#include "cli/output_format.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/voxelize_settings.h"
#include "core/world_units.h"
#include "pipeline/cluster.h"
#include "pipeline/voxelize_run.h"
#include "plan/box_request.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numeric>
#include <optional>

namespace yv {
namespace {

void voxelizeAndReport(const VoxelizeJob& request) {
    const VoxelizeReport r = runVoxelize(request, [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); });
    if (request.quiet || r.rankOnly) return;
    std::printf("%s: %llu slices -> %llu active voxels in %llu bricks (grid %dx%dx%d, voxel %.4g), %.2f s voxelize\n"
                "wrote %s\n",
                request.input.c_str(), static_cast<unsigned long long>(r.slices),
                static_cast<unsigned long long>(r.activeVoxels), static_cast<unsigned long long>(r.bricks), r.dims.x,
                r.dims.y, r.dims.z, r.voxelSize, r.voxelizeSeconds, request.output.c_str());
    // Interpenetrating yarns: say how much fibre the overlap rule met, when more than a trace.
    if (r.tallyComplete && r.reduce == Reduce::Mean && r.tally.excessShare() > 1e-3)
        std::printf("overlap: %llu voxels held more than their volume of fibre (%.2f %% of the fibre volume above 1); %s\n",
                    static_cast<unsigned long long>(r.tally.voxelsOverOne), 100.0 * r.tally.excessShare(),
                    r.overlap == Overlap::Clamp ? "clamped to 1 (--overlap sum keeps the sums)"
                                                : "kept as sums (--overlap sum)");
}

/// --progress-lines: every stage's progress as lines on stderr while the
/// command runs, terminal or not ("progress: voxelize 3/10 regions"), for a
/// program that runs yarnvox and shows its progress (the Python module, the
/// Blender add-on); an observer already installed still hears it.
class ProgressLines {
  public:
    explicit ProgressLines(bool on) {
        if (!on) return;
        active_ = true;
        previous_ = setProgressObserver({});
        setProgressObserver([previous = previous_](const std::string& stage, const std::string& unit,
                                                   std::uint64_t done, std::uint64_t total) {
            std::fprintf(stderr, "progress: %s %llu/%llu %s\n", stage.c_str(), static_cast<unsigned long long>(done),
                         static_cast<unsigned long long>(total), unit.c_str());
            std::fflush(stderr);
            if (previous) previous(stage, unit, done, total);
        });
    }
    ~ProgressLines() {
        if (active_) setProgressObserver(previous_);
    }
    ProgressLines(const ProgressLines&) = delete;
    ProgressLines& operator=(const ProgressLines&) = delete;

  private:
    bool active_ = false;
    ProgressObserver previous_;
};

/// The grid, the slices and the cross-section.
void addGeometryOptions(CLI::App* cmd, VoxelizeJob& a) {
    auto* res = cmd->add_option("--resolution", a.resolution, "Voxels on the longest axis of the padded garment box")
                    ->check(wholeNumber(8, 1 << 20));
    cmd->add_option("--voxel-size", a.voxelSize, "Voxel edge length, world units (instead of --resolution)")
        ->check(worldLength())
        ->excludes(res);
    cmd->add_option("--yarn-radius", a.yarnRadius, "Yarn radius, world units (default: from the cross-section PNG or the garment file, else "
                    "estimated from the distances between touching yarns)")
        ->check(worldLength());
    auto* perSegment =
        cmd->add_option("--slices-per-segment", a.slicesPerSegment,
                        "Slices per curve segment (the paper uses 25 and 50; default: one slice per voxel along the yarn)")
            ->check(wholeNumber(1, 100000));
    cmd->add_option("--slice-spacing", a.spacing,
                    "Distance between slices, world units (default: the voxel size over --supersample)")
        ->check(worldLength())
        ->excludes(perSegment);
    cmd->add_option("--twist", a.twist, "Yarn twist, radians per world unit of yarn length")
        ->capture_default_str()
        ->check(finiteNumber(kMaxTwist));
    cmd->add_option("--cross-section", a.crossSection, "Fibre density on each slice: fibers, disk, or FILE.png (alpha = density)")
        ->capture_default_str();
    auto* bbox = cmd->add_option_function<std::string>(
        "--bbox", [&a](const std::string& text) { a.box = parseBoxRequest(false, text); },
        "Voxelize only this box, i0,j0,k0,i1,j1,k1 in voxel indices (max exclusive) of the grid that "
        "--resolution or --voxel-size fixes over the whole garment: its voxels are the whole run's, nothing "
        "outside it is written, and only the slices that can reach it are drawn. Clipped to the grid");
    cmd->add_option_function<std::string>(
           "--bbox-world", [&a](const std::string& text) { a.box = parseBoxRequest(true, text); },
           "As --bbox, in the garment's world units x0,y0,z0,x1,y1,z1: every voxel whose cell overlaps the box")
        ->excludes(bbox);
    cmd->add_flag("--albedo", a.albedo,
                  "Also write the fibres' colour: an 'albedo' grid (linear RGB) from the RGB of the --cross-section PNG "
                  "(read as sRGB), the density-weighted mean of each voxel's samples. Needs a colour PNG and the mean "
                  "reduction (either backend); not with --method dense. With a pyramid (--lod), albedo_lodL too "
                  "(mass-weighted)");
}

/// What the voxels hold and how the .vdb stores them.
void addVolumeOptions(CLI::App* cmd, VoxelizeJob& a) {
    cmd->add_option("--reduce", a.reduce, "mean: fibre volume fraction and mean axis; max: the paper's max density")
        ->default_str("mean")
        ->transform(oneOf(kReduceWords));
    cmd->add_option("--overlap", a.overlap,
                    "Where yarns interpenetrate (mean): clamp keeps every voxel's fibre fraction at or below 1; "
                    "sum adds them up")
        ->default_str("clamp")
        ->transform(oneOf(kOverlapWords));
    cmd->add_option("--vdb-compression", a.compression,
                    "How the .vdb's leaves are compressed: mask (active values only, no codec: the fastest), "
                    "blosc (OpenVDB's default: smaller, slower), zip (the orientation grid only) or none")
        ->default_str("mask")
        ->transform(oneOf(kCompressionWords));
    cmd->add_option("--precision", a.precision,
                    "How the .vdb's values are stored: half (16-bit: about half the bytes of float; density within "
                    "2^-11 relative, and renders that match float's within the sampling noise) or float. A .vol or "
                    ".nvdb output is converted from a float .vdb unless --precision is given")
        ->default_str(toString(kDefaultVdbPrecision))
        ->transform(oneOf(kPrecisionWords));
    cmd->add_option_function<std::string>(
           "--lod", [&a](const std::string& text) { a.lod = parseLodRequest(text); },
           "Level-of-detail grids density_lodL and orientation_lodL (and albedo_lodL with --albedo), level L at "
           "2^-L of the resolution (mean density, structure-tensor axis): preview (levels 3 to the coarsest, whose "
           "voxel is one 8^3 brick: a small pyramid made as the bricks are written; none on a grid under 64 voxels, "
           "with --method dense, or for a .vol or .nvdb output), 0 (none) or N (every level 1..N)")
        ->default_str("preview")
        ->check(lodWords());
}

/// Sampling, the GPU, the work dir and what the run prints.
void addRunOptions(CLI::App* cmd, VoxelizeJob& a) {
    cmd->add_option("--supersample", a.supersample, "Samples per voxel face along each axis")
        ->capture_default_str()
        ->check(wholeNumber(1, kMaxSupersample));
    cmd->add_option("--device", a.device, "GL backend: EGL device index (default: first GPU, else llvmpipe)")
        ->check(wholeNumber(0, 1023));
    // The GL append counter is 32 bits, and a pass that reaches 2^31 counts as overflowed.
    cmd->add_option("--fragment-budget", a.fragmentCapacity,
                    "Fragments (samples) one zoom region may produce (default: from GPU limits and free memory; "
                    "for the CPU backend from host memory, and at most what a quarter of it holds); zoom regions "
                    "are sized to it")
        ->check(wholeNumber<std::uint64_t>(1, 0x7fffffffu));
    cmd->add_option("--work-dir", a.workDir,
                    "Directory for the per-region brick files (default: OUT.vdb.work, removed after the merge)");
    cmd->add_flag("--resume", a.resume, "Re-use the complete, verified regions in --work-dir (needed) and compute the rest");
    cmd->add_flag("--keep-work-dir", a.keepWorkDir, "Keep the default work directory after the merge");
    cmd->add_option("--stats", a.statsPath, "Write run statistics (JSON) to this file");
    cmd->add_flag("-q,--quiet", a.quiet, "No progress and no summary");
    cmd->add_flag("-v,--verbose", a.verbose, "Name the renderer and print GPU limits");
}

/// The garments asked for: INPUT files then those --list names.
std::vector<std::string> garmentsAsked(const std::vector<std::string>& inputs, const std::string& list) {
    std::vector<std::string> garments = inputs;
    if (!list.empty())
        for (const std::string& path : readGarmentList(list)) garments.push_back(path);
    if (garments.empty()) throw Error("give a garment file (INPUT) or --list FILE");
    return garments;
}

/// At least as many garments as ranks: whole garments go to whichever rank
/// asks next, largest file first, each voxelized by its rank alone (as one
/// process would, so the same file).
template <class VoxelizeOne>
void handOutWholeGarments(Cluster& group, const std::vector<GarmentJob>& jobs, bool quiet, VoxelizeOne&& voxelizeOne) {
    std::vector<std::size_t> order(jobs.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
        return std::filesystem::file_size(jobs[x].input) > std::filesystem::file_size(jobs[y].input);
    });
    group.beginHandout(jobs.size());
    double done = 0.0;
    while (const std::optional<std::uint64_t> item = group.claim()) {
        const GarmentJob& job = jobs[order[*item]];
        if (!quiet)
            std::printf("rank %d: %s, whole (%zu garments over %d ranks)\n", group.rank(), job.input.c_str(),
                        jobs.size(), group.size());
        voxelizeOne(job, true);
        done += 1.0;
    }
    group.endHandout({done});
}

/// Voxelizes each garment asked for into its output, in its format.
/// `precisionGiven`: --precision was on the command line.
void voxelizeGarments(const VoxelizeJob& a, const std::string& format, const std::vector<std::string>& inputs,
                      const std::string& list, bool precisionGiven) {
    const std::vector<std::string> garments = garmentsAsked(inputs, list);
    std::vector<GarmentJob> jobs;
    if (garments.size() == 1 && list.empty()) {
        jobs.push_back({garments[0], a.output, a.workDir, a.statsPath});
    } else {
        const OutputFormat f = resolveOutputFormat(format, "", true);
        const char* extension = f == OutputFormat::Vol ? ".vol" : f == OutputFormat::Nvdb ? ".nvdb" : ".vdb";
        jobs = planGarmentJobs(garments, a.output, extension, a.workDir, a.statsPath);
    }
    Cluster* const group = cluster() && cluster()->size() > 1 ? cluster() : nullptr;
    const auto voxelizeOne = [&](const GarmentJob& job, bool alone) {
        const bool vdbOutput = resolveOutputFormat(format, job.output, true) == OutputFormat::Vdb;
        voxelizeInFormat(format, job.output, job.input, a.quiet, [&](const std::string& vdbPath) {
            VoxelizeJob run = a;
            // A .vdb converted to .vol or .nvdb and removed: the conversion reads level 0 only,
            // and writes float32 (halves would only round the values it converts).
            if (!vdbOutput && run.lod.kind == LodRequest::Kind::Preview) run.lod = LodRequest::none();
            if (!vdbOutput && !precisionGiven) run.precision = VdbPrecision::Float;
            run.input = job.input;
            run.output = vdbPath;
            run.workDir = job.workDir;
            run.statsPath = job.statsPath;
            run.alone = alone;
            voxelizeAndReport(run);
        });
    };
    if (group && jobs.size() >= std::size_t(group->size())) return handOutWholeGarments(*group, jobs, a.quiet, voxelizeOne);
    for (const GarmentJob& job : jobs) {
        if (group && resolveOutputFormat(format, job.output, true) != OutputFormat::Vdb)
            throw Error("-o " + job.output + ": under mpirun the output is a .vdb; convert it afterwards with `yarnvox export`");
        // Fewer garments than ranks: one after another, all ranks sharing each one's regions.
        voxelizeOne(job, false);
    }
}

} // namespace

void addVoxelizeCommand(CLI::App& app) {
    auto a = std::make_shared<VoxelizeJob>();
    auto progressLines = std::make_shared<bool>(false);
    auto format = std::make_shared<std::string>();
    auto inputs = std::make_shared<std::vector<std::string>>();
    auto list = std::make_shared<std::string>();
    CLI::App* cmd = app.add_subcommand("voxelize", "Voxelize a garment (BCC) into an OpenVDB file of fibre density and orientation");
    cmd->add_option("input", *inputs,
                    "Garment .bcc file; several (the frames of an animation) are voxelized one after another, "
                    "one output each")
        ->check(CLI::ExistingFile);
    cmd->add_option("--list", *list,
                    "File naming garments, one path per line (relative to the file's folder; blank lines and "
                    "lines starting with # skipped), voxelized after those on the command line")
        ->check(CLI::ExistingFile);
    cmd->add_option("-o,--output", a->output,
                    "Output file: OUT.vdb, OUT.vol or OUT.nvdb (see --format). With several garments (or --list) "
                    "a directory (made when missing): DIR/STEM.vdb for each INPUT named STEM.bcc, and --work-dir "
                    "DIR/STEM, --stats DIR/STEM.json likewise")
        ->required();
    cmd->add_option("--format", *format,
                    "vdb, vol (Mitsuba: OUT.vol density, OUT.orientation.vol axes, float32) or nvdb (NanoVDB); default "
                    "from the output's extension, else vdb. vol and nvdb are converted from a temporary .vdb "
                    "(`yarnvox export` converts one you have, with more choices)")
        ->check(CLI::IsMember({"vdb", "vol", "nvdb"}));
    cmd->add_option("--backend", a->backend,
                    "auto (gl on a GPU and for --method dense, else cpu), gl (OpenGL 4.5 through EGL: a GPU, or "
                    "Mesa's llvmpipe) or cpu (the TBB reference; out of core like gl)")
        ->default_str("auto")
        ->transform(oneOf(kBackendWords));
    cmd->add_option("--method", a->method,
                    "sparse: fragment list, bricks, zoom regions; dense: the paper's dense 3D textures "
                    "(a benchmark baseline, limited to one texture, max reduction)")
        ->default_str("sparse")
        ->transform(oneOf(kMethodWords));
    cmd->add_option("--sample-items", a->sampleItems,
                    "GL backend: how the pixels each slice can put fibre in are found: raster (the slices drawn as "
                    "point sprites or triangles, the fragment shader appending them) or compute (a compute pass "
                    "testing each slice's pixels, on every unit of the GPU); auto: compute, the faster on GPUs and on "
                    "llvmpipe. The same voxels either way")
        ->default_str("auto")
        ->transform(oneOf(kSampleItemsWords));
    addGeometryOptions(cmd, *a);
    addVolumeOptions(cmd, *a);
    addRunOptions(cmd, *a);
    cmd->add_flag("--progress-lines", *progressLines,
                  "Progress as lines on stderr, terminal or not (\"progress: STAGE DONE/TOTAL UNIT\"), for programs "
                  "that run yarnvox (none with --quiet)");
    cmd->footer(clusterSupport()
                    ? "MPI: `mpirun -np N yarnvox voxelize ...` shares the zoom regions of one run among N processes "
                      "(each on its own GPU, by local rank, unless --device is given) through one work dir on a "
                      "file system they all see (--work-dir, default OUT.vdb.work); rank 0 merges. See README, "
                      "\"Scale-out with MPI\"."
                    : "");
    cmd->callback([cmd, a, format, inputs, list, progressLines] {
        const ProgressLines lines(*progressLines);
        const bool precisionGiven = cmd->get_option("--precision")->count() > 0;
        runInterruptible("every output is whole",
                         [&] { voxelizeGarments(*a, *format, *inputs, *list, precisionGiven); });
    });
}

} // namespace yv
