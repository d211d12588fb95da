// A run given up: VoxelizeJob::cancel stops a run at a zoom region boundary
// (or before its first) with RunCancelled and nothing written; the live
// view's voxelizer gives up the pass under way when a newer view is asked
// for, says "dropped", and runs the newer one.
#include "bcc.h"
#include "core/error.h"
#include "garment/slices.h"
#include "pipeline/voxelize_run.h"
#include "run_cli.h"
#include "test_helpers.h"
#include "view/view_voxelizer.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

/// A small generated garment and its world bounds, as --bbox-world text.
struct TestGarment {
    fs::path bcc;
    glm::dvec3 min{0.0}, max{0.0};
    explicit TestGarment(const fs::path& dir) : bcc(dir / "plain.bcc") {
        REQUIRE(yv::test::runYarnvox("gen --pattern plain --crossings 16 --quiet -o " + bcc.string()).exitCode == 0);
        yv::curveBounds(yv::readBcc(bcc.string()), min, max);
    }
    /// The garment's box grown by `margin` on every side.
    std::string boxText(double margin) const {
        char text[256];
        std::snprintf(text, sizeof text, "%.6g,%.6g,%.6g,%.6g,%.6g,%.6g", min.x - margin, min.y - margin, min.z - margin,
                      max.x + margin, max.y + margin, max.z + margin);
        return text;
    }
    double longestSide() const {
        const glm::dvec3 d = max - min;
        return std::max(d.x, std::max(d.y, d.z));
    }
};

yv::ViewVoxelization viewPlan(const TestGarment& g, double voxels) {
    yv::ViewVoxelization plan;
    plan.voxelSize = g.longestSide() / voxels;
    char text[64];
    std::snprintf(text, sizeof text, "%.3g", plan.voxelSize);
    plan.voxelSizeText = text;
    plan.voxelSize = std::stod(plan.voxelSizeText);
    plan.boxText = g.boxText(0.5);
    return plan;
}

} // namespace

TEST_CASE("A run given up before or between its regions throws RunCancelled and writes nothing", "[voxelize][cancel]") {
    yv::test::ScratchDir scratch("yv_cancel");
    const TestGarment garment(scratch.path);
    for (const bool workDir : {false, true}) {
        INFO("work dir: " << workDir);
        yv::VoxelizeJob job;
        job.input = garment.bcc.string();
        job.output = (scratch.path / (workDir ? "w.vdb" : "m.vdb")).string();
        if (workDir) job.workDir = (scratch.path / "w.work").string();
        job.backend = yv::BackendRequest::Cpu;
        job.resolution = 32;
        job.quiet = true;
        job.cancel = std::make_shared<std::atomic<bool>>(true);
        // Given up as soon as the garment is sliced: neither planned nor rasterized.
        CHECK_THROWS_MATCHES(yv::runVoxelize(job, [](const std::string&) {}), yv::RunCancelled,
                             Catch::Matchers::Predicate<yv::RunCancelled>([](const yv::RunCancelled& e) {
                                 return std::string(e.what()).find("after slicing the garment") != std::string::npos;
                             }));
        CHECK_FALSE(fs::exists(job.output));
        // The same job not given up writes its .vdb.
        job.cancel = std::make_shared<std::atomic<bool>>(false);
        CHECK(yv::runVoxelize(job, [](const std::string&) {}).activeVoxels > 0);
        CHECK(fs::exists(job.output));
    }
}

TEST_CASE("View voxelizer: a newer view gives up the pass under way, which says dropped, and the newer one is kept",
          "[view][cancel]") {
    yv::test::ScratchDir scratch("yv_view_cancel");
    const TestGarment garment(scratch.path);
    const fs::path saves = scratch.path / "saves";
    fs::create_directories(saves);

    std::mutex mutex;
    std::condition_variable wake;
    std::vector<Json> told;
    int finished = 0;
    yv::ViewVoxelizer::Listener listener;
    listener.tell = [&](const std::string& text) {
        const std::lock_guard lock(mutex);
        told.push_back(Json::parse(text));
        wake.notify_all();
    };
    listener.finished = [&] {
        const std::lock_guard lock(mutex);
        ++finished;
        wake.notify_all();
    };
    yv::VoxelizeJob base;
    base.input = garment.bcc.string();
    base.backend = yv::BackendRequest::Cpu;
    base.fragmentCapacity = 20000; // many small regions: a boundary comes soon
    yv::ViewVoxelizer voxelizer(base, saves, listener);

    // A fine run: many seconds of regions on two cores.
    REQUIRE(voxelizer.request(viewPlan(garment, 400)));
    {
        std::unique_lock lock(mutex);
        REQUIRE(wake.wait_for(lock, std::chrono::seconds(120), [&] { return !told.empty(); }));
        REQUIRE(told.front()["state"] == "running");
        REQUIRE(told.front()["id"] == 1);
    }
    const auto asked = std::chrono::steady_clock::now();
    REQUIRE(voxelizer.request(viewPlan(garment, 24)));
    {
        std::unique_lock lock(mutex);
        REQUIRE(wake.wait_for(lock, std::chrono::seconds(300), [&] { return finished > 0; }));
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - asked).count();
    const std::optional<yv::DetailRun> run = voxelizer.takeFinished();
    REQUIRE(run);
    CHECK(run->id == 2);
    CHECK(run->activeVoxels > 0);
    std::vector<std::string> states;
    {
        const std::lock_guard lock(mutex);
        for (const Json& m : told) {
            INFO(m.dump());
            CHECK(m["state"] != "failed");
            states.push_back(m["state"].get<std::string>() + " " + std::to_string(m["id"].get<int>()));
        }
    }
    INFO("the newer run came " << seconds << " s after it was asked");
    CHECK(states == std::vector<std::string>{"running 1", "dropped 1", "running 2"});
    // The run shown is its kept bricks; a view's runs write no file.
    REQUIRE(run->bricks);
    CHECK(run->bricks->brickCount() > 0);
    CHECK(fs::is_empty(saves));
}
