// Throughput of the voxelizers on generated garments (or a BCC file with
// --input): slices/s and active
// voxels/s end to end; for GL also fragments/s of the raster+append pass and
// of the brick passes (GPU timer queries). Repeats each run and keeps the
// fastest; prints one JSON object per run (JSON lines) on stdout.
//
// --backend compare instead runs both once and prints their agreement (IoU of
// active voxels, mass ratio, per-voxel density difference, mean axis angle),
// the numbers the GL tests check.
//
//   yv_bench_voxelize [--backend cpu|gl|both|compare] [--pattern knit] [--shape flat]
//                     [--crossings 1000,10000] [--input FILE.bcc --yarn-radius R]
//                     [--resolution 512] [--slices-per-segment K (default: one slice per voxel)]
//                     [--cross-section fibers|disk] [--supersample 1] [--repeat 3] [--device -1]
#include "bcc.h"
#include "core/error.h"
#include "core/process_memory.h"
#include "core/stats.h"
#include "core/volume_compare.h"
#include "cpu/cpu_voxelizer.h"
#include "garment/cross_section.h"
#include "garment/generate.h"
#include "gpu/egl_context.h"
#include "gpu/gl_voxelizer.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

using namespace yv;

namespace {

struct Args {
    std::string backend = "both", pattern = "knit", shape = "flat", input, crossSection = "fibers";
    std::vector<std::uint64_t> crossings = {1000};
    int resolution = 512, slicesPerSegment = 0, supersample = 1, repeat = 3, device = -1;
    double twist = 1.0, yarnRadius = 0.0;
};

Args parse(int argc, char** argv) {
    Args a;
    for (int i = 1; i < argc; ++i) {
        const std::string k = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw Error(k + ": missing value");
            return argv[++i];
        };
        if (k == "--backend") a.backend = value();
        else if (k == "--pattern") a.pattern = value();
        else if (k == "--shape") a.shape = value();
        else if (k == "--resolution") a.resolution = std::stoi(value());
        else if (k == "--slices-per-segment") a.slicesPerSegment = std::stoi(value());
        else if (k == "--supersample") a.supersample = std::stoi(value());
        else if (k == "--repeat") a.repeat = std::stoi(value());
        else if (k == "--device") a.device = std::stoi(value());
        else if (k == "--twist") a.twist = std::stod(value());
        else if (k == "--input") a.input = value();
        else if (k == "--yarn-radius") a.yarnRadius = std::stod(value());
        else if (k == "--cross-section") a.crossSection = value();
        else if (k == "--crossings") {
            a.crossings.clear();
            std::stringstream ss(value());
            for (std::string item; std::getline(ss, item, ',');) a.crossings.push_back(std::stoull(item));
        } else throw Error("unknown option " + k + " (see the comment at the top of bench/bench_voxelize.cpp)");
    }
    return a;
}

double seconds(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

} // namespace

