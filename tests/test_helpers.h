// Garments and comparisons shared by the tests.
#pragma once

#include "core/bricks.h"
#include "core/volume_compare.h"
#include "garment/garment.h"
#include "garment/generate.h"
#include "garment/slices.h"
#include "plan/grid.h"
#include "gpu/egl_context.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <unordered_map>

#include <unistd.h>

/// GL tests fail where no GL 4.5 context can be had: the README's test
/// command expects one (Mesa's llvmpipe where there is no GPU). They are
/// skipped, with a warning, only when asked for with YV_GL_TESTS=skip.
#define YV_REQUIRE_GL()                                                                                      \
    if (!::yv::GlContext::available()) {                                                                     \
        const char* mode = std::getenv("YV_GL_TESTS");                                                       \
        if (mode && std::string(mode) == "skip") {                                                           \
            WARN("no OpenGL 4.5 context on this machine: GL backend test skipped (YV_GL_TESTS=skip)");       \
            return;                                                                                          \
        }                                                                                                    \
        FAIL("no OpenGL 4.5 context on this machine (set YV_GL_TESTS=skip to skip GL tests on purpose)");   \
    }

namespace yv::test {

/// A folder of this test process's own under the temporary directory, named
/// `prefix` and the process id, removed when the process ends: CTest runs
/// test cases as parallel processes, and other checkouts' test runs may share
/// the machine, so a fixed name would let them overwrite each other's files.
/// A fresh folder under the temporary directory, unique to this object
/// (prefix, process id, a random number), removed with it.
struct ScratchDir {
    std::filesystem::path path;
    explicit ScratchDir(const std::string& prefix)
        : path(std::filesystem::temp_directory_path() /
               (prefix + "_" + std::to_string(::getpid()) + "_" + std::to_string(std::random_device{}()))) {
        std::filesystem::create_directories(path);
    }
    ~ScratchDir() {
        std::error_code ignored;
        std::filesystem::remove_all(path, ignored);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
};

inline std::filesystem::path processScratchDir(const std::string& prefix) {
    struct Owned {
        std::filesystem::path path;
        ~Owned() {
            std::error_code ignored;
            std::filesystem::remove_all(path, ignored);
        }
    };
    static std::map<std::string, Owned> dirs;
    Owned& dir = dirs[prefix];
    if (dir.path.empty()) {
        dir.path = std::filesystem::temp_directory_path() / (prefix + "_" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir.path);
    }
    return dir.path;
}

/// A generated garment's slices at the default spacing for `resolution`, and its grid.
struct GeneratedRun {
    double radius = 0.0;
    SlicePlan plan;
    VoxelGrid grid;
};

inline GeneratedRun generatedRun(WeavePattern pattern, GarmentShape shape, int crossings, double twist, int resolution) {
    GenerateOptions g;
    g.pattern = pattern;
    g.shape = shape;
    g.crossings = crossings;
    const Garment garment = generateGarment(g);
    SliceOptions opt;
    opt.radius = garment.yarnRadius;
    opt.twist = twist;
    opt.spacing = defaultSliceSpacing(voxelSizeFor(garment, opt.radius, resolution, 0.0), 1);
    GeneratedRun run;
    run.radius = opt.radius;
    run.plan = planSlices(garment, opt);
    run.grid = makeGrid(run.plan, resolution, 0.0);
    return run;
}

/// A straight yarn from `start` along unit `direction`, one control point per
/// unit of length: a uniform Catmull-Rom through collinear, evenly spaced
/// points is the straight segment itself.
inline Garment straightYarn(glm::dvec3 start, glm::dvec3 direction, int length) {
    Garment g;
    Yarn y;
    for (int i = 0; i <= length; ++i) y.points.push_back(start + double(i) * glm::normalize(direction));
    g.yarns.push_back(y);
    return g;
}

/// Ten straight yarns through one point, each segment one brick long at a
/// voxel size of 0.125: with the GL backend's smallest list, the bricks at
/// the crossing take fragments from so many segments that they are drawn in
/// halves (segments split) and added up on the host.
inline Garment yarnsThroughOnePoint() {
    Garment garment;
    for (int i = 0; i < 10; ++i) {
        const double a = 0.45 * i, b = 0.9 * i;
        const glm::dvec3 dir(std::cos(a) * std::cos(b), std::sin(a) * std::cos(b), std::sin(b));
        garment.yarns.push_back(straightYarn(-2.0 * dir, dir, 4).yarns[0]);
    }
    return garment;
}

/// yarnsThroughOnePoint sliced (radius 0.6, 8 slices a segment, `twist`) on
/// voxels of 0.125.
struct CrossingRun {
    SlicePlan plan;
    VoxelGrid grid;
};
inline CrossingRun crossingRun(double twist = 0.0) {
    SliceOptions opt;
    opt.radius = 0.6;
    opt.slicesPerSegment = 8;
    opt.twist = twist;
    CrossingRun run;
    run.plan = planSlices(yarnsThroughOnePoint(), opt);
    run.grid = makeGrid(run.plan, 0, 0.125);
    return run;
}

/// The smallest fragment budget the GL backend accepts for `plan` whatever
/// the slab depth: one segment's slices over 64 pixels of a brick face, 8
/// voxels deep.
inline std::uint64_t smallestFragmentBudget(const SlicePlan& plan) {
    std::uint32_t maxSlices = 0;
    for (const SegmentRecord& seg : plan.segments) maxSlices = std::max(maxSlices, seg.sliceCount);
    return std::uint64_t(maxSlices) * 64 * 8;
}

/// Voxel lookup over a BrickVolume by global voxel coordinate.
class VolumeIndex {
  public:
    explicit VolumeIndex(const BrickVolume& v) : volume_(v) {
        for (std::size_t i = 0; i < v.bricks.size(); ++i) slot_[v.bricks[i].key] = i;
    }
    const VoxelBrick* brick(glm::ivec3 voxel) const {
        auto it = slot_.find(brickKey(voxel >> 3));
        return it == slot_.end() ? nullptr : &volume_.bricks[it->second];
    }
    float density(glm::ivec3 voxel) const {
        const VoxelBrick* b = brick(voxel);
        return b ? b->density[brickOffset(voxel.x & 7, voxel.y & 7, voxel.z & 7)] : 0.0f;
    }

  private:
    const BrickVolume& volume_;
    std::unordered_map<std::uint64_t, std::size_t> slot_;
};

using yv::compareVolumes;
using yv::VolumeComparison;

} // namespace yv::test
