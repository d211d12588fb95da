// The bricks a run keeps in memory beside its .vdb (core/kept_bricks.h), as
// the live view draws them (keptBricksSource): the same bricks and the same
// values, voxel for voxel, as the .vdb read back, whether the regions were
// resolved on the host or came packed as the GPU's resolve reads them back.
#include "core/error.h"
#include "core/kept_bricks.h"
#include "gpu/egl_context.h"
#include "inspect/volume_source.h"
#include "packed_test_bricks.h"
#include "pipeline/voxelize_run.h"
#include "run_cli.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>

#include <array>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;

namespace {

/// A brick's active voxels as a source hands them over: density, and the axis where there is density.
struct SeenBrick {
    std::array<float, yv::kBrickVoxels> density{};
    std::array<glm::vec3, yv::kBrickVoxels> axis{};
};
using SeenBricks = std::map<std::uint64_t, SeenBrick>;

SeenBricks seen(const yv::VolumeSource& source, glm::ivec3 lo, glm::ivec3 hi, bool concurrent) {
    SeenBricks out;
    std::mutex mutex;
    const auto take = [&](const yv::SourceBrick& b) {
        SeenBrick s;
        for (int v = 0; v < yv::kBrickVoxels; ++v) {
            s.density[std::size_t(v)] = b.density[v];
            if (b.density[v] != 0.0f && b.orientation) s.axis[std::size_t(v)] = b.orientation[v];
        }
        const std::lock_guard lock(mutex);
        REQUIRE(out.emplace(yv::brickKey(b.coord), s).second); // each brick once
    };
    if (concurrent) source.forEachBrickConcurrently(lo, hi, take);
    else source.forEachBrick(lo, hi, take);
    return out;
}

SeenBricks seenAll(const yv::VolumeSource& source, bool concurrent = true) {
    return seen(source, glm::ivec3(-(1 << 20)), glm::ivec3(1 << 20), concurrent);
}

void checkSame(const SeenBricks& a, const SeenBricks& b) {
    REQUIRE(a.size() == b.size());
    for (const auto& [key, brick] : a) {
        INFO("brick " << key);
        const auto it = b.find(key);
        REQUIRE(it != b.end());
        for (int v = 0; v < yv::kBrickVoxels; ++v) {
            INFO("voxel " << v);
            REQUIRE(brick.density[std::size_t(v)] == it->second.density[std::size_t(v)]);
            REQUIRE(brick.axis[std::size_t(v)] == it->second.axis[std::size_t(v)]);
        }
    }
}

yv::VoxelizeJob keepingJob(const fs::path& garment, const fs::path& output, yv::BackendRequest backend) {
    yv::VoxelizeJob job;
    job.input = garment.string();
    job.output = output.string();
    job.resolution = 40;
    job.backend = backend;
    job.precision = yv::VdbPrecision::Float; // the file holds the floats the run kept
    job.fragmentCapacity = 3000;             // several regions
    job.quiet = true;
    job.keepBricks = std::make_shared<yv::KeptBricks>();
    return job;
}

fs::path smallGarment(const yv::test::ScratchDir& dir) {
    const fs::path garment = dir.path / "plain.bcc";
    REQUIRE(yv::test::runYarnvox("gen --pattern plain --crossings 16 --quiet -o " + garment.string()).exitCode == 0);
    return garment;
}

} // namespace

