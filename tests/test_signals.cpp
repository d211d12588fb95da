// SIGINT and SIGTERM at chosen points of every command that writes, and
// SIGKILL where nothing can be cleaned up: no temporary stays behind, the
// command says in one line what was kept and how to go on, exits non-zero,
// and a later run removes what a killed one left. The points are raised from
// inside yarnvox by YARNVOX_TEST_SIGNAL_AT=POINT[:SIG] (core/interrupt.h),
// so each lands exactly where it is named: before, during and after the .vdb
// write, during a merge, a picture, a report, an export.
#include "core/stale_temporaries.h"
#include "run_cli.h"
#include "test_helpers.h"
#include "vdb_bytes.h"

#include <catch2/catch.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>
#include <vector>

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

/// Everything under `dir` (recursively) named like a temporary of yarnvox's.
std::vector<std::string> temporariesIn(const fs::path& dir) {
    std::vector<std::string> found;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        const std::string name = e.path().filename().string();
        if (name.find(".partial-") != std::string::npos || name.find(".tmp-") != std::string::npos ||
            name.find(".old-") != std::string::npos)
            found.push_back(e.path().string());
    }
    return found;
}

std::size_t errorLines(const std::string& output) {
    std::size_t n = 0;
    for (std::size_t at = output.find("yarnvox: "); at != std::string::npos; at = output.find("yarnvox: ", at + 1)) ++n;
    return n;
}

/// The command after "go on with: " in `output`.
std::string goOnCommand(const std::string& output) {
    const std::string marker = "go on with: ";
    const std::size_t at = output.find(marker);
    if (at == std::string::npos) return "";
    const std::size_t end = output.find('\n', at);
    return output.substr(at + marker.size(), end - at - marker.size());
}

/// A small garment on the CPU backend: a run of a few regions, in well under a second.
struct SignalRun {
    fs::path dir, bcc, reference;
    std::string options = " --backend cpu --resolution 96 --yarn-radius 0.1 --slices-per-segment 2 --fragment-budget 20000 --quiet";

    explicit SignalRun(const std::string& name) {
        dir = fs::temp_directory_path() / ("yv_signals_" + std::to_string(getpid())) / name;
        fs::remove_all(dir);
        fs::create_directories(dir);
        bcc = dir / "g.bcc";
        reference = dir / "reference.vdb";
        REQUIRE(yv::test::runYarnvox("gen --pattern twill --shape cylinder --crossings 64 --quiet -o " + bcc.string()).exitCode == 0);
        REQUIRE(yv::test::runYarnvox("voxelize " + bcc.string() + " -o " + reference.string() + options).exitCode == 0);
    }
    ~SignalRun() { fs::remove_all(dir.parent_path()); }

    std::string voxelize(const fs::path& out, const std::string& extra = "") const {
        return "voxelize " + bcc.string() + " -o " + out.string() + options + extra;
    }
    bool sameAsReference(const fs::path& out) const {
        return yv::test::vdbBytesWithoutUuid(out) == yv::test::vdbBytesWithoutUuid(reference);
    }
};

/// `yarnvox ARGS` with a signal raised at `point`.
yv::test::RunResult runSignalled(const std::string& point, const std::string& args) {
    return yv::test::runShell("YARNVOX_TEST_SIGNAL_AT=" + point + " " + std::string(YV_BINARY_DIR) + "/yarnvox " + args);
}

/// Each (point, arguments, output): stopped there, one line, exit 1, neither the output nor a temporary.
void checkStopped(const SignalRun& run, const std::vector<std::tuple<std::string, std::string, std::string>>& cases) {
    for (const auto& [point, args, output] : cases) {
        INFO(point << ": " << args);
        const auto r = runSignalled(point, args);
        INFO(r.output);
        CHECK(r.exitCode == 1);
        CHECK(errorLines(r.output) == 1);
        CHECK_THAT(r.output, Contains("interrupted by SIG"));
        CHECK_FALSE(fs::exists(run.dir / output));
        CHECK(temporariesIn(run.dir).empty());
    }
}

} // namespace

TEST_CASE("Signals: voxelize stopped before, during or after the .vdb write keeps no temporary and says so", "[signals][cli]") {
    SignalRun run("voxelize");
    const fs::path out = run.dir / "out.vdb";
    for (const std::string point : {"vdb-start", "vdb-chunk:TERM", "vdb-publish", "vdb-written:TERM"}) {
        for (const bool workDir : {false, true}) {
            INFO(point << (workDir ? " with a work dir" : " in memory"));
            fs::remove(out);
            const fs::path work = run.dir / "work";
            fs::remove_all(work);
            const auto r = runSignalled(point, run.voxelize(out, workDir ? " --work-dir " + work.string() : ""));
            INFO(r.output);
            CHECK(r.exitCode == 1);
            CHECK(errorLines(r.output) == 1);
            const std::string signal = point.ends_with(":TERM") ? "SIGTERM" : "SIGINT";
            CHECK_THAT(r.output, Contains("yarnvox: error: interrupted by " + signal));
            CHECK(temporariesIn(run.dir).empty());
            if (point.starts_with("vdb-written")) {
                // Too late to stop: the file is whole, and the command still fails.
                CHECK_THAT(r.output, Contains("after the command had finished"));
                const bool same = run.sameAsReference(out);
                CHECK(same);
                continue;
            }
            CHECK_FALSE(fs::exists(out));
            if (!workDir) {
                CHECK_THAT(r.output, Contains("nothing was written or kept"));
                continue;
            }
            CHECK_THAT(r.output, Contains("regions are kept in " + work.string()));
            const std::string command = goOnCommand(r.output);
            CHECK_THAT(command, Contains(" --resume"));
            const auto resumed = yv::test::runShell(command);
            INFO(resumed.output);
            REQUIRE(resumed.exitCode == 0);
            const bool same = run.sameAsReference(out);
            CHECK(same);
        }
    }
}

