// Faults in the middle of an out-of-core run: a disk that fills while the
// work directory is written, and a run killed again and again. Each ends, once
// resumed, in the .vdb an uninterrupted run writes.
#include "run_cli.h"
#include "test_helpers.h"
#include "vdb_bytes.h"

#include <catch2/catch.hpp>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <thread>

namespace fs = std::filesystem;

namespace {

/// A garment and options that make a few dozen small zoom regions on llvmpipe.
struct FaultRun {
    fs::path dir, bcc, reference;
    std::string options = " --backend gl --resolution 1024 --yarn-radius 0.1 --slices-per-segment 2 --twist 2 --fragment-budget 50000 --quiet";

    explicit FaultRun(const std::string& name) {
        dir = fs::temp_directory_path() / ("yv_faults_" + std::to_string(getpid())) / name;
        fs::remove_all(dir);
        fs::create_directories(dir);
        bcc = dir / "g.bcc";
        reference = dir / "reference.vdb";
        REQUIRE(yv::test::runYarnvox("gen --pattern twill --shape cylinder --crossings 64 --quiet -o " + bcc.string()).exitCode == 0);
        REQUIRE(yv::test::runYarnvox(voxelize(reference, dir / "work-ref")).exitCode == 0);
    }
    ~FaultRun() { fs::remove_all(dir.parent_path()); }

    std::string voxelize(const fs::path& out, const fs::path& work, bool resume = false) const {
        return "voxelize " + bcc.string() + " -o " + out.string() + options + " --work-dir " + work.string() +
               (resume ? " --resume" : "");
    }
    bool sameAsReference(const fs::path& out) const {
        return yv::test::vdbBytesWithoutUuid(out) == yv::test::vdbBytesWithoutUuid(reference);
    }
};

} // namespace

TEST_CASE("A disk that fills while regions are written: exit 1, no .vdb, and the resume writes the uninterrupted run's", "[gl][out-of-core][cli][faults]") {
    YV_REQUIRE_GL();
    FaultRun run("store-full");
    const fs::path work = run.dir / "work", out = run.dir / "out.vdb";
    // A 48 KiB file-size limit (SIGXFSZ ignored: writes past it fail with EFBIG, as with ENOSPC).
    const yv::test::RunResult full =
        yv::test::runShell("ulimit -f 48; trap '' XFSZ; exec " + std::string(YV_BINARY_DIR) + "/yarnvox " + run.voxelize(out, work));
    INFO(full.output);
    CHECK(full.exitCode == 1);
    CHECK(full.output.find("yarnvox: error:") != std::string::npos);
    CHECK(full.output.find("File too large") != std::string::npos);
    CHECK_FALSE(fs::exists(out));
    const yv::test::RunResult resumed = yv::test::runYarnvox(run.voxelize(out, work, true));
    INFO(resumed.output);
    REQUIRE(resumed.exitCode == 0);
    const bool same = run.sameAsReference(out);
    CHECK(same);
}

TEST_CASE("A run killed at random points again and again, each time resumed, ends in the uninterrupted run's .vdb", "[gl][out-of-core][cli][faults]") {
    YV_REQUIRE_GL();
    FaultRun run("kill-loop");
    const fs::path work = run.dir / "work", out = run.dir / "out.vdb";
    std::mt19937 rng(20261123);
    int kills = 0;
    for (int attempt = 0; attempt < 6; ++attempt) {
        const pid_t child = fork();
        REQUIRE(child >= 0);
        if (child == 0) {
            const std::string line = std::string(YV_BINARY_DIR) + "/yarnvox " + run.voxelize(out, work, attempt > 0);
            execl("/bin/sh", "sh", "-c", ("exec " + line + " >/dev/null 2>&1").c_str(), static_cast<char*>(nullptr));
            _exit(127);
        }
        // Anywhere from start-up to the merge.
        std::this_thread::sleep_for(std::chrono::milliseconds(100 + rng() % 1500));
        int status = 0;
        if (waitpid(child, &status, WNOHANG) == child) {
            REQUIRE(WIFEXITED(status));
            REQUIRE(WEXITSTATUS(status) == 0);
            break; // finished before this kill
        }
        kill(child, SIGKILL);
        waitpid(child, &status, 0);
        ++kills;
        // A killed run leaves no .vdb, unless the kill came after the rename:
        // then the file is whole.
        if (fs::exists(out)) break;
    }
    CHECK(kills >= 2);
    if (!fs::exists(out)) REQUIRE(yv::test::runYarnvox(run.voxelize(out, work, true)).exitCode == 0);
    const bool same = run.sameAsReference(out);
    CHECK(same);
}

TEST_CASE("SIGINT stops at a region boundary, says how far and how to go on, and going on gives the uninterrupted file", "[gl][out-of-core][cli][faults]") {
    YV_REQUIRE_GL();
    FaultRun run("sigint");
    const fs::path work = run.dir / "work", out = run.dir / "out.vdb", log = run.dir / "log.txt";
    const pid_t child = fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        // yarnvox itself gets the signal (exec, no shell in between).
        const std::string line = "exec " + std::string(YV_BINARY_DIR) + "/yarnvox " + run.voxelize(out, work) + " >" +
                                 log.string() + " 2>&1";
        execl("/bin/sh", "sh", "-c", line.c_str(), static_cast<char*>(nullptr));
        _exit(127);
    }
    const auto regionFiles = [&] {
        std::size_t n = 0;
        std::error_code ec;
        for (const auto& e : fs::directory_iterator(work, ec)) n += e.path().extension() == ".yvb";
        return n;
    };
    int status = 0;
    while (regionFiles() < 3) {
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
    CHECK(text.find("yarnvox: error: interrupted by SIGINT after ") != std::string::npos);
    CHECK_FALSE(fs::exists(out));
    const std::string marker = "go on with: ";
    const std::size_t at = text.find(marker);
    REQUIRE(at != std::string::npos);
    const std::string command = text.substr(at + marker.size(), text.find('\n', at) - at - marker.size());
    CHECK(command.find(" --resume") != std::string::npos);
    const yv::test::RunResult resumed = yv::test::runShell(command);
    INFO(resumed.output);
    REQUIRE(resumed.exitCode == 0);
    const bool same = run.sameAsReference(out);
    CHECK(same);
}
