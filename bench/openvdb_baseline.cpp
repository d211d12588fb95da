// The baseline a user already has: OpenVDB's own tools on the CPU, on the same
// garment and the same grid as `yarnvox voxelize`. Spheres of the yarn radius
// every half voxel along each yarn's curve (tools::ParticlesToLevelSet), then
// tools::sdfToFogVolume for a density fog volume; with --orientation also a
// vec3 grid of the curve tangent, transferred from the nearest sphere by
// ParticlesToLevelSet's attribute transfer, so that the output holds what
// yarnvox's does. Written with openvdb::io::File (its default compression).
// Prints one JSON object with the time of each stage.
//
//   yv_openvdb_baseline (--input FILE.bcc --yarn-radius R | --pattern P --shape S --crossings N)
//                       --resolution N [--orientation] -o OUT.vdb
#include "bcc.h"
#include "core/error.h"
#include "core/process_memory.h"
#include "garment/catmull_rom.h"
#include "garment/generate.h"
#include "garment/slices.h"
#include "plan/grid.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetUtil.h>
#include <openvdb/tools/ParticlesToLevelSet.h>
#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

using namespace yv;

namespace {

/// Sphere centres and curve tangents, in the interface ParticlesToLevelSet reads.
struct CurveParticles {
    using PosType = openvdb::Vec3R; // for OpenVDB's point partitioner

    std::vector<openvdb::Vec3R> position;
    std::vector<openvdb::Vec3s> tangent;
    double radius = 0.0;

    std::size_t size() const { return position.size(); }
    void getPos(std::size_t n, openvdb::Vec3R& xyz) const { xyz = position[n]; }
    void getPosRad(std::size_t n, openvdb::Vec3R& xyz, openvdb::Real& r) const {
        xyz = position[n];
        r = radius;
    }
    void getAtt(std::size_t n, openvdb::Vec3s& att) const { att = tangent[n]; }
};

double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

} // namespace

