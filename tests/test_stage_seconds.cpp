// Time per stage: recorded by `yarnvox voxelize` in the work dir's manifest,
// shown by `yarnvox inspect` (and for a .vdb whose metadata carries them);
// older work dirs without them still open.
#include "core/error.h"
#include "core/stage_seconds.h"
#include "inspect/inspect_vdb.h"
#include "run_cli.h"
#include "store/brick_store.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <openvdb/openvdb.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

using namespace yv;
namespace fs = std::filesystem;

namespace {

struct Scratch : test::ScratchDir {
    Scratch() : test::ScratchDir("yv_test_stages") {}
};

/// `text` without blanks, so JSON is matched whatever its layout.
std::string compact(std::string text) {
    std::erase_if(text, [](char c) { return c == ' ' || c == '\n'; });
    return text;
}

double seconds(const StageSeconds& stages, const std::string& name) {
    for (const auto& [n, s] : stages)
        if (n == name) return s;
    FAIL("no stage " << name);
    return -1.0;
}

} // namespace

TEST_CASE("voxelize records its time per stage and inspect shows it", "[inspect][stages]") {
    Scratch scratch;
    const fs::path bcc = scratch.path / "plain.bcc", vdb = scratch.path / "plain.vdb", work = scratch.path / "work";
    REQUIRE(test::runYarnvox("gen --pattern plain --crossings 16 -o " + bcc.string()).exitCode == 0);
    const auto start = std::chrono::steady_clock::now();
    const test::RunResult v = test::runYarnvox("voxelize " + bcc.string() + " -o " + vdb.string() +
                                               " --backend cpu --resolution 48 --quiet --work-dir " + work.string());
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    INFO(v.output);
    REQUIRE(v.exitCode == 0);

    const StageSeconds stages = readManifest(work.string()).stageSeconds;
    REQUIRE(stages.size() >= 4);
    const std::vector<std::string> whole = {"read", "slices", "plan", "voxelize"};
    double sum = 0.0;
    for (std::size_t i = 0; i < whole.size(); ++i) {
        CHECK(stages[i].first == whole[i]); // in the order the run went through them
        sum += stages[i].second;
    }
    for (const auto& [name, s] : stages) {
        INFO(name);
        CHECK(s >= 0.0);
        CHECK((isWholeStage(name) || name.starts_with("voxelize.")));
    }
    CHECK(wholeStageSum(stages) == Approx(sum));
    CHECK(sum <= wall); // within the process's own lifetime
    CHECK(seconds(stages, "voxelize.store_write") >= 0.0); // the writer's parts are there

    // Text and JSON say the same.
    const test::RunResult text = test::runYarnvox("inspect " + work.string());
    INFO(text.output);
    CHECK(text.exitCode == 0);
    CHECK(text.output.find("time per stage: read ") != std::string::npos);
    CHECK(text.output.find("parts of them, on their own threads") != std::string::npos);
    const test::RunResult json = test::runYarnvox("inspect " + work.string() + " --json");
    CHECK(compact(json.output).find("\"stages\":{\"recorded\":true,\"seconds\":{\"read\":") != std::string::npos);

    // yarnvox's .vdb carries no times (its bytes are the same run after run), and says so.
    CHECK(inspectVdb(vdb.string()).stageSeconds.empty());
    const test::RunResult vdbText = test::runYarnvox("inspect " + vdb.string());
    CHECK(vdbText.output.find("time per stage: not recorded (the file has no stage_seconds metadata") != std::string::npos);
    // A .vdb whose metadata carries them (added here through OpenVDB) shows them.
    const fs::path timed = scratch.path / "timed.vdb";
    {
        openvdb::initialize();
        openvdb::io::File in(vdb.string());
        in.open();
        const openvdb::GridPtrVecPtr grids = in.getGrids();
        openvdb::MetaMap::Ptr meta = in.getMetadata();
        in.close();
        meta->insertMeta("stage_seconds", openvdb::StringMetadata(formatStageSeconds(stages)));
        openvdb::io::File(timed.string()).write(*grids, *meta);
    }
    const VdbSummary file = inspectVdb(timed.string());
    REQUIRE(file.stageSeconds.size() == stages.size());
    for (std::size_t i = 0; i < stages.size(); ++i) {
        CHECK(file.stageSeconds[i].first == stages[i].first);
        CHECK(file.stageSeconds[i].second == Approx(stages[i].second).epsilon(1e-6));
    }
    const test::RunResult timedText = test::runYarnvox("inspect " + timed.string());
    CHECK(timedText.output.find("time per stage: read ") != std::string::npos);
}