int main(int argc, char** argv) try {
    const Args args = parse(argc, argv);
    const CrossSection xs = makeCrossSection(args.crossSection);
    // One run per garment: the generated sizes, or the one input file.
    const std::vector<std::uint64_t> sizes = args.input.empty() ? args.crossings : std::vector<std::uint64_t>{0};
    for (std::uint64_t crossings : sizes) {
        Garment garment;
        if (args.input.empty()) {
            GenerateOptions g;
            g.pattern = parseWeavePattern(args.pattern);
            g.shape = parseGarmentShape(args.shape);
            g.crossings = crossings;
            garment = generateGarment(g);
        } else {
            garment = readBcc(args.input);
        }
        SliceOptions opt;
        opt.radius = args.yarnRadius > 0.0 ? args.yarnRadius : garment.yarnRadius;
        if (!(opt.radius > 0.0)) throw Error(args.input + ": no yarn radius in the file: pass --yarn-radius");
        opt.twist = args.twist;
        opt.slicesPerSegment = args.slicesPerSegment;
        if (args.slicesPerSegment == 0)
            opt.spacing = defaultSliceSpacing(voxelSizeFor(garment, opt.radius, args.resolution, 0.0), args.supersample);
        auto t0 = std::chrono::steady_clock::now();
        const SlicePlan plan = planSlices(garment, opt);
        const double planSeconds = seconds(t0);
        const VoxelGrid grid = makeGrid(plan, args.resolution, 0.0);

        if (args.backend == "compare") {
            VoxelizeSettings s;
            s.supersample = args.supersample;
            GlVoxelizeSettings gs;
            gs.base = s;
            GlVoxelizeCounters glc;
            const BrickVolume cpu = voxelizeCpu(plan, xs, grid, s);
            const GlContext context(GlContextOptions{args.device});
            const BrickVolume gl = voxelizeGl(plan, xs, grid, gs, context, &glc);
            const VolumeComparison c = compareVolumes(cpu, gl);
            std::printf("{ \"compare\": \"gl vs cpu\", \"renderer\": %s, \"input\": %s, \"pattern\": \"%s\", "
                        "\"shape\": \"%s\", \"crossings\": %llu, \"slices\": %llu, \"resolution\": %d, \"twist\": %g, "
                        "\"active_cpu\": %llu, \"iou\": %.6f, \"mass_ratio\": %.7f, \"density_max_diff\": %.3g, "
                        "\"density_mean_diff\": %.3g, \"density_within_1e-4\": %.6f, \"mean_angle_deg\": %.4f }\n",
                        jsonQuote(glc.renderer).c_str(), jsonQuote(args.input).c_str(), args.pattern.c_str(),
                        args.shape.c_str(), static_cast<unsigned long long>(crossings),
                        static_cast<unsigned long long>(plan.sliceCount), args.resolution, args.twist,
                        static_cast<unsigned long long>(c.both + c.onlyA), c.iou, c.massRatio, c.maxDensityDiff,
                        c.meanDensityDiff, c.densityWithinShare(), c.meanAngleDeg);
            std::fflush(stdout);
            continue;
        }
        for (const std::string backend : {"cpu", "gl"}) {
            if (args.backend != "both" && args.backend != backend) continue;
            JsonObject best;
            double bestSeconds = 1e300;
            for (int r = 0; r < args.repeat; ++r) {
                VoxelizeSettings s;
                s.supersample = args.supersample;
                JsonObject run;
                const auto start = std::chrono::steady_clock::now();
                BrickVolume v;
                GlVoxelizeCounters glc;
                CpuVoxelizeCounters cpuc;
                if (std::string(backend) == "cpu") {
                    v = voxelizeCpu(plan, xs, grid, s, &cpuc);
                } else {
                    GlVoxelizeSettings gs;
                    gs.base = s;
                    // A context of each run's own, within its time, as a run of yarnvox makes one.
                    const GlContext context(GlContextOptions{args.device});
                    v = voxelizeGl(plan, xs, grid, gs, context, &glc);
                }
                const double total = seconds(start);
                const std::uint64_t active = v.activeVoxelCount();
                run.set("backend", backend)
                    .set("pattern", args.pattern)
                    .set("shape", args.shape)
                    .set("crossings", crossings)
                    .set("slices", plan.sliceCount)
                    .set("resolution", args.resolution)
                    .set("grid", std::to_string(grid.dims.x) + "x" + std::to_string(grid.dims.y) + "x" + std::to_string(grid.dims.z))
                    .set("supersample", args.supersample)
                    .set("plan_seconds", planSeconds)
                    .set("voxelize_seconds", total)
                    .set("slices_per_second", plan.sliceCount / total)
                    .set("active_voxels", active)
                    .set("active_voxels_per_second", active / total)
                    .set("bricks", static_cast<std::uint64_t>(v.bricks.size()));
                if (std::string(backend) == "cpu") {
                    run.set("samples", cpuc.samples).set("samples_per_second", cpuc.samples / total);
                } else {
                    run.set("renderer", glc.renderer)
                        .set("fragments", glc.fragments)
                        .set("raster_passes", glc.passes)
                        .set("overflow_retries", glc.overflows)
                        .set("raster_gpu_seconds", glc.rasterSeconds)
                        .set("raster_slices_per_second", plan.sliceCount / glc.rasterSeconds)
                        .set("raster_fragments_per_second", glc.fragments / glc.rasterSeconds)
                        .set("brick_gpu_seconds", glc.brickSeconds)
                        .set("brick_fragments_per_second", glc.fragments / glc.brickSeconds)
                        .set("resolve_gpu_seconds", glc.resolveSeconds)
                        .set("readback_seconds", glc.readbackSeconds)
                        .set("readback_bytes", glc.readbackBytes)
                        .set("gpu_slice_data_bytes", glc.sliceDataBytes)
                        .set("gpu_peak_bytes", glc.peakGpuBytes);
                }
                run.set("peak_host_bytes", peakResidentBytes());
                if (total < bestSeconds) {
                    bestSeconds = total;
                    best = run;
                }
            }
            best.set("repeats", args.repeat);
            std::string line = best.dump();
            for (char& ch : line)
                if (ch == '\n') ch = ' ';
            std::printf("%s\n", line.c_str());
            std::fflush(stdout);
        }
    }
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "yv_bench_voxelize: error: %s\n", e.what());
    return 1;
}
