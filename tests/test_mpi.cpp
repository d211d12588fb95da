// `mpirun -np N yarnvox voxelize`: any number of ranks writes the .vdb of one
// process, and a run that lost a rank resumes, with another N, to the same file.
// Built and run only with -DYARNVOX_MPI=ON, where mpirun must work: a missing
// or broken Open MPI fails these tests rather than skipping them.
#include "run_cli.h"
#include "test_helpers.h"
#include "vdb_bytes.h"

#include <catch2/catch.hpp>

#include <chrono>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <unistd.h>

namespace fs = std::filesystem;
using yv::test::runShell;
using yv::test::runYarnvox;

namespace {

/// `mpirun -np RANKS` as every MPI test starts it, with what this machine and
/// CI need, in one place:
/// - --allow-run-as-root: CI runs as root, which Open MPI refuses otherwise;
/// - --oversubscribe: three ranks on a two-core machine;
/// - btl self,vader and no single-copy (CMA) mechanism: in a container,
///   ptrace-based copies between processes are often not permitted, and there
///   is no network to look for;
/// - mpi_yield_when_idle: ranks that wait give their core to those working;
/// - --bind-to none: as a real run (README), each rank's threads on every core.
std::string mpirun(int ranks) {
    REQUIRE(fs::exists(YV_MPIEXEC));
    return std::string(YV_MPIEXEC) + " --bind-to none --allow-run-as-root --oversubscribe --mca btl self,vader"
                                     " --mca btl_vader_single_copy_mechanism none --mca mpi_yield_when_idle 1 -np " +
           std::to_string(ranks) + " " + YV_BINARY_DIR + "/yarnvox ";
}

fs::path scratchDir(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("yv_mpi_" + std::to_string(getpid())) / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::size_t regionFiles(const fs::path& dir) {
    std::size_t n = 0;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) n += e.path().extension() == ".yvb";
    return n;
}

std::string readFile(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// The value of `"key": N` in a --stats file (-1 when absent).
long long jsonNumber(const std::string& json, const std::string& key) {
    const std::string needle = "\"" + key + "\": ";
    const std::size_t at = json.find(needle);
    return at == std::string::npos ? -1 : std::stoll(json.substr(at + needle.size()));
}

bool sameVdb(const fs::path& a, const fs::path& b) {
    return yv::test::vdbBytesWithoutUuid(a) == yv::test::vdbBytesWithoutUuid(b);
}

/// A garment whose run has dozens of small regions, so every rank gets some.
fs::path makeGarment(const fs::path& dir) {
    const fs::path bcc = dir / "g.bcc";
    const auto gen = runYarnvox("gen --pattern twill --shape cylinder --crossings 64 -o " + bcc.string());
    REQUIRE(gen.exitCode == 0);
    return bcc;
}

std::string options(const std::string& backend) {
    return " --backend " + backend +
           " --resolution 512 --yarn-radius 0.1 --slices-per-segment 2 --twist 2 --fragment-budget 50000 --quiet";
}

} // namespace

TEST_CASE("mpirun with 1 2 and 3 ranks writes the .vdb of a single process", "[mpi][cli]") {
    const std::string backend = GENERATE(as<std::string>(), "gl", "cpu");
    if (backend == "gl") YV_REQUIRE_GL();
    INFO("--backend " << backend);
    const fs::path dir = scratchDir("ranks-" + backend);
    const fs::path bcc = makeGarment(dir);
    const fs::path reference = dir / "reference.vdb";
    const auto single = runYarnvox("voxelize " + bcc.string() + " -o " + reference.string() + options(backend));
    REQUIRE(single.exitCode == 0);
    for (const int ranks : {1, 2, 3}) {
        INFO("mpirun -np " << ranks);
        const fs::path out = dir / ("ranks" + std::to_string(ranks) + ".vdb"), stats = dir / "stats.json";
        const auto run = runShell(mpirun(ranks) + "voxelize " + bcc.string() + " -o " + out.string() + options(backend) +
                                  " --stats " + stats.string());
        INFO(run.output);
        REQUIRE(run.exitCode == 0);
        CHECK(sameVdb(reference, out));
        const std::string json = readFile(stats);
        CHECK(json.find("\"ranks\": " + std::to_string(ranks)) != std::string::npos);
        // Every region rasterized exactly once, over all ranks together.
        CHECK(jsonNumber(json, "regions_computed") == jsonNumber(json, "zoom_regions"));
        CHECK(jsonNumber(json, "regions_computed") > 20);
        // The default work dir only carried the regions between the ranks.
        CHECK_FALSE(fs::exists(out.string() + ".work"));
    }
    fs::remove_all(dir.parent_path());
}

TEST_CASE("A rank killed part-way then --resume with another rank count gives the same .vdb", "[mpi][cli]") {
    YV_REQUIRE_GL();
    const fs::path dir = scratchDir("killed");
    const fs::path bcc = makeGarment(dir);
    const fs::path reference = dir / "reference.vdb", work = dir / "work", out = dir / "out.vdb";
    REQUIRE(runYarnvox("voxelize " + bcc.string() + " -o " + reference.string() + options("gl")).exitCode == 0);

    // Rank 1 dies (SIGKILL) holding its fourth region: the run stops, naming it.
    const std::string args = "voxelize " + bcc.string() + " -o " + out.string() + options("gl") + " --work-dir " + work.string();
    const auto killed = runShell("YARNVOX_TEST_KILL_RANK=1:3 " + mpirun(2) + args);
    INFO(killed.output);
    CHECK(killed.exitCode != 0);
    CHECK_THAT(killed.output, Catch::Contains("rank 1"));
    CHECK_FALSE(fs::exists(out));
    // How many regions are on disk depends on timing: the survivor stops
    // within 0.2 s of the death, and finished regions still queued for
    // writing die with their rank (on a loaded machine that may be all of
    // them). What is kept must be exactly what the resume trusts.
    const std::size_t kept = regionFiles(work);
    INFO(kept << " regions kept");

    // Three ranks finish what is missing and write the same file.
    const fs::path stats = dir / "stats.json";
    const auto resumed = runShell(mpirun(3) + args + " --resume --stats " + stats.string());
    INFO(resumed.output);
    REQUIRE(resumed.exitCode == 0);
    CHECK(sameVdb(reference, out));
    const std::string json = readFile(stats);
    CHECK(json.find("\"regions_resumed\": " + std::to_string(kept)) != std::string::npos);
    CHECK(json.find("\"regions_computed\": 0") == std::string::npos);
    fs::remove_all(dir.parent_path());
}

TEST_CASE("A dead rank is noticed by the others, which stop at once, keep the regions and say how to go on", "[mpi][cli]") {
    const fs::path dir = scratchDir("dead-rank");
    const fs::path bcc = makeGarment(dir);
    const fs::path reference = dir / "reference.vdb", out = dir / "out.vdb";
    REQUIRE(runYarnvox("voxelize " + bcc.string() + " -o " + reference.string() + options("cpu")).exitCode == 0);
    // Rank 1, or rank 0 (which hands out the regions), dies holding its third region.
    for (const auto& [ranks, dead] : {std::pair{2, 1}, std::pair{3, 1}, std::pair{3, 0}}) {
        INFO("mpirun -np " << ranks << ", rank " << dead << " killed");
        const fs::path work = dir / ("work-" + std::to_string(ranks) + "-" + std::to_string(dead));
        const std::string args = "voxelize " + bcc.string() + " -o " + out.string() + options("cpu") + " --work-dir " + work.string();
        const auto start = std::chrono::steady_clock::now();
        const auto killed = runShell("YARNVOX_TEST_KILL_RANK=" + std::to_string(dead) + ":2 timeout 60 " + mpirun(ranks) + args);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        INFO(killed.output);
        CHECK(killed.exitCode != 0);
        CHECK(killed.exitCode != 124); // mpirun ended by itself, not by the timeout
        CHECK(seconds < 30.0);
        CHECK_FALSE(fs::exists(out));
        // A survivor says which rank is gone, what is kept and the command that goes on.
        const std::string said = "rank " + std::to_string(dead) + " (PID ";
        CHECK_THAT(killed.output, Catch::Contains(said) && Catch::Contains("ended before the run did"));
        const std::string marker = "kept in " + work.string() + "; go on with: ";
        const std::size_t at = killed.output.find(marker);
        REQUIRE(at != std::string::npos);
        const std::string command = killed.output.substr(at + marker.size(), killed.output.find('\n', at) - at - marker.size());
        CHECK_THAT(command, Catch::EndsWith(" --resume"));
        // What the ranks wrote stays for the resume, which trusts exactly that
        // (how much was written before the stop depends on timing: finished
        // regions still queued for writing end with their rank).
        const std::size_t kept = regionFiles(work);
        INFO(kept << " regions kept");
        const fs::path stats = dir / "stats.json";
        const auto resumed = runShell(command + " --stats " + stats.string());
        INFO(resumed.output);
        REQUIRE(resumed.exitCode == 0);
        CHECK(sameVdb(reference, out));
        CHECK(jsonNumber(readFile(stats), "regions_resumed") == static_cast<long long>(kept));
        for (const auto& e : fs::directory_iterator(work)) CHECK(e.path().filename().string().find(".partial-") == std::string::npos);
        fs::remove(out);
    }
    fs::remove_all(dir.parent_path());
}

TEST_CASE("Under mpirun a SIGTERM is answered at once with what is kept and the command that goes on", "[mpi][cli]") {
    const fs::path dir = scratchDir("sigterm");
    const fs::path bcc = makeGarment(dir);
    const fs::path reference = dir / "reference.vdb", out = dir / "out.vdb", work = dir / "work";
    REQUIRE(runYarnvox("voxelize " + bcc.string() + " -o " + reference.string() + options("cpu")).exitCode == 0);
    // Rank 0 gets SIGTERM while it writes the .vdb (mpirun would end it a second later).
    const std::string args = "voxelize " + bcc.string() + " -o " + out.string() + options("cpu") + " --work-dir " + work.string();
    const auto stopped = runShell("YARNVOX_TEST_SIGNAL_AT=vdb-chunk:TERM timeout 60 " + mpirun(2) + args);
    INFO(stopped.output);
    CHECK(stopped.exitCode != 0);
    CHECK(stopped.exitCode != 124);
    CHECK_FALSE(fs::exists(out));
    CHECK_THAT(stopped.output, Catch::Contains("yarnvox: error: rank 0: stopped by SIGTERM"));
    const std::string marker = "kept in " + work.string() + "; go on with: ";
    const std::size_t at = stopped.output.find(marker);
    REQUIRE(at != std::string::npos);
    const std::string command = stopped.output.substr(at + marker.size(), stopped.output.find('\n', at) - at - marker.size());
    // The .vdb's temporary stays (the rank ended at once); the run that goes on removes it.
    std::size_t left = 0;
    for (const auto& e : fs::directory_iterator(dir)) left += e.path().filename().string().starts_with("out.vdb.partial-");
    CHECK(left == 1);
    const auto resumed = runShell(command);
    INFO(resumed.output);
    REQUIRE(resumed.exitCode == 0);
    CHECK(sameVdb(reference, out));
    for (const auto& e : fs::directory_iterator(dir)) CHECK(e.path().filename().string().find(".partial-") == std::string::npos);
    fs::remove_all(dir.parent_path());
}

TEST_CASE("mpirun with several garments writes one .vdb per input and each is the single-process file", "[mpi][cli]") {
    const fs::path dir = scratchDir("frames");
    const fs::path a = dir / "a.bcc", b = dir / "b.bcc";
    REQUIRE(runYarnvox("gen --pattern plain --crossings 16 -o " + a.string()).exitCode == 0);
    REQUIRE(runYarnvox("gen --pattern knit --crossings 16 -o " + b.string()).exitCode == 0);
    const std::string opts = " --backend cpu --resolution 128 --fragment-budget 50000 --quiet";
    REQUIRE(runYarnvox("voxelize " + a.string() + " -o " + (dir / "alone-a.vdb").string() + opts).exitCode == 0);
    REQUIRE(runYarnvox("voxelize " + b.string() + " -o " + (dir / "alone-b.vdb").string() + opts).exitCode == 0);
    // Fewer garments than ranks: the ranks share each garment's regions.
    const auto shared = runShell(mpirun(3) + "voxelize " + a.string() + " " + b.string() + " -o " + (dir / "out").string() + opts);
    INFO(shared.output);
    REQUIRE(shared.exitCode == 0);
    CHECK(sameVdb(dir / "alone-a.vdb", dir / "out" / "a.vdb"));
    CHECK(sameVdb(dir / "alone-b.vdb", dir / "out" / "b.vdb"));
    // As many garments as ranks or more: whole garments, one rank each.
    const fs::path c = dir / "c.bcc";
    REQUIRE(runYarnvox("gen --pattern twill --crossings 16 -o " + c.string()).exitCode == 0);
    REQUIRE(runYarnvox("voxelize " + c.string() + " -o " + (dir / "alone-c.vdb").string() + opts).exitCode == 0);
    const std::string loud = " --backend cpu --resolution 128 --fragment-budget 50000";
    const auto whole = runShell(mpirun(2) + "voxelize " + a.string() + " " + b.string() + " " + c.string() + " -o " +
                                (dir / "whole").string() + loud);
    INFO(whole.output);
    REQUIRE(whole.exitCode == 0);
    std::size_t wholeLines = 0;
    for (std::size_t at = whole.output.find(", whole ("); at != std::string::npos; at = whole.output.find(", whole (", at + 1))
        ++wholeLines;
    CHECK(wholeLines == 3);
    CHECK(sameVdb(dir / "alone-a.vdb", dir / "whole" / "a.vdb"));
    CHECK(sameVdb(dir / "alone-b.vdb", dir / "whole" / "b.vdb"));
    CHECK(sameVdb(dir / "alone-c.vdb", dir / "whole" / "c.vdb"));
    fs::remove_all(dir.parent_path());
}