TEST_CASE("a work dir from before stage times opens and says they are not recorded", "[inspect][stages]") {
    Scratch scratch;
    const fs::path bcc = scratch.path / "plain.bcc", work = scratch.path / "work";
    REQUIRE(test::runYarnvox("gen --pattern plain --crossings 16 -o " + bcc.string()).exitCode == 0);
    REQUIRE(test::runYarnvox("voxelize " + bcc.string() + " -o " + (scratch.path / "plain.vdb").string() +
                             " --backend cpu --resolution 48 --quiet --work-dir " + work.string())
                .exitCode == 0);
    // A finished run's manifest without its stage times.
    std::ifstream in(work / "manifest");
    nlohmann::ordered_json manifest = nlohmann::ordered_json::parse(in);
    in.close();
    REQUIRE(manifest.contains("complete_regions"));
    REQUIRE(manifest.erase("stage_seconds") == 1);
    std::ofstream(work / "manifest", std::ios::trunc) << manifest.dump(2) << "\n";
    CHECK(readManifest(work.string()).stageSeconds.empty());

    const test::RunResult text = test::runYarnvox("inspect " + work.string());
    INFO(text.output);
    CHECK(text.exitCode == 0);
    CHECK(text.output.find("time per stage: not recorded (made by a yarnvox that did not record them)") !=
          std::string::npos);
    CHECK(compact(test::runYarnvox("inspect " + work.string() + " --json").output).find("\"recorded\":false") !=
          std::string::npos);
    CHECK(test::runYarnvox("merge " + work.string() + " -o " + (scratch.path / "m.vdb").string() + " --quiet").exitCode == 0);
}

TEST_CASE("stage times that are malformed are refused with the place named", "[inspect][stages]") {
    CHECK_THROWS_WITH(parseStageSeconds(R"({"read": 0.5, "slices": -1})", "f.vdb"),
                      Catch::StartsWith("f.vdb: stage times: \"slices\": expected seconds not negative"));
    CHECK_THROWS_WITH(parseStageSeconds(R"({"re ad": 0.5})", "f.vdb"), Catch::Contains("\"re ad\": expected a stage name"));
    CHECK_THROWS_WITH(parseStageSeconds(R"({"read": "0.5"})", "f.vdb"), Catch::Contains("\"read\": expected a finite number"));
    CHECK_THROWS_WITH(parseStageSeconds("read=0.5", "f.vdb"), Catch::StartsWith("f.vdb: stage times: not JSON"));
    CHECK_THROWS_WITH(parseStageSeconds("[0.5]", "f.vdb"), Catch::Contains("expected a JSON object"));
    CHECK(parseStageSeconds(formatStageSeconds({{"read", 0.25}, {"voxelize.store_write", 2.0}}), "x") ==
          StageSeconds{{"read", 0.25}, {"voxelize.store_write", 2.0}});

    StoreManifest m;
    m.grid.voxelSize = 1.0;
    m.grid.dims = {8, 8, 8};
    m.completeRegions = 1;
    m.stageSeconds = {{"read", 0.5}};
    const std::string text = formatManifest(m);
    CHECK(parseManifest("m", text).stageSeconds == StageSeconds{{"read", 0.5}});
    const auto with = [&](const std::string& from, const std::string& to) {
        std::string t = text;
        t.replace(t.find(from), from.size(), to);
        return t;
    };
    CHECK_THROWS_WITH(parseManifest("m", with("\"read\": 0.5", "\"read\": -0.5")),
                      Catch::StartsWith("m: stage times: \"read\": expected seconds not negative"));
    CHECK_THROWS_WITH(parseManifest("m", with("\"read\": 0.5", "\"read\": null")), Catch::Contains("finite number"));
    CHECK_THROWS_WITH(parseManifest("m", with("\"complete_regions\": 1,", "")),
                      Catch::Contains("\"stage_seconds\": recorded for a run that has not finished"));
}
