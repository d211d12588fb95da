// Every command that writes a file refuses to write it over what is not a
// regular file: a FIFO, a symbolic link, a directory, a device. Renaming a
// finished file over one of them would destroy it (a device node, a link
// the user made). Device nodes are checked through the path check itself,
// never by running a command against one: if the check failed, the run
// would replace the machine's /dev/null. docs/reliability.md lists them.
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/output_path.h"
#include "run_cli.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

std::string readText(const fs::path& p) {
    std::ifstream in(p);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::size_t lineCount(const std::string& s) { return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')); }

/// Three things that are not a regular file, under names ending in `suffix`:
/// a FIFO, a symbolic link to a file of their own, a directory holding one.
struct NotFiles {
    fs::path fifo, link, linked, dir;

    NotFiles(const fs::path& in, const std::string& suffix)
        : fifo(in / ("fifo" + suffix)), link(in / ("link" + suffix)), linked(in / "linked.txt"), dir(in / ("dir" + suffix)) {
        REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
        std::ofstream(linked) << "keep me";
        fs::create_symlink(linked, link);
        fs::create_directory(dir);
        std::ofstream(dir / "inside.txt") << "keep me too";
    }

    /// Each is still what it was, and holds what it held.
    void checkUnchanged() const {
        CHECK(fs::is_fifo(fs::symlink_status(fifo)));
        CHECK(fs::is_symlink(fs::symlink_status(link)));
        CHECK(fs::read_symlink(link) == linked);
        CHECK(readText(linked) == "keep me");
        CHECK(fs::is_directory(fs::symlink_status(dir)));
        CHECK(readText(dir / "inside.txt") == "keep me too");
    }
};

/// No temporary (PATH.partial-..., DIR.tmp-...) left anywhere under `dir`.
void checkNoTemporaries(const fs::path& dir) {
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        const std::string name = e.path().filename().string();
        INFO(e.path());
        CHECK(name.find(".partial-") == std::string::npos);
        CHECK(name.find(".tmp-") == std::string::npos);
    }
}

/// Runs `yarnvox ARGS` (a FIFO opened for writing would block: never more
/// than two minutes) and checks it is refused in one line naming `target`.
void expectRefused(const std::string& args, const fs::path& target, const std::string& kind) {
    const yv::test::RunResult r = yv::test::runShell("timeout 120 " + std::string(YV_BINARY_DIR) + "/yarnvox " + args);
    INFO("yarnvox " << args << "\n" << r.output);
    CHECK(r.exitCode != 0);
    CHECK(r.exitCode != 124); // not stopped by the timeout
    CHECK_THAT(r.output, Contains("yarnvox: error: ") && Contains(target.string()) && Contains(kind));
    CHECK(lineCount(r.output) == 1);
}

} // namespace

