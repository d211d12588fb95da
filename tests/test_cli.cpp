// The yarnvox binary end to end: exit codes, messages, files left behind.
#include <catch2/catch.hpp>

#include <openvdb/openvdb.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;

namespace {

struct RunResult {
    int exitCode;
    std::string output; // stdout and stderr
};

RunResult run(const std::string& args) {
    const std::string cmd = std::string(YV_BINARY_DIR) + "/yarnvox " + args + " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    REQUIRE(pipe);
    std::string out;
    std::array<char, 4096> buf;
    while (std::size_t n = std::fread(buf.data(), 1, buf.size(), pipe)) out.append(buf.data(), n);
    const int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

fs::path scratch(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / "yv_cli_test";
    fs::create_directories(dir);
    return dir / name;
}

} // namespace

TEST_CASE("CLI: gen then voxelize writes a readable .vdb and stats", "[cli]") {
    const fs::path bcc = scratch("knit.bcc"), vdb = scratch("knit.vdb"), stats = scratch("knit.json");
    fs::remove(vdb);
    RunResult gen = run("gen --pattern knit --crossings 40 --shape cylinder --seed 2 -o " + bcc.string());
    REQUIRE(gen.exitCode == 0);
    RunResult vox = run("voxelize " + bcc.string() + " -o " + vdb.string() +
                        " --backend cpu --resolution 64 --twist 1 --stats " + stats.string());
    INFO(vox.output);
    REQUIRE(vox.exitCode == 0);
    CHECK(vox.output.find(vdb.string()) != std::string::npos);
    REQUIRE(fs::exists(vdb));
    std::ifstream in(stats);
    const std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    CHECK(json.find("\"active_voxels\"") != std::string::npos);
    CHECK(json.find("\"peak_host_bytes\"") != std::string::npos);

    openvdb::initialize();
    openvdb::io::File file(vdb.string());
    file.open();
    auto grids = file.getGrids();
    file.close();
    REQUIRE(grids->size() == 2);
    CHECK(grids->at(0)->getName() == "density");
    CHECK(grids->at(1)->getName() == "orientation");
    CHECK(grids->at(0)->activeVoxelCount() > 100);
}

TEST_CASE("CLI: bad input gives one clear line, a non-zero exit and no output", "[cli]") {
    const fs::path bad = scratch("bad.bcc"), vdb = scratch("bad.vdb");
    fs::remove(vdb);
    {
        std::ofstream f(bad, std::ios::binary);
        f << "BCC\x44" << "C0";
    }
    RunResult r = run("voxelize " + bad.string() + " -o " + vdb.string() + " --backend cpu --resolution 32");
    CHECK(r.exitCode != 0);
    CHECK(r.output.find("bad.bcc") != std::string::npos);
    CHECK(r.output.find("byte") != std::string::npos);
    CHECK_FALSE(fs::exists(vdb));
    CHECK_FALSE(fs::exists(vdb.string() + ".partial"));

    RunResult missing = run("voxelize " + scratch("none.bcc").string() + " -o " + vdb.string());
    CHECK(missing.exitCode != 0);

    RunResult pattern = run("gen --pattern lace -o " + scratch("x.bcc").string());
    CHECK(pattern.exitCode != 0);
    CHECK(pattern.output.find("plain") != std::string::npos);
}

TEST_CASE("CLI: --help of every subcommand names units and defaults", "[cli]") {
    RunResult v = run("voxelize --help");
    CHECK(v.exitCode == 0);
    CHECK(v.output.find("--resolution") != std::string::npos);
    CHECK(v.output.find("world units") != std::string::npos);
    CHECK(v.output.find("radians per world unit") != std::string::npos);
    RunResult g = run("gen --help");
    CHECK(g.exitCode == 0);
    CHECK(g.output.find("--crossings") != std::string::npos);
}
