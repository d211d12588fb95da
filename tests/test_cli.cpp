// The yarnvox binary end to end: exit codes, messages, files left behind.
#include "core/json_fields.h"
#include "gpu/egl_context.h"
#include "run_cli.h"
#include "test_helpers.h"
#include "vdb_bytes.h"

#include <catch2/catch.hpp>

#include <openvdb/openvdb.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;

namespace {

using yv::test::RunResult;

RunResult run_shell(const std::string& line) { return yv::test::runShell(line); }
RunResult run(const std::string& args) { return yv::test::runYarnvox(args); }

fs::path scratch(const std::string& name) {
    return yv::test::processScratchDir("yv_cli_test") / name;
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
    // Level 0 and the preview pyramid: a grid 80 voxels long has level 3 only
    // (getGrids lists them by name).
    REQUIRE(grids->size() == 4);
    CHECK(grids->at(0)->getName() == "density");
    CHECK(grids->at(1)->getName() == "density_lod3");
    CHECK(grids->at(2)->getName() == "orientation");
    CHECK(grids->at(3)->getName() == "orientation_lod3");
    CHECK(grids->at(0)->activeVoxelCount() > 100);
    CHECK(grids->at(1)->activeVoxelCount() > 0);
}

TEST_CASE("CLI: YV_TRACE writes a timeline of the run's threads, and only when asked", "[cli]") {
    const fs::path bcc = scratch("trace.bcc"), vdb = scratch("trace.vdb"), trace = scratch("trace.json");
    REQUIRE(run("gen --pattern plain --crossings 16 -o " + bcc.string()).exitCode == 0);
    const std::string voxelize = "voxelize " + bcc.string() + " -o " + vdb.string() + " --backend cpu --resolution 48 --quiet";
    fs::remove(trace);
    RunResult plain = run(voxelize);
    INFO(plain.output);
    REQUIRE(plain.exitCode == 0);
    CHECK(!fs::exists(trace));

    fs::remove(vdb);
    RunResult traced = run_shell("YV_TRACE=" + trace.string() + " " + std::string(YV_BINARY_DIR) + "/yarnvox " + voxelize);
    INFO(traced.output);
    REQUIRE(traced.exitCode == 0);
    REQUIRE(fs::exists(vdb));
    REQUIRE(fs::exists(trace));
    std::ifstream in(trace);
    const std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    CHECK(json.rfind("{", 0) == 0);
    CHECK(json.find("\"traceEvents\": [") != std::string::npos);
    // The stages on the command's thread, a region on a writer thread, the file's chunks.
    for (const char* name : {"\"read\"", "\"slices\"", "\"voxelize\"", "\"write\"", "\"write a region\"",
                             "\"encode leaves\"", "\"write the file in chunks\"", "\"fsync\""})
        CHECK(json.find(std::string("\"name\": ") + name) != std::string::npos);
    CHECK(json.find("\"tid\": 1") != std::string::npos); // a thread besides the command's

    // A timeline that cannot be written is a warning, never the run's failure.
    fs::remove(vdb);
    RunResult unwritable = run_shell("YV_TRACE=" + scratch("no-such-dir/t.json").string() + " " +
                                     std::string(YV_BINARY_DIR) + "/yarnvox " + voxelize);
    CHECK(unwritable.exitCode == 0);
    CHECK(unwritable.output.find("warning: YV_TRACE: cannot write") != std::string::npos);
    CHECK(fs::exists(vdb));
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

namespace {

struct DensityRange {
    double max = 0.0, mass = 0.0;
    std::string overlap;
};

DensityRange readDensity(const fs::path& vdb) {
    openvdb::initialize();
    openvdb::io::File file(vdb.string());
    file.open();
    auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density"));
    const auto meta = file.getMetadata();
    file.close();
    REQUIRE(grid);
    DensityRange r;
    r.overlap = meta->metaValue<std::string>("overlap");
    for (auto it = grid->cbeginValueOn(); it; ++it) {
        r.max = std::max(r.max, double(*it));
        r.mass += *it;
    }
    const double h = grid->voxelSize()[0];
    r.mass *= h * h * h;
    return r;
}

double jsonNumber(const std::string& json, const std::string& key) {
    const std::size_t at = json.find("\"" + key + "\"");
    REQUIRE(at != std::string::npos);
    return std::stod(json.substr(json.find(':', at) + 1));
}

std::string readText(const fs::path& p) {
    std::ifstream in(p);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

} // namespace

TEST_CASE("CLI: --overlap clamp keeps voxels at 1, sum keeps the sums, --stats says how much was above", "[cli]") {
    // A twill cylinder of thick yarns: warp and weft interpenetrate at crossings.
    const fs::path bcc = scratch("twill.bcc");
    REQUIRE(run("gen --pattern twill --shape cylinder --crossings 64 --yarn-radius 0.45 -o " + bcc.string()).exitCode == 0);
    DensityRange range[2];
    std::string stats[2];
    const char* modes[2] = {"clamp", "sum"};
    for (int i = 0; i < 2; ++i) {
        const fs::path vdb = scratch(std::string("twill-") + modes[i] + ".vdb"), json = scratch("twill.json");
        // Float values: the stats' fibre volume (of the floats) is compared with the file's below.
        const RunResult r = run("voxelize " + bcc.string() + " -o " + vdb.string() + " --backend cpu --resolution 96 " +
                                "--cross-section disk --precision float --overlap " + modes[i] + " --stats " +
                                json.string());
        INFO(r.output);
        REQUIRE(r.exitCode == 0);
        // More than a trace of the fibre overlaps: the summary line says so.
        CHECK(r.output.find("overlap:") != std::string::npos);
        range[i] = readDensity(vdb);
        stats[i] = readText(json);
    }
    CHECK(range[0].overlap == "clamp");
    CHECK(range[1].overlap == "sum");
    CHECK(range[0].max <= 1.0);
    CHECK(range[1].max > 1.2);
    const double over = jsonNumber(stats[0], "voxels_over_one"), share = jsonNumber(stats[0], "mass_share_over_one");
    CHECK(over > 0);
    CHECK(over == jsonNumber(stats[1], "voxels_over_one"));
    // What clamping removed is the excess the stats report.
    CHECK(range[1].mass - range[0].mass == Approx(share * range[1].mass).epsilon(1e-3));
    CHECK(jsonNumber(stats[0], "fiber_volume") == Approx(range[0].mass).epsilon(1e-6));
}

TEST_CASE("CLI: --stats of a GL run times the raster and its placing, and counts what was drawn", "[cli][gl]") {
    YV_REQUIRE_GL();
    const fs::path bcc = scratch("gl-stats.bcc"), vdb = scratch("gl-stats.vdb"), stats = scratch("gl-stats.json");
    REQUIRE(run("gen --pattern twill --crossings 40 --shape cylinder -o " + bcc.string()).exitCode == 0);
    const RunResult r = run("voxelize " + bcc.string() + " -o " + vdb.string() +
                            " --backend gl --resolution 64 --quiet --stats " + stats.string());
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    const std::string json = readText(stats);
    INFO(json);
    const double raster = jsonNumber(json, "gpu_raster_seconds"), place = jsonNumber(json, "gpu_place_seconds");
    CHECK(place > 0.0);
    CHECK(place <= raster); // the placing is a part of the raster's time
    CHECK(jsonNumber(json, "slices_drawn") >= jsonNumber(json, "slices")); // a slice is drawn in every region it reaches
    CHECK(jsonNumber(json, "sample_items") > 0.0);
    CHECK(jsonNumber(json, "fragments") > 0.0);
}

TEST_CASE("CLI: --sample-items raster and compute write the same bytes and say which ran and go with gl only", "[cli][gl]") {
    YV_REQUIRE_GL();
    const fs::path bcc = scratch("items.bcc");
    REQUIRE(run("gen --pattern twill --crossings 40 --shape cylinder -o " + bcc.string()).exitCode == 0);
    std::map<std::string, std::vector<std::uint8_t>> bytes;
    for (const std::string items : {"raster", "compute", "auto"}) {
        const fs::path vdb = scratch("items-" + items + ".vdb"), stats = scratch("items-" + items + ".json");
        const RunResult r = run("voxelize " + bcc.string() + " -o " + vdb.string() +
                                " --backend gl --resolution 64 --quiet --sample-items " + items + " --stats " +
                                stats.string());
        INFO(items << ": " << r.output);
        REQUIRE(r.exitCode == 0);
        const std::string json = readText(stats);
        // The raster draws triangles on llvmpipe, point sprites on a GPU.
        const bool llvmpipe = json.find("llvmpipe") != std::string::npos;
        const std::string expected = items != "raster" ? "compute" : llvmpipe ? "triangle" : "point";
        CHECK(json.find("\"slice_primitive\": \"" + expected + "\"") != std::string::npos);
        CHECK(jsonNumber(json, "sample_items") > 0.0);
        bytes[items] = yv::test::vdbBytesWithoutUuid(vdb);
    }
    CHECK(bytes["raster"] == bytes["compute"]);
    CHECK(bytes["raster"] == bytes["auto"]);
    for (const std::string refused : {"--backend cpu", "--method dense"}) {
        const fs::path vdb = scratch("items-refused.vdb");
        const RunResult r = run("voxelize " + bcc.string() + " -o " + vdb.string() + " --resolution 64 " + refused +
                                " --sample-items compute");
        INFO(refused << ": " << r.output);
        CHECK(r.exitCode != 0);
        CHECK(r.output.find("--sample-items compute: goes with the GL backend's sparse method") != std::string::npos);
        CHECK_FALSE(fs::exists(vdb));
    }
    // --backend auto on a machine without a GPU runs the CPU backend, which
    // says that it finds no items rather than leaving the option unheard.
    const fs::path autoStats = scratch("items-auto-backend.json");
    const RunResult onAuto = run("voxelize " + bcc.string() + " -o " + scratch("items-auto-backend.vdb").string() +
                                 " --resolution 64 --sample-items compute --stats " + autoStats.string());
    INFO(onAuto.output);
    REQUIRE(onAuto.exitCode == 0);
    const bool ranOnCpu = readText(autoStats).find("\"backend\": \"cpu\"") != std::string::npos;
    CHECK((onAuto.output.find("warning: --sample-items compute: the CPU backend runs here") != std::string::npos) ==
          ranOnCpu);
    const RunResult bad = run("voxelize " + bcc.string() + " -o " + scratch("items-bad.vdb").string() +
                              " --resolution 64 --sample-items points");
    CHECK(bad.exitCode != 0);
    CHECK(bad.output.find("--sample-items") != std::string::npos);
}

TEST_CASE("CLI: slices follow the voxel size by default, and a coarse explicit spacing warns", "[cli]") {
    const fs::path bcc = scratch("plain.bcc"), vdb = scratch("plain.vdb"), json = scratch("plain.json");
    REQUIRE(run("gen --pattern plain --crossings 16 -o " + bcc.string()).exitCode == 0);
    std::uint64_t slices[2] = {0, 0};
    const int resolutions[2] = {64, 256};
    for (int i = 0; i < 2; ++i) {
        const RunResult r = run("voxelize " + bcc.string() + " -o " + vdb.string() + " --backend cpu --resolution " +
                                std::to_string(resolutions[i]) + " --stats " + json.string());
        INFO(r.output);
        REQUIRE(r.exitCode == 0);
        CHECK(r.output.find("warning") == std::string::npos);
        const std::string s = readText(json);
        slices[i] = static_cast<std::uint64_t>(jsonNumber(s, "slices"));
        // One slice per voxel along the yarn: the spacing is the voxel size.
        CHECK(jsonNumber(s, "slice_spacing") <= jsonNumber(s, "voxel_size") * 1.01);
    }
    CHECK(slices[1] > 3 * slices[0]);

    const RunResult coarse = run("voxelize " + bcc.string() + " -o " + vdb.string() +
                                 " --backend cpu --resolution 256 --slices-per-segment 2");
    INFO(coarse.output);
    REQUIRE(coarse.exitCode == 0);
    CHECK(coarse.output.find("warning: --slices-per-segment 2 places slices up to") != std::string::npos);
    CHECK(run("voxelize " + bcc.string() + " -o " + vdb.string() + " --slices-per-segment 2 --slice-spacing 0.1 --resolution 32")
              .exitCode != 0);
}

TEST_CASE("CLI: -o and --stats must name new or regular files, not the input, a directory or a link", "[cli]") {
    const fs::path bcc = scratch("guard.bcc"), dir = scratch("guard-dir"), link = scratch("guard-link.vdb");
    REQUIRE(run("gen --pattern plain --crossings 16 -o " + bcc.string()).exitCode == 0);
    const std::string before = readText(bcc);
    fs::create_directories(dir);
    fs::remove(link);
    fs::create_symlink(scratch("elsewhere.vdb"), link);
    const std::string common = " --backend cpu --resolution 32";
    struct Case {
        std::string args, says;
    };
    const Case cases[] = {
        {"-o " + bcc.string(), "same file as"},
        {"-o " + dir.string(), "is a directory"},
        {"-o " + link.string(), "is a symbolic link"},
        {"-o /dev/null", "is a device"},
        {"-o " + scratch("no-such-dir").string() + "/out.vdb", "does not exist"},
        {"-o " + scratch("guard.vdb").string() + " --stats " + bcc.string(), "same file as"},
        {"-o " + scratch("guard.vdb").string() + " --stats " + scratch("guard.vdb").string(), "same file as -o"},
    };
    for (const Case& c : cases) {
        const RunResult r = run("voxelize " + bcc.string() + " " + c.args + common);
        INFO(c.args << "\n" << r.output);
        CHECK(r.exitCode == 1);
        CHECK(r.output.find(c.says) != std::string::npos);
        CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 1);
    }
    CHECK(readText(bcc) == before);
    CHECK(fs::is_directory(dir));
    CHECK(fs::is_symlink(link));
    CHECK_FALSE(fs::exists(scratch("elsewhere.vdb")));
}

TEST_CASE("CLI: a .vdb write that fails (the file-size limit, as a full disk) is an error, not a finished file", "[cli]") {
    const fs::path bcc = scratch("full.bcc"), vdb = scratch("full.vdb");
    REQUIRE(run("gen --pattern knit --crossings 400 -o " + bcc.string()).exitCode == 0);
    fs::remove(vdb);
    // The child runs with a 64 KiB file-size limit (SIGXFSZ ignored, so writes
    // past it fail with EFBIG, the way they fail with ENOSPC on a full disk):
    // the output fails, or with the writer's scratch space all in its file
    // (YV_SPILL_MEMORY_MB=0), the scratch file first.
    for (const bool scratchInFile : {false, true}) {
        const std::string cmd = "ulimit -f 64; trap '' XFSZ; " +
                                std::string(scratchInFile ? "export YV_SPILL_MEMORY_MB=0; " : "") + "exec " +
                                std::string(YV_BINARY_DIR) + "/yarnvox voxelize " + bcc.string() + " -o " + vdb.string() +
                                " --backend cpu --resolution 256";
        const RunResult r = run_shell(cmd);
        INFO((scratchInFile ? "scratch space in its file: " : "scratch space in memory: ") << r.output);
        CHECK(r.exitCode == 1);
        CHECK(r.output.find("cannot write the OpenVDB file") != std::string::npos);
        CHECK(r.output.find("wrote") == std::string::npos);
        CHECK_FALSE(fs::exists(vdb));
        std::size_t leftovers = 0;
        for (const auto& e : fs::directory_iterator(vdb.parent_path()))
            leftovers += e.path().filename().string().rfind("full.vdb.partial", 0) == 0;
        CHECK(leftovers == 0);
    }
    // Without the limit the same run writes a file OpenVDB reads.
    REQUIRE(run("voxelize " + bcc.string() + " -o " + vdb.string() + " --backend cpu --resolution 256").exitCode == 0);
    CHECK(fs::file_size(vdb) > 64 * 1024);
    CHECK(readDensity(vdb).mass > 0.0);
}

TEST_CASE("CLI: several garments and --list write one output each into the -o directory", "[cli]") {
    const fs::path dir = fs::temp_directory_path() / ("yv_cli_frames_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir / "sub");
    const fs::path a = dir / "a.bcc", b = dir / "sub" / "b.bcc";
    REQUIRE(run("gen --pattern plain --crossings 8 -o " + a.string()).exitCode == 0);
    REQUIRE(run("gen --pattern knit --crossings 8 -o " + b.string()).exitCode == 0);
    {
        std::ofstream list(dir / "frames.txt");
        list << "# frames, relative to this file\n\n  sub/b.bcc  \n";
    }
    const std::string opts = " --backend cpu --resolution 48 --quiet";
    // Each output is the file a run of its garment alone writes.
    REQUIRE(run("voxelize " + a.string() + " -o " + (dir / "alone-a.vdb").string() + opts).exitCode == 0);
    REQUIRE(run("voxelize " + b.string() + " -o " + (dir / "alone-b.vdb").string() + opts).exitCode == 0);
    const fs::path out = dir / "out", stats = dir / "stats";
    const RunResult both = run("voxelize " + a.string() + " --list " + (dir / "frames.txt").string() + " -o " +
                               out.string() + " --stats " + stats.string() + opts);
    INFO(both.output);
    REQUIRE(both.exitCode == 0);
    const auto bytes = [](const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        REQUIRE(s.size() > 57);
        std::fill(s.begin() + 21, s.begin() + 57, '\0'); // OpenVDB's per-file UUID
        return s;
    };
    CHECK(bytes(out / "a.vdb") == bytes(dir / "alone-a.vdb"));
    CHECK(bytes(out / "b.vdb") == bytes(dir / "alone-b.vdb"));
    CHECK(fs::exists(stats / "a.json"));
    CHECK(fs::exists(stats / "b.json"));

    // Refused before any work, each in one line that names the problem.
    fs::copy_file(a, dir / "sub" / "a.bcc");
    const RunResult clash = run("voxelize " + a.string() + " " + (dir / "sub" / "a.bcc").string() + " -o " +
                                (dir / "clash").string() + opts);
    CHECK(clash.exitCode == 1);
    CHECK_THAT(clash.output, Catch::Contains("would both write") && Catch::Contains("a.vdb"));
    CHECK_FALSE(fs::exists(dir / "clash" / "a.vdb"));
    {
        std::ofstream list(dir / "bad.txt");
        list << "sub/b.bcc\nmissing.bcc\n";
    }
    const RunResult badList = run("voxelize --list " + (dir / "bad.txt").string() + " -o " + (dir / "bad").string() + opts);
    CHECK(badList.exitCode == 1);
    CHECK_THAT(badList.output, Catch::Contains("bad.txt, line 2") && Catch::Contains("missing.bcc"));
    const RunResult none = run("voxelize -o " + (dir / "none.vdb").string() + opts);
    CHECK(none.exitCode == 1);
    CHECK_THAT(none.output, Catch::Contains("give a garment file"));
    fs::remove_all(dir);
}

TEST_CASE("CLI: YV_WRITER_THREADS sets the writer's threads and keeps the bytes, a bad count is one line", "[cli]") {
    const fs::path bcc = scratch("writers.bcc");
    REQUIRE(run("gen --pattern plain --crossings 64 -o " + bcc.string()).exitCode == 0);
    // Small passes, so that the run has regions enough for every writer.
    const auto voxelize = [&](const std::string& threads, const fs::path& vdb, const fs::path& trace) {
        fs::remove(vdb);
        return run_shell("YV_WRITER_THREADS=" + threads + " YV_TRACE=" + trace.string() + " " +
                         std::string(YV_BINARY_DIR) + "/yarnvox voxelize " + bcc.string() + " -o " + vdb.string() +
                         " --backend cpu --resolution 96 --fragment-budget 20000 --quiet");
    };
    // The threads that wrote a region, from the timeline.
    const auto writerThreadsIn = [](const fs::path& trace) {
        std::ifstream in(trace);
        const yv::Json json = yv::Json::parse(in);
        std::set<int> tids;
        for (const yv::Json& e : json["traceEvents"])
            if (e.value("name", "") == "write a region") tids.insert(e["tid"].get<int>());
        return tids.size();
    };
    const fs::path one = scratch("writers-1.vdb"), three = scratch("writers-3.vdb");
    const RunResult a = voxelize("1", one, scratch("writers-1.json"));
    INFO(a.output);
    REQUIRE(a.exitCode == 0);
    const RunResult b = voxelize("3", three, scratch("writers-3.json"));
    INFO(b.output);
    REQUIRE(b.exitCode == 0);
    CHECK(writerThreadsIn(scratch("writers-1.json")) == 1);
    const std::size_t used = writerThreadsIn(scratch("writers-3.json"));
    CHECK(used >= 2);
    CHECK(used <= 3);
    CHECK(yv::test::vdbBytesWithoutUuid(one) == yv::test::vdbBytesWithoutUuid(three));

    for (const char* bad : {"0", "4x", "300", ""}) {
        const fs::path vdb = scratch("writers-bad.vdb");
        const RunResult r = voxelize(bad, vdb, scratch("writers-bad.json"));
        INFO(bad << ": " << r.output);
        CHECK(r.exitCode != 0);
        CHECK(r.output.find(std::string("YV_WRITER_THREADS=") + bad + ": not a count of threads") != std::string::npos);
        CHECK_FALSE(fs::exists(vdb));
    }
}

TEST_CASE("CLI: YV_PIPELINE_REGIONS is taken and a bad count is one line with nothing written", "[cli]") {
    const fs::path bcc = scratch("pipeline-regions.bcc");
    REQUIRE(run("gen --pattern plain --crossings 64 -o " + bcc.string()).exitCode == 0);
    const auto voxelize = [&](const std::string& regions, const fs::path& vdb) {
        fs::remove(vdb);
        return run_shell("YV_PIPELINE_REGIONS=" + regions + " " + std::string(YV_BINARY_DIR) + "/yarnvox voxelize " +
                         bcc.string() + " -o " + vdb.string() + " --backend cpu --resolution 64 --quiet");
    };
    const fs::path vdb = scratch("pipeline-regions.vdb");
    const RunResult good = voxelize("4", vdb);
    INFO(good.output);
    CHECK(good.exitCode == 0);
    CHECK(fs::exists(vdb));
    for (const char* bad : {"0", "3.5", "70000", "", "-2"}) {
        const RunResult r = voxelize(bad, vdb);
        INFO(bad << ": " << r.output);
        CHECK(r.exitCode != 0);
        CHECK(r.output.find(std::string("YV_PIPELINE_REGIONS=") + bad + ": not a count of regions (1 to 65536)") !=
              std::string::npos);
        CHECK_FALSE(fs::exists(vdb));
    }
}

TEST_CASE("CLI: YV_SPILL_MEMORY_MB moves the writer's scratch space between memory and file with the same bytes, a "
          "bad count is one line",
          "[cli]") {
    const fs::path bcc = scratch("spill-memory.bcc");
    REQUIRE(run("gen --pattern plain --crossings 64 -o " + bcc.string()).exitCode == 0);
    // Many small regions, so that their leaves are streamed: about 3 MB of records.
    const auto voxelize = [&](const std::string& env, const fs::path& vdb) {
        fs::remove(vdb);
        return run_shell(env + " " + std::string(YV_BINARY_DIR) + "/yarnvox voxelize " + bcc.string() + " -o " +
                         vdb.string() + " --backend cpu --resolution 192 --fragment-budget 20000 --quiet --stats " +
                         vdb.string() + ".json");
    };
    std::vector<std::vector<std::uint8_t>> bytes;
    for (const char* env : {"YV_SPILL_MEMORY_MB=0", "YV_SPILL_MEMORY_MB=2", "YV_SPILL_MEMORY_MB=1024", ""}) {
        const fs::path vdb = scratch("spill-memory.vdb");
        const RunResult r = voxelize(env, vdb);
        INFO(env << ": " << r.output);
        REQUIRE(r.exitCode == 0);
        std::ifstream in(vdb.string() + ".json");
        const yv::Json stats = yv::Json::parse(in);
        // Past 2.5 MiB, so that with 2 MiB in memory some records are in the file.
        CHECK(stats["vdb_streamed_bytes"].get<std::uint64_t>() > (std::uint64_t(5) << 19));
        bytes.push_back(yv::test::vdbBytesWithoutUuid(vdb));
    }
    for (std::size_t i = 1; i < bytes.size(); ++i) CHECK(bytes[i] == bytes[0]);
    for (const char* bad : {"-1", "2G", ""}) {
        const fs::path vdb = scratch("spill-memory-bad.vdb");
        const RunResult r = voxelize(std::string("YV_SPILL_MEMORY_MB=") + bad, vdb);
        INFO(bad << ": " << r.output);
        CHECK(r.exitCode != 0);
        CHECK(r.output.find(std::string("YV_SPILL_MEMORY_MB=") + bad + ": not a count of MB") != std::string::npos);
        CHECK_FALSE(fs::exists(vdb));
    }
}