TEST_CASE("CLI: every command that writes a file refuses a FIFO, a symbolic link or a directory, and changes none",
          "[cli][output-paths]") {
    yv::test::ScratchDir scratch("yv_output_paths");
    const fs::path& at = scratch.path;
    const std::string bcc = (at / "g.bcc").string(), vdb = (at / "g.vdb").string(), work = (at / "g.work").string();
    REQUIRE(yv::test::runYarnvox("gen --crossings 40 --quiet -o " + bcc).exitCode == 0);
    REQUIRE(yv::test::runYarnvox("voxelize " + bcc + " -o " + vdb + " --backend cpu --resolution 32 --quiet --work-dir " +
                                 work)
                .exitCode == 0);
    REQUIRE(fs::is_directory(work));

    struct Command {
        std::string name, suffix;
        std::function<std::string(const fs::path&)> args;
    };
    const Command commands[] = {
        {"gen", ".bcc", [](const fs::path& t) { return "gen --crossings 40 -o " + t.string(); }},
        {"voxelize", ".vdb", [&](const fs::path& t) { return "voxelize " + bcc + " --backend cpu --resolution 32 -o " + t.string(); }},
        {"voxelize-stats", ".json",
         [&](const fs::path& t) {
             return "voxelize " + bcc + " --backend cpu --resolution 32 -o " + (at / "ok.vdb").string() + " --stats " + t.string();
         }},
        {"voxelize-vol", ".vol", [&](const fs::path& t) { return "voxelize " + bcc + " --backend cpu --resolution 32 -o " + t.string(); }},
        {"merge", ".vdb", [&](const fs::path& t) { return "merge " + work + " -o " + t.string(); }},
        {"export", ".vol", [&](const fs::path& t) { return "export " + vdb + " -o " + t.string(); }},
        {"export-nvdb", ".nvdb", [&](const fs::path& t) { return "export " + vdb + " -o " + t.string(); }},
        {"inspect-render", ".png", [&](const fs::path& t) { return "inspect " + vdb + " --render cut --cut z:4 -o " + t.string(); }},
        {"inspect-mesh", ".ply", [&](const fs::path& t) { return "inspect " + vdb + " --mesh " + t.string(); }},
    };
    for (const Command& c : commands) {
        DYNAMIC_SECTION(c.name) {
            const fs::path in = at / c.name;
            fs::create_directory(in);
            const NotFiles targets(in, c.suffix);
            expectRefused(c.args(targets.fifo), targets.fifo, "is a FIFO, not a regular file");
            expectRefused(c.args(targets.link), targets.link, "is a symbolic link, not a regular file");
            expectRefused(c.args(targets.dir), targets.dir, "is a directory, not a regular file");
            targets.checkUnchanged();
            checkNoTemporaries(in);
            CHECK_FALSE(fs::exists(at / "ok.vdb"));
        }
    }
    // --html writes a directory: a FIFO, a link or a directory of other files is refused.
    SECTION("inspect-html") {
        const fs::path in = at / "html";
        fs::create_directory(in);
        const NotFiles targets(in, "");
        const std::string html = "inspect " + vdb + " --html ";
        expectRefused(html + targets.fifo.string(), targets.fifo, "not a directory");
        expectRefused(html + targets.link.string(), targets.link, "is a symbolic link");
        expectRefused(html + targets.dir.string(), targets.dir, "not a yarnvox report");
        targets.checkUnchanged();
        checkNoTemporaries(in);
    }
}

TEST_CASE("Output paths: a device, a FIFO or a link is never replaced, checked up front and again when published",
          "[output-paths]") {
    // The device is only looked at: checkOutputPath and nonRegularKind never
    // open it, and a PendingFile refused there has made no temporary yet.
    CHECK(yv::nonRegularKind("/dev/null") == "a device");
    CHECK_THROWS_WITH(yv::checkOutputPath("/dev/null", "-o", {}),
                      Contains("-o /dev/null: is a device, not a regular file: refusing to replace it"));
    CHECK_THROWS_WITH(yv::PendingFile("/dev/null"), Contains("cannot write /dev/null: it is a device"));
    for (const auto& e : fs::directory_iterator("/dev")) CHECK(e.path().filename().string().rfind("null.partial-", 0) != 0);

    yv::test::ScratchDir scratch("yv_pending_targets");
    const NotFiles targets(scratch.path, ".out");
    CHECK(yv::nonRegularKind(targets.fifo) == "a FIFO");
    CHECK(yv::nonRegularKind(targets.link) == "a symbolic link");
    CHECK(yv::nonRegularKind(targets.dir) == "a directory");
    CHECK(yv::nonRegularKind(targets.linked) == "");
    CHECK(yv::nonRegularKind(scratch.path / "absent") == "");
    const std::vector<std::uint8_t> bytes = {1, 2, 3};
    for (const fs::path& p : {targets.fifo, targets.link, targets.dir})
        CHECK_THROWS_WITH(yv::writeFileAtomically(p.string(), bytes), Contains("cannot write " + p.string() + ": it is a"));

    // A target that became a FIFO while the file was written: refused at the rename.
    const fs::path late = scratch.path / "late.out";
    {
        yv::PendingFile file(late.string());
        file.append(bytes);
        REQUIRE(::mkfifo(late.c_str(), 0600) == 0);
        CHECK_THROWS_WITH(file.publish(), Contains("cannot write " + late.string() + ": it is a FIFO"));
    }
    CHECK(fs::is_fifo(fs::symlink_status(late)));
    targets.checkUnchanged();
    checkNoTemporaries(scratch.path);

    // A regular file is replaced as before.
    yv::writeFileAtomically(targets.linked.string(), bytes);
    CHECK(fs::file_size(targets.linked) == 3);
}