TEST_CASE("Kept bricks: a run's bricks kept in memory read as its .vdb reads, voxel for voxel, with or without the file "
          "(CPU and GL)",
          "[view][pipeline]") {
    const yv::test::ScratchDir dir{"yv_kept_bricks"};
    const fs::path garment = smallGarment(dir);
    for (const yv::BackendRequest backend : {yv::BackendRequest::Cpu, yv::BackendRequest::Gl}) {
        if (backend == yv::BackendRequest::Gl) {
            YV_REQUIRE_GL();
        }
        INFO("backend " << yv::toString(backend));
        const fs::path vdb = dir.path / (std::string(yv::toString(backend)) + ".vdb");
        const yv::VoxelizeJob job = keepingJob(garment, vdb, backend);
        const yv::VoxelizeReport report = yv::runVoxelize(job, [](const std::string&) {});
        REQUIRE(job.keepBricks->brickCount() == report.bricks);
        CHECK(job.keepBricks->resolvedRegions().size() + job.keepBricks->packedRegions().size() > 1);
        CHECK(job.keepBricks->bytes() > 0);

        const std::unique_ptr<yv::VolumeSource> kept = yv::keptBricksSource(job.keepBricks);
        const std::unique_ptr<yv::VolumeSource> file = yv::openVdbSource(vdb.string());
        REQUIRE(kept->occupiedBricks() == file->occupiedBricks());
        CHECK(kept->bounds().min == file->bounds().min);
        CHECK(kept->bounds().max == file->bounds().max);
        CHECK(kept->hasOrientation());
        const SeenBricks fromKept = seenAll(*kept), fromFile = seenAll(*file);
        REQUIRE(fromKept.size() == report.bricks);
        checkSame(fromKept, fromFile);
        // One brick at a time gives the same as all at once.
        checkSame(seenAll(*kept, false), fromKept);
        CHECK_THROWS_AS(kept->regionBounds(0), yv::Error);

        // The same run with no output keeps the same bricks and writes nothing.
        yv::VoxelizeJob only = keepingJob(garment, "", backend);
        REQUIRE(only.bricksOnly());
        const std::set<fs::path> before(fs::directory_iterator(dir.path), fs::directory_iterator());
        const yv::VoxelizeReport onlyReport = yv::runVoxelize(only, [](const std::string&) {});
        CHECK(std::set<fs::path>(fs::directory_iterator(dir.path), fs::directory_iterator()) == before);
        REQUIRE(only.keepBricks->brickCount() == onlyReport.bricks);
        checkSame(seenAll(*yv::keptBricksSource(only.keepBricks)), fromFile);
    }
}

TEST_CASE("Kept bricks: packed regions read as the same bricks resolved, a box gives only its bricks, and a brick "
          "kept twice is refused",
          "[view][pipeline]") {
    const yv::test::ScratchDir dir{"yv_kept_packed"};
    const fs::path garment = smallGarment(dir);
    const yv::VoxelizeJob job = keepingJob(garment, dir.path / "cpu.vdb", yv::BackendRequest::Cpu);
    yv::runVoxelize(job, [](const std::string&) {});
    const auto& regions = job.keepBricks->resolvedRegions();
    REQUIRE(regions.size() > 1);
    REQUIRE(job.keepBricks->packedRegions().empty());

    // The same regions, packed as the GPU's resolve hands them over.
    const auto packed = std::make_shared<yv::KeptBricks>();
    for (const auto& region : regions) packed->add(yv::test::packBricks(region));
    REQUIRE(packed->brickCount() == job.keepBricks->brickCount());
    const std::unique_ptr<yv::VolumeSource> fromResolved = yv::keptBricksSource(job.keepBricks);
    const std::unique_ptr<yv::VolumeSource> fromPacked = yv::keptBricksSource(packed);
    REQUIRE(fromPacked->occupiedBricks() == fromResolved->occupiedBricks());
    const SeenBricks all = seenAll(*fromResolved);
    checkSame(seenAll(*fromPacked), all);

    // A box of bricks: exactly the occupied bricks inside it.
    const yv::VoxelBox bounds = fromPacked->bounds();
    const glm::ivec3 lo = bounds.min / yv::kBrickSize + 1, hi = bounds.max / yv::kBrickSize - 1;
    SeenBricks inside;
    for (const auto& [key, brick] : all) {
        const glm::ivec3 c = yv::brickCoord(key);
        if (glm::all(glm::greaterThanEqual(c, lo)) && glm::all(glm::lessThan(c, hi))) inside.emplace(key, brick);
    }
    REQUIRE_FALSE(inside.empty());
    REQUIRE(inside.size() < all.size());
    checkSame(seen(*fromPacked, lo, hi, true), inside);
    checkSame(seen(*fromResolved, lo, hi, false), inside);

    // Regions never share a brick; one kept twice is an error, not a silent pick.
    const auto twice = std::make_shared<yv::KeptBricks>();
    twice->add(regions.front());
    twice->add(yv::test::packBricks(regions.front()));
    REQUIRE_THROWS_WITH(yv::keptBricksSource(twice), Catch::Contains("twice"));
}

