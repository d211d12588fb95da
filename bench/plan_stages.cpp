// The host's planning of a voxelization, alone: the garment's slices
// (planSlices) and the zoom regions (planZoomRegions), as `yarnvox voxelize`
// plans them, timed round after round without the GPU's passes or the write
// after them. What the 41 M-slice configuration spends before its first
// pass, measurable on any machine.
//
//   yv_bench_plan_stages --input G.bcc --yarn-radius R --resolution N
//                        [--slices-per-segment K (default: one slice per voxel)]
//                        [--fragment-budget F (default 2^27)] [--pipeline-regions P (default 32)]
//                        [--rounds 5]
//
// One JSON object a round on stdout: the seconds of each stage, the plan's
// slices, segments, regions and the segments they hold, and the whole
// garment's expected fragments (what two builds must agree on to have
// planned alike).
#include "bcc.h"
#include "core/error.h"
#include "garment/cross_section.h"
#include "garment/slices.h"
#include "plan/grid.h"
#include "plan/zoom_plan.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

using namespace yv;

namespace {

struct Args {
    std::string input;
    double yarnRadius = 0.0;
    int resolution = 0, slicesPerSegment = 0, rounds = 5;
    std::uint64_t fragmentBudget = std::uint64_t(1) << 27;
    double pipelineRegions = kPipelineRegions;
};

Args parse(int argc, char** argv) {
    Args a;
    for (int i = 1; i < argc; ++i) {
        const std::string k = argv[i];
        if (i + 1 >= argc) throw Error(k + ": missing value");
        const std::string v = argv[++i];
        if (k == "--input") a.input = v;
        else if (k == "--yarn-radius") a.yarnRadius = std::stod(v);
        else if (k == "--resolution") a.resolution = std::stoi(v);
        else if (k == "--slices-per-segment") a.slicesPerSegment = std::stoi(v);
        else if (k == "--fragment-budget") a.fragmentBudget = std::stoull(v);
        else if (k == "--pipeline-regions") a.pipelineRegions = std::stod(v);
        else if (k == "--rounds") a.rounds = std::stoi(v);
        else throw Error("unknown option " + k);
    }
    if (a.input.empty() || !(a.yarnRadius > 0.0) || a.resolution <= 0 || a.rounds <= 0)
        throw Error("give --input, --yarn-radius and --resolution (and --rounds above 0)");
    return a;
}

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

int main(int argc, char** argv) try {
    const Args args = parse(argc, argv);
    const Garment garment = readBcc(args.input);
    const CrossSection xs = makeFiberCrossSection();
    for (int round = 1; round <= args.rounds; ++round) {
        // As sliceGarment: the curves' bounds once, the voxel size from them,
        // one slice per voxel unless a count is given.
        auto start = std::chrono::steady_clock::now();
        glm::dvec3 curveMin, curveMax;
        curveBounds(garment, curveMin, curveMax);
        const double voxelSize = voxelSizeForCurves(curveMin, curveMax, args.yarnRadius, args.resolution, 0.0);
        SliceOptions options;
        options.radius = args.yarnRadius;
        options.slicesPerSegment = args.slicesPerSegment;
        options.spacing = args.slicesPerSegment > 0 ? 0.0 : defaultSliceSpacing(voxelSize, 1);
        const SlicePlan plan = planSlices(garment, options, curveMin, curveMax);
        const double slicesSeconds = secondsSince(start);

        start = std::chrono::steady_clock::now();
        const VoxelGrid grid = makeGrid(plan, args.resolution, 0.0);
        const ZoomPlan zoom = planZoomRegions(plan, grid, xs, {args.fragmentBudget, 1024, 1, nullptr, args.pipelineRegions});
        const double zoomSeconds = secondsSince(start);

        std::uint64_t regionSegments = 0;
        for (const ZoomRegion& r : zoom.regions) regionSegments += r.segments.size();
        std::printf("{\"round\": %d, \"slices_seconds\": %.4f, \"zoom_seconds\": %.4f, \"slices\": %llu, "
                    "\"segments\": %zu, \"regions\": %zu, \"region_segments\": %llu, \"estimated_fragments\": %.6g}\n",
                    round, slicesSeconds, zoomSeconds, static_cast<unsigned long long>(plan.sliceCount),
                    plan.segments.size(), zoom.regions.size(), static_cast<unsigned long long>(regionSegments),
                    zoom.estimatedFragments);
        std::fflush(stdout);
    }
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "yv_bench_plan_stages: %s\n", e.what());
    return 1;
}
