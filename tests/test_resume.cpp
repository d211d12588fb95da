// --resume as a script sees it: the counts --stats gives (regions found
// done, missing, damaged), the refusal of a --resume with nothing to resume
// from, and the command an interrupted run prints. CPU backend: no GL needed.
// docs/reliability.md lists them.
#include "run_cli.h"
#include "test_helpers.h"
#include "vdb_bytes.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

/// The region files of a work directory, in name order.
std::vector<fs::path> regionFiles(const fs::path& work) {
    std::vector<fs::path> files;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(work, ec))
        if (e.path().extension() == ".yvb") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files;
}

nlohmann::json readJson(const fs::path& p) {
    std::ifstream in(p);
    return nlohmann::json::parse(in);
}

/// A garment and options that make a few dozen zoom regions on the CPU backend.
struct ResumeRun {
    yv::test::ScratchDir dir{"yv_resume"};
    std::string bcc = (dir.path / "g.bcc").string();
    std::string options = " --backend cpu --resolution 1024 --yarn-radius 0.1 --slices-per-segment 2 --fragment-budget 50000 --quiet";
    ResumeRun() {
        REQUIRE(yv::test::runYarnvox("gen --pattern twill --shape cylinder --crossings 64 --quiet -o " + bcc).exitCode == 0);
    }
    std::string voxelize(const fs::path& out, const std::string& more) const {
        return "voxelize " + bcc + " -o " + out.string() + options + " " + more;
    }
};

} // namespace

TEST_CASE("Resume: --stats counts the regions found missing and those found damaged apart", "[out-of-core][cli]") {
    ResumeRun run;
    const fs::path work = run.dir.path / "work", reference = run.dir.path / "reference.vdb";
    const fs::path stats = run.dir.path / "stats.json";
    REQUIRE(yv::test::runYarnvox(run.voxelize(reference, "--work-dir " + work.string() + " --stats " + stats.string())).exitCode == 0);
    nlohmann::json json = readJson(stats)["backend_stats"];
    const std::uint64_t regions = json["zoom_regions"];
    REQUIRE(regions > 10);
    // A run that resumes nothing found nothing missing or damaged.
    CHECK(json["regions_missing_recomputed"] == 0);
    CHECK(json["regions_damaged_recomputed"] == 0);

    // As a killed run leaves it: three region files never written, two damaged.
    const std::vector<fs::path> files = regionFiles(work);
    REQUIRE(files.size() == regions);
    for (std::size_t i : {1, 4, 7}) fs::remove(files[i]);
    for (std::size_t i : {2, 9}) {
        std::fstream f(files[i], std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(static_cast<std::streamoff>(fs::file_size(files[i]) / 2));
        f.put('\x5a');
        f.put('\xa5');
    }
    const fs::path out = run.dir.path / "out.vdb";
    const yv::test::RunResult r = yv::test::runYarnvox(
        run.voxelize(out, "--work-dir " + work.string() + " --resume --stats " + stats.string()));
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    json = readJson(stats)["backend_stats"];
    CHECK(json["regions_missing_recomputed"] == 3); // were counted as damaged
    CHECK(json["regions_damaged_recomputed"] == 2);
    CHECK(json["regions_resumed"] == regions - 5);
    CHECK(json["regions_computed"] == 5);
    CHECK(yv::test::vdbBytesWithoutUuid(out) == yv::test::vdbBytesWithoutUuid(reference));

    // Resumed once more, complete: all found done.
    REQUIRE(yv::test::runYarnvox(run.voxelize(out, "--work-dir " + work.string() + " --resume --stats " + stats.string()))
                .exitCode == 0);
    json = readJson(stats)["backend_stats"];
    CHECK(json["regions_resumed"] == regions);
    CHECK(json["regions_missing_recomputed"] == 0);
    CHECK(json["regions_damaged_recomputed"] == 0);
}

TEST_CASE("bad input: --resume without --work-dir is refused in one line", "[bad-input][cli]") {
    ResumeRun run;
    const fs::path out = run.dir.path / "out.vdb";
    for (const std::string& more : {std::string("--resume"), std::string("--resume --keep-work-dir")}) {
        const yv::test::RunResult r = yv::test::runYarnvox(run.voxelize(out, more));
        INFO(more << "\n" << r.output);
        CHECK(r.exitCode == 1);
        CHECK_THAT(r.output, Contains("yarnvox: error: --resume needs --work-dir DIR") && Contains(out.string() + ".work"));
        CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 1);
        CHECK_FALSE(fs::exists(out));
        CHECK_FALSE(fs::exists(out.string() + ".work"));
    }
}

TEST_CASE("Resume: a run interrupted in its default work dir prints a command that names it and goes on",
          "[out-of-core][cli][faults]") {
    ResumeRun run;
    const fs::path out = run.dir.path / "out.vdb", work = run.dir.path / "out.vdb.work", log = run.dir.path / "log.txt";
    const pid_t child = fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        const std::string line = "exec " + std::string(YV_BINARY_DIR) + "/yarnvox " + run.voxelize(out, "--keep-work-dir") +
                                 " >" + log.string() + " 2>&1";
        execl("/bin/sh", "sh", "-c", line.c_str(), static_cast<char*>(nullptr));
        _exit(127);
    }
    int status = 0;
    while (regionFiles(work).size() < 3) {
        if (waitpid(child, &status, WNOHANG) == child) FAIL("the run ended before it could be interrupted");
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    kill(child, SIGINT);
    waitpid(child, &status, 0);
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 1);
    std::ifstream in(log);
    const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    INFO(text);
    const std::string marker = "go on with: ";
    const std::size_t at = text.find(marker);
    REQUIRE(at != std::string::npos);
    const std::string command = text.substr(at + marker.size(), text.find('\n', at) - at - marker.size());
    CHECK_THAT(command, Contains(" --work-dir " + work.string() + " --resume"));
    const yv::test::RunResult resumed = yv::test::runShell(command);
    INFO(resumed.output);
    CHECK(resumed.exitCode == 0);
    CHECK(fs::exists(out));
}