TEST_CASE("Kept bricks: a run through a work directory keeps none", "[view][pipeline]") {
    const yv::test::ScratchDir dir{"yv_kept_workdir"};
    const fs::path garment = smallGarment(dir);
    yv::VoxelizeJob job = keepingJob(garment, dir.path / "w.vdb", yv::BackendRequest::Cpu);
    job.workDir = (dir.path / "w.work").string();
    yv::runVoxelize(job, [](const std::string&) {});
    CHECK(fs::exists(job.output));
    CHECK(job.keepBricks->brickCount() == 0);
}

TEST_CASE("Kept bricks: a run with no output needs somewhere to keep its bricks and no work dir", "[view][pipeline]") {
    const yv::test::ScratchDir dir{"yv_kept_only"};
    const fs::path garment = smallGarment(dir);
    // Nothing to keep them in, or a work dir to write: refused before any work.
    yv::VoxelizeJob noKeep = keepingJob(garment, "", yv::BackendRequest::Cpu);
    noKeep.keepBricks.reset();
    CHECK_THROWS_AS(yv::runVoxelize(noKeep, [](const std::string&) {}), yv::Error);
    yv::VoxelizeJob workDir = keepingJob(garment, "", yv::BackendRequest::Cpu);
    workDir.workDir = (dir.path / "only.work").string();
    CHECK_THROWS_WITH(yv::runVoxelize(workDir, [](const std::string&) {}), Catch::Contains("without a work dir"));
    CHECK_FALSE(fs::exists(workDir.workDir));
}

TEST_CASE("A GL context kept between runs gives each run the bricks a context of its own gives", "[view][pipeline][gl]") {
    YV_REQUIRE_GL();
    const yv::test::ScratchDir dir{"yv_kept_context"};
    const fs::path garment = smallGarment(dir);
    // Two different runs, one after the other, on one context (released between
    // them, as the view's voxelizer leaves it for a pass on another thread).
    const auto kept = std::make_shared<yv::GlContext>(yv::GlContextOptions{});
    kept->releaseCurrent(); // made here, driven on the runs' threads
    std::vector<yv::VoxelizeJob> onKept;
    for (const int resolution : {40, 36, 40}) {
        yv::VoxelizeJob job = keepingJob(garment, "", yv::BackendRequest::Gl);
        job.resolution = resolution;
        job.glContext = kept;
        std::string failed;
        std::thread([&] {
            try {
                yv::runVoxelize(job, [](const std::string&) {});
            } catch (const std::exception& e) {
                failed = e.what();
            }
            kept->releaseCurrent();
        }).join();
        INFO(failed);
        REQUIRE(failed.empty());
        onKept.push_back(job);
    }
    for (const yv::VoxelizeJob& job : onKept) {
        INFO("resolution " << job.resolution);
        yv::VoxelizeJob own = job;
        own.glContext.reset();
        own.keepBricks = std::make_shared<yv::KeptBricks>();
        yv::runVoxelize(own, [](const std::string&) {});
        REQUIRE(job.keepBricks->brickCount() > 0);
        checkSame(seenAll(*yv::keptBricksSource(job.keepBricks)), seenAll(*yv::keptBricksSource(own.keepBricks)));
    }
}