int main(int argc, char** argv) try {
    std::string input, output, pattern = "twill", shape = "cylinder";
    std::uint64_t crossings = 0;
    double radius = 0.0;
    int resolution = 0;
    bool orientation = false;
    for (int i = 1; i < argc; ++i) {
        const std::string k = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw Error(k + ": missing value");
            return argv[++i];
        };
        if (k == "--input") input = value();
        else if (k == "--yarn-radius") radius = std::stod(value());
        else if (k == "--pattern") pattern = value();
        else if (k == "--shape") shape = value();
        else if (k == "--crossings") crossings = std::stoull(value());
        else if (k == "--resolution") resolution = std::stoi(value());
        else if (k == "--orientation") orientation = true;
        else if (k == "-o") output = value();
        else throw Error("unknown option " + k + " (see the comment at the top of bench/openvdb_baseline.cpp)");
    }
    if (output.empty() || resolution <= 0 || (input.empty() == (crossings == 0)))
        throw Error("give -o OUT.vdb, --resolution N and one of --input FILE.bcc or --crossings N");

    const auto start = std::chrono::steady_clock::now();
    auto t = start;
    Garment garment;
    if (!input.empty()) {
        garment = readBcc(input);
    } else {
        GenerateOptions g;
        g.pattern = parseWeavePattern(pattern);
        g.shape = parseGarmentShape(shape);
        g.crossings = crossings;
        garment = generateGarment(g);
    }
    if (radius <= 0.0) radius = garment.yarnRadius;
    if (!(radius > 0.0)) throw Error("no yarn radius: pass --yarn-radius");
    const double readSeconds = secondsSince(t);

    // The grid yarnvox would use, so both outputs share voxels and transform.
    t = std::chrono::steady_clock::now();
    const double h = voxelSizeFor(garment, radius, resolution, 0.0);
    SliceOptions opt;
    opt.radius = radius;
    opt.spacing = h / 2.0; // one sphere every half voxel
    const SlicePlan plan = planSlices(garment, opt);
    const VoxelGrid grid = makeGrid(plan, resolution, 0.0);
    CurveParticles particles;
    particles.radius = radius;
    particles.position.resize(plan.sliceCount);
    particles.tangent.resize(plan.sliceCount);
    tbb::parallel_for(std::size_t(0), plan.segments.size(), [&](std::size_t s) {
        const SegmentRecord& seg = plan.segments[s];
        for (std::uint32_t k = 0; k < seg.sliceCount; ++k) {
            const double u = (k + 0.5) / seg.sliceCount;
            const glm::dvec3 p = evalCatmullRom(seg.points, u);
            const glm::dvec3 d = glm::normalize(evalCatmullRomDerivative(seg.points, u));
            particles.position[seg.firstSlice + k] = openvdb::Vec3R(p.x, p.y, p.z);
            particles.tangent[seg.firstSlice + k] = openvdb::Vec3s(float(d.x), float(d.y), float(d.z));
        }
    });
    const double particleSeconds = secondsSince(t);

    openvdb::initialize();
    auto transform = openvdb::math::Transform::createLinearTransform(h);
    const glm::dvec3 c = grid.origin + 0.5 * h;
    transform->postTranslate(openvdb::Vec3d(c.x, c.y, c.z));
    auto sdf = openvdb::FloatGrid::create(float(openvdb::LEVEL_SET_HALF_WIDTH * h));
    sdf->setGridClass(openvdb::GRID_LEVEL_SET);
    sdf->setTransform(transform);

    t = std::chrono::steady_clock::now();
    openvdb::Vec3SGrid::Ptr tangents;
    if (orientation) {
        openvdb::tools::ParticlesToLevelSet<openvdb::FloatGrid, openvdb::Vec3s> raster(*sdf);
        raster.setRmin(0.5);
        raster.rasterizeSpheres(particles);
        raster.finalize();
        tangents = raster.attributeGrid();
    } else {
        openvdb::tools::ParticlesToLevelSet<openvdb::FloatGrid> raster(*sdf);
        raster.setRmin(0.5);
        raster.rasterizeSpheres(particles);
        raster.finalize();
    }
    const double rasterSeconds = secondsSince(t);

    t = std::chrono::steady_clock::now();
    openvdb::tools::sdfToFogVolume(*sdf);
    sdf->setName("density");
    openvdb::GridPtrVec grids{sdf};
    if (tangents) {
        tangents->setName("orientation");
        tangents->setTransform(transform);
        tangents->setVectorType(openvdb::VEC_INVARIANT);
        grids.push_back(tangents);
    }
    const double fogSeconds = secondsSince(t);

    t = std::chrono::steady_clock::now();
    openvdb::io::File(output).write(grids);
    const double writeSeconds = secondsSince(t);
    const double total = secondsSince(start);

    double mass = 0.0;
    for (auto it = sdf->cbeginValueOn(); it; ++it) mass += *it;
    std::printf("{ \"baseline\": \"openvdb ParticlesToLevelSet + sdfToFogVolume\", \"input\": \"%s\", \"crossings\": %llu, "
                "\"resolution\": %d, \"voxel_size\": %.9g, \"orientation\": %s, \"particles\": %zu, "
                "\"active_voxels\": %llu, \"mass\": %.9g, \"file_bytes\": %llu, \"peak_host_bytes\": %llu, "
                "\"seconds\": { \"read\": %.4f, \"particles\": %.4f, \"rasterize\": %.4f, \"fog\": %.4f, "
                "\"write\": %.4f, \"total\": %.4f } }\n",
                input.c_str(), static_cast<unsigned long long>(crossings), resolution, h, orientation ? "true" : "false",
                particles.size(), static_cast<unsigned long long>(sdf->activeVoxelCount()), mass * h * h * h,
                static_cast<unsigned long long>(std::filesystem::file_size(output)),
                static_cast<unsigned long long>(peakResidentBytes()), readSeconds, particleSeconds, rasterSeconds,
                fogSeconds, writeSeconds, total);
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "yv_openvdb_baseline: error: %s\n", e.what());
    return 1;
}