TEST_CASE("Signals: voxelize --format vol stopped during its .vdb leaves neither the .vdb nor a .vol", "[signals][cli]") {
    SignalRun run("format");
    const fs::path out = run.dir / "out.vol";
    for (const std::string point : {"vdb-chunk", "vol-piece:TERM"}) {
        INFO(point);
        const auto r = runSignalled(point, run.voxelize(out));
        INFO(r.output);
        CHECK(r.exitCode == 1);
        CHECK(errorLines(r.output) == 1);
        CHECK_THAT(r.output, Contains("interrupted by SIG"));
        CHECK_FALSE(fs::exists(out));
        CHECK_FALSE(fs::exists(run.dir / "out.orientation.vol"));
        CHECK(temporariesIn(run.dir).empty());
    }
}

TEST_CASE("Signals: merge stopped while it reads regions or writes keeps the work dir and says how to go on", "[signals][cli]") {
    SignalRun run("merge");
    const fs::path work = run.dir / "work", out = run.dir / "merged.vdb", first = run.dir / "first.vdb";
    REQUIRE(yv::test::runYarnvox(run.voxelize(first, " --work-dir " + work.string())).exitCode == 0);
    const auto listing = [&] {
        std::vector<std::string> names;
        for (const auto& e : fs::directory_iterator(work)) names.push_back(e.path().filename().string() + ":" + std::to_string(fs::file_size(e.path())));
        std::sort(names.begin(), names.end());
        return names;
    };
    const auto before = listing();
    for (const std::string point : {"merge-region", "vdb-chunk:TERM", "vdb-publish"}) {
        INFO(point);
        const auto r = runSignalled(point, "merge " + work.string() + " -o " + out.string() + " --quiet");
        INFO(r.output);
        CHECK(r.exitCode == 1);
        CHECK(errorLines(r.output) == 1);
        CHECK_THAT(r.output, Contains("while merging " + work.string()));
        CHECK_THAT(r.output, Contains("is unchanged"));
        CHECK_FALSE(fs::exists(out));
        CHECK(temporariesIn(run.dir).empty());
        CHECK(listing() == before);
        const std::string command = goOnCommand(r.output);
        REQUIRE_FALSE(command.empty());
        const auto again = yv::test::runShell(command);
        INFO(again.output);
        REQUIRE(again.exitCode == 0);
        const bool same = yv::test::vdbBytesWithoutUuid(out) == yv::test::vdbBytesWithoutUuid(first);
        CHECK(same);
        fs::remove(out);
    }
}

TEST_CASE("Signals: gen, export and inspect --mesh stop without a temporary", "[signals][cli]") {
    SignalRun run("others");
    const fs::path bcc = run.dir / "new.bcc";
    const auto gen = runSignalled("gen-write", "gen --crossings 50 --quiet -o " + bcc.string());
    INFO(gen.output);
    CHECK(gen.exitCode == 1);
    CHECK_THAT(gen.output, Contains("interrupted by SIGINT before " + bcc.string() + " was written"));
    CHECK_FALSE(fs::exists(bcc));
    const auto genLate = runSignalled("command-end:TERM", "gen --crossings 50 --quiet -o " + bcc.string());
    CHECK(genLate.exitCode == 1);
    CHECK_THAT(genLate.output, Contains("interrupted by SIGTERM after the command had finished: " + bcc.string() + " is whole"));
    CHECK(fs::exists(bcc));

    checkStopped(run, {{"vol-piece", "export " + run.reference.string() + " -o " + (run.dir / "e.vol").string(), "e.vol"},
                       {"nvdb-write:TERM", "export " + run.reference.string() + " -o " + (run.dir / "e.nvdb").string(), "e.nvdb"},
                       {"mesh-write", "inspect " + run.reference.string() + " --mesh " + (run.dir / "m.ply").string() + " --iso 0.05", "m.ply"}});
}

TEST_CASE("Signals: inspect's pictures and report stop without a temporary", "[signals][cli][gl]") {
    YV_REQUIRE_GL();
    SignalRun run("inspect");
    const std::string vdb = run.reference.string(), html = " --size 32x24 --html-renders 1";
    checkStopped(run, {{"png-write", "inspect " + vdb + " --render mip --size 32x32 -o " + (run.dir / "p.png").string(), "p.png"},
                       {"png-write:TERM", "inspect " + vdb + " --html " + (run.dir / "report").string() + html, "report"},
                       {"html-move", "inspect " + vdb + " --html " + (run.dir / "report").string() + html, "report"}});
}

TEST_CASE("Signals: what a killed run leaves beside its output, the next run removes", "[signals][cli]") {
    SignalRun run("killed");
    const fs::path out = run.dir / "out.vdb";
    const auto killed = runSignalled("vdb-chunk:KILL", run.voxelize(out));
    CHECK(killed.exitCode != 0);
    CHECK_FALSE(fs::exists(out));
    const std::vector<std::string> left = temporariesIn(run.dir);
    REQUIRE(left.size() == 1); // OUT.partial-PID-N: nothing could remove it
    CHECK_THAT(left[0], Contains("out.vdb.partial-"));
    // Another output beside it keeps it (it is not that run's)...
    REQUIRE(yv::test::runYarnvox(run.voxelize(run.dir / "other.vdb")).exitCode == 0);
    CHECK(temporariesIn(run.dir) == left);
    // ... the next run writing out.vdb removes it.
    const auto again = yv::test::runYarnvox(run.voxelize(out));
    INFO(again.output);
    REQUIRE(again.exitCode == 0);
    CHECK(temporariesIn(run.dir).empty());
}

TEST_CASE("Signals: a report directory a killed run left is removed by the next report", "[signals][cli][gl]") {
    YV_REQUIRE_GL();
    SignalRun run("killed-report");
    const fs::path out = run.reference;
    const fs::path report = run.dir / "report";
    const std::string html = "inspect " + out.string() + " --html " + report.string() + " --size 32x24 --html-renders 1";
    CHECK(runSignalled("png-write:KILL", html).exitCode != 0);
    REQUIRE(temporariesIn(run.dir).size() >= 1); // report.tmp-PID and what is in it
    const auto report2 = yv::test::runYarnvox(html);
    INFO(report2.output);
    REQUIRE(report2.exitCode == 0);
    CHECK(temporariesIn(run.dir).empty());
    CHECK(fs::exists(report / "index.html"));
}

TEST_CASE("Stale temporaries: only yarnvox's names of the output, and only of processes that are gone", "[signals]") {
    using yv::temporaryOwner;
    CHECK(temporaryOwner("out.vdb.partial-123-4", "out.vdb") == 123);
    CHECK(temporaryOwner("out.vol.partial-77.vdb", "out.vol") == 77);
    CHECK(temporaryOwner("out.vol.partial-77.vdb.partial-77-0", "out.vol") == 77);
    CHECK(temporaryOwner("report.tmp-9", "report") == 9);
    CHECK(temporaryOwner("report.old-9", "report") == 9);
    CHECK(temporaryOwner("out.vdb.partial-", "out.vdb") == -1);
    CHECK(temporaryOwner("out.vdb.partial-12x", "out.vdb") == -1);
    CHECK(temporaryOwner("out.vdb.partial-12-0", "out.vd") == -1);
    CHECK(temporaryOwner("xout.vdb.partial-12-0", "out.vdb") == -1);
    CHECK(temporaryOwner("out.vdb", "out.vdb") == -1);

    const fs::path dir = fs::temp_directory_path() / ("yv_stale_" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const pid_t child = fork();
    REQUIRE(child >= 0);
    if (child == 0) _exit(0);
    waitpid(child, nullptr, 0); // its PID now names no process
    const std::string dead = std::to_string(child), alive = std::to_string(getppid());
    const auto touch = [&](const std::string& name) { std::ofstream(dir / name) << "x"; };
    touch("out.vdb.partial-" + dead + "-0");
    touch("out.vdb.partial-" + alive + "-0");
    touch("out.vdb.partial-" + std::to_string(getpid()) + "-0"); // this process's own: it is writing it
    touch("other.vdb.partial-" + dead + "-0");
    touch("out.vdb.notes");
    fs::create_directories(dir / ("out.vdb.tmp-" + dead) / "renders");
    fs::create_directories(dir / ("out.vdb.old-" + dead)); // no renders/: not a report yarnvox was building
    const std::vector<std::string> removed = yv::removeStaleTemporaries((dir / "out.vdb").string());
    CHECK(removed.size() == 2);
    CHECK_FALSE(fs::exists(dir / ("out.vdb.partial-" + dead + "-0")));
    CHECK_FALSE(fs::exists(dir / ("out.vdb.tmp-" + dead)));
    CHECK(fs::exists(dir / ("out.vdb.partial-" + alive + "-0")));
    CHECK(fs::exists(dir / ("out.vdb.partial-" + std::to_string(getpid()) + "-0")));
    CHECK(fs::exists(dir / ("other.vdb.partial-" + dead + "-0")));
    CHECK(fs::exists(dir / "out.vdb.notes"));
    CHECK(fs::exists(dir / ("out.vdb.old-" + dead)));
    fs::remove_all(dir);
}
