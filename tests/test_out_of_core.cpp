// Zoom regions and the work directory: the same tree whatever the budget,
// and a killed run resumed to the same result.
#include "garment/cross_section.h"
#include "garment/generate.h"
#include "gpu/egl_context.h"
#include "gpu/gl_voxelizer.h"
#include "test_helpers.h"
#include "vdb_bytes.h"

#include <catch2/catch.hpp>
#include <openvdb/openvdb.h>

#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

using namespace yv;
namespace fs = std::filesystem;

namespace {

class Collect : public RegionSink {
  public:
    void consume(const ZoomRegion&, PackedBricks&& bricks) override {
        all.push_back(std::move(bricks));
        ++regions;
    }
    std::vector<PackedBricks> all;
    std::uint64_t regions = 0;
};

BrickVolume runWithBudget(const SlicePlan& plan, const CrossSection& xs, const VoxelGrid& grid, std::uint64_t budget,
                          GlVoxelizeCounters& counters) {
    GlVoxelizeSettings s;
    s.fragmentCapacity = budget;
    s.brickResolve = BrickResolve::Gpu; // Collect takes packed bricks
    const GlContext context;
    GlBackend backend(plan, xs, grid, s, context);
    const ZoomPlan zoom = planZoomRegions(plan, grid, xs, {backend.fragmentBudget(), backend.maxRegionSize(), 1});
    Collect sink;
    backend.run(zoom.regions, sink);
    counters = backend.counters();
    return unpackVolume(grid, Reduce::Mean, sink.all);
}

} // namespace

TEST_CASE("Past the 2 GB texture limit, 64+ zoom regions give exactly the tree of one big budget", "[gl][out-of-core]") {
    YV_REQUIRE_GL();
    GenerateOptions g;
    g.pattern = WeavePattern::Twill;
    g.shape = GarmentShape::Cylinder; // a tall, round grid: 1080 x 1072 x 2056 voxels at 2048
    g.crossings = 64;
    const Garment garment = generateGarment(g);
    SliceOptions opt;
    // Thin yarns in a big grid: every voxel a yarn crosses is filled, so the
    // yarn volume (not the grid) sets the work llvmpipe has to get through
    // (15 M fragments a run, about 30 s each here).
    opt.radius = garment.yarnRadius / 8;
    opt.twist = 2.0;
    opt.slicesPerSegment = 2; // few slices, each slab split over the voxels it spans
    const SlicePlan plan = planSlices(garment, opt);
    const VoxelGrid grid = makeGrid(plan, 2048, 0.0);
    // One byte per voxel would already be past a 2 GB 3D texture.
    REQUIRE(grid.voxelCount() > (std::uint64_t(2) << 30));
    const CrossSection xs = makeDiskCrossSection();

    GlVoxelizeCounters big, small;
    const BrickVolume a = runWithBudget(plan, xs, grid, 0, big);
    const BrickVolume b = runWithBudget(plan, xs, grid, 300000, small);
    INFO("regions: big budget " << big.plannedRegions << ", small " << small.plannedRegions << "; overflows "
                                << small.overflows);
    CHECK(big.plannedRegions >= 64);
    CHECK(small.plannedRegions >= 4 * big.plannedRegions);
    CHECK(small.fragments == big.fragments);
    REQUIRE(a.bricks.size() == b.bricks.size());
    std::size_t differing = 0;
    for (std::size_t i = 0; i < a.bricks.size(); ++i)
        differing += a.bricks[i].key != b.bricks[i].key || a.bricks[i].activeMask != b.bricks[i].activeMask ||
                     std::memcmp(a.bricks[i].density.data(), b.bricks[i].density.data(), 4 * kBrickVoxels) != 0 ||
                     std::memcmp(a.bricks[i].orientation.data(), b.bricks[i].orientation.data(), 12 * kBrickVoxels) != 0;
    CHECK(differing == 0);
    CHECK(a.activeVoxelCount() > 1000000);
}

namespace {

std::string yarnvox() { return std::string(YV_BINARY_DIR) + "/yarnvox"; }

fs::path scratchDir(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("yv_ooc_" + std::to_string(getpid())) / name;
    fs::remove_all(dir);
    fs::create_directories(dir.parent_path());
    return dir;
}

int runQuiet(const std::string& args) { return std::system((yarnvox() + " " + args + " >/dev/null 2>&1").c_str()); }

std::string readFile(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// The same .vdb bytes, OpenVDB's per-file UUID aside.
bool sameVdbBytes(const fs::path& a, const fs::path& b) {
    return test::vdbBytesWithoutUuid(a) == test::vdbBytesWithoutUuid(b);
}

std::size_t regionFiles(const fs::path& dir) {
    std::size_t n = 0;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
        n += e.path().extension() == ".yvb";
    return n;
}

} // namespace

TEST_CASE("A run killed part-way and resumed gives the same .vdb, and damaged regions are recomputed", "[gl][out-of-core][cli]") {
    // Both backends are region rasterizers feeding the same store.
    const std::string backend = GENERATE(as<std::string>(), "gl", "cpu");
    if (backend == "gl") YV_REQUIRE_GL();
    INFO("--backend " << backend);
    const fs::path dir = scratchDir("resume-" + backend);
    fs::create_directories(dir);
    const fs::path bcc = dir / "g.bcc";
    REQUIRE(runQuiet("gen --pattern twill --shape cylinder --crossings 64 -o " + bcc.string()) == 0);
    // Thin yarns keep the filled volume (and llvmpipe's work) small; a small
    // fragment budget still makes hundreds of regions (348 on the CPU backend).
    const std::string common = " --backend " + backend +
                               " --resolution 512 --yarn-radius 0.1 --slices-per-segment 2 --twist 2 --fragment-budget 12500 --quiet ";

    // The reference: one uninterrupted run.
    const fs::path reference = dir / "reference.vdb";
    REQUIRE(runQuiet("voxelize " + bcc.string() + " -o " + reference.string() + common + "--work-dir " +
                     (dir / "work-ref").string()) == 0);
    const std::size_t regions = regionFiles(dir / "work-ref");
    REQUIRE(regions > 20);

    // Killed once a few regions are on disk.
    const fs::path work = dir / "work", out = dir / "out.vdb";
    const pid_t child = fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        execl(yarnvox().c_str(), "yarnvox", "voxelize", bcc.c_str(), "-o", out.c_str(), "--backend", backend.c_str(), "--resolution", "512",
              "--yarn-radius", "0.1", "--slices-per-segment", "2", "--twist", "2", "--fragment-budget", "12500", "--quiet", "--work-dir",
              work.c_str(), static_cast<char*>(nullptr));
        _exit(127);
    }
    while (regionFiles(work) < regions / 4) {
        int status = 0;
        if (waitpid(child, &status, WNOHANG) == child) FAIL("the run ended before it could be killed");
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    kill(child, SIGKILL);
    int status = 0;
    waitpid(child, &status, 0);
    REQUIRE(WIFSIGNALED(status));
    CHECK_FALSE(fs::exists(out));
    const std::size_t before = regionFiles(work);
    CHECK(before < regions);

    // Resumed: the regions on disk are re-used, the rest computed.
    const fs::path stats = dir / "stats.json";
    REQUIRE(runQuiet("voxelize " + bcc.string() + " -o " + out.string() + common + "--work-dir " + work.string() +
                     " --resume --stats " + stats.string()) == 0);
    CHECK(sameVdbBytes(reference, out));
    std::string json = readFile(stats);
    CHECK(json.find("\"regions_resumed\": " + std::to_string(before)) != std::string::npos);

    // A damaged region file is found, recomputed, and the result is the same again.
    fs::path victim;
    for (const auto& e : fs::directory_iterator(work))
        if (e.path().extension() == ".yvb" && fs::file_size(e.path()) > 200) victim = e.path();
    REQUIRE(!victim.empty());
    {
        std::fstream f(victim, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(static_cast<std::streamoff>(fs::file_size(victim) - 10));
        f.put('\x5a');
    }
    const fs::path again = dir / "again.vdb";
    REQUIRE(runQuiet("voxelize " + bcc.string() + " -o " + again.string() + common + "--work-dir " + work.string() +
                     " --resume --stats " + stats.string()) == 0);
    CHECK(sameVdbBytes(reference, again));
    json = readFile(stats);
    CHECK(json.find("\"regions_damaged_recomputed\": 1") != std::string::npos);
    CHECK(json.find("\"regions_resumed\": " + std::to_string(regions - 1)) != std::string::npos);

    // `yarnvox merge` of the finished work dir writes the same file once more.
    const fs::path merged = dir / "merged.vdb";
    REQUIRE(runQuiet("merge " + work.string() + " -o " + merged.string()) == 0);
    CHECK(sameVdbBytes(reference, merged));
    fs::remove_all(dir.parent_path());
}

TEST_CASE("Resuming a work dir made by another yarnvox version or sampling code is refused, saying which, deleting nothing", "[gl][out-of-core][cli]") {
    YV_REQUIRE_GL();
    const fs::path dir = scratchDir("other-version");
    fs::create_directories(dir);
    const fs::path bcc = dir / "g.bcc", work = dir / "work", out = dir / "out.vdb";
    REQUIRE(runQuiet("gen --pattern plain --crossings 8 -o " + bcc.string()) == 0);
    const std::string args = "voxelize " + bcc.string() + " -o " + out.string() +
                             " --backend gl --resolution 64 --fragment-budget 50000 --quiet --work-dir " + work.string();
    REQUIRE(runQuiet(args) == 0);
    const std::size_t regions = regionFiles(work);
    REQUIRE(regions > 0);
    const std::string manifest = readFile(work / "manifest");
    REQUIRE(manifest.find(std::string("\"yarnvox_version\": \"") + YV_VERSION + "\"") != std::string::npos);
    const std::string codeField = "\"sampling_code\": \"0x";
    const std::size_t code = manifest.find(codeField);
    REQUIRE(code != std::string::npos);
    fs::remove(out);

    const auto resumeWith = [&](const std::string& text) {
        std::ofstream(work / "manifest", std::ios::binary | std::ios::trunc) << text;
        const fs::path log = dir / "log.txt";
        const int rc = std::system((yarnvox() + " " + args + " --resume >" + log.string() + " 2>&1").c_str());
        CHECK(rc != 0);
        CHECK_FALSE(fs::exists(out));
        CHECK(regionFiles(work) == regions); // nothing deleted
        return readFile(log);
    };
    std::string older = manifest;
    older.replace(older.find(YV_VERSION, older.find("yarnvox_version")), std::strlen(YV_VERSION), "0.0.9");
    CHECK_THAT(resumeWith(older), Catch::Contains(std::string("made by yarnvox 0.0.9, this is ") + YV_VERSION) &&
                                      Catch::Contains("use a fresh --work-dir"));
    std::string otherCode = manifest;
    const std::size_t digit = code + codeField.size(); // the first hex digit
    otherCode[digit] = otherCode[digit] == '0' ? '1' : '0';
    CHECK_THAT(resumeWith(otherCode), Catch::Contains("the sampling code differs"));

    // The work dir's own manifest back: it resumes (every region re-used).
    std::ofstream(work / "manifest", std::ios::binary | std::ios::trunc) << manifest;
    CHECK(runQuiet(args + " --resume") == 0);
    CHECK(fs::exists(out));

    // The same run on the other backend is another run (the two agree to
    // float precision, not bit for bit), and the refusal says why.
    std::string cpuArgs = args;
    cpuArgs.replace(cpuArgs.find("--backend gl"), std::strlen("--backend gl"), "--backend cpu");
    const fs::path log = dir / "backend.txt";
    CHECK(std::system((yarnvox() + " " + cpuArgs + " --resume >" + log.string() + " 2>&1").c_str()) != 0);
    CHECK_THAT(readFile(log), Catch::Contains("made with --backend gl, this run uses --backend cpu"));
    CHECK(regionFiles(work) == regions);
    fs::remove_all(dir.parent_path());
}

TEST_CASE("Without a work dir, regions go straight into the .vdb: the same file as through the store", "[gl][out-of-core][cli]") {
    const std::string backend = GENERATE(as<std::string>(), "gl", "cpu");
    if (backend == "gl") YV_REQUIRE_GL();
    INFO("--backend " << backend);
    const fs::path dir = scratchDir("in-memory-" + backend);
    fs::create_directories(dir);
    const fs::path bcc = dir / "g.bcc";
    REQUIRE(runQuiet("gen --pattern knit --shape cylinder --crossings 64 -o " + bcc.string()) == 0);
    // A small budget, so that many regions make up the volume either way.
    const std::string common = " --backend " + backend + " --resolution 192 --fragment-budget 60000 --quiet ";
    const fs::path direct = dir / "direct.vdb", stored = dir / "stored.vdb";
    REQUIRE(runQuiet("voxelize " + bcc.string() + " -o " + direct.string() + common + "--stats " +
                     (dir / "direct.json").string()) == 0);
    REQUIRE(runQuiet("voxelize " + bcc.string() + " -o " + stored.string() + common + "--work-dir " +
                     (dir / "work").string() + " --stats " + (dir / "stored.json").string()) == 0);
    CHECK(sameVdbBytes(direct, stored));
    CHECK_FALSE(fs::exists(direct.string() + ".work"));
    const std::string a = readFile(dir / "direct.json"), b = readFile(dir / "stored.json");
    CHECK(a.find("\"regions_to\": \"memory\"") != std::string::npos);
    CHECK(b.find("\"regions_to\": \"work dir\"") != std::string::npos);
    CHECK(regionFiles(dir / "work") > 4);
}

TEST_CASE("A work dir whose run metadata does not parse gives one line and exit 1 from merge, not an abort", "[cli]") {
    const fs::path dir = scratchDir("bad-metadata");
    fs::create_directories(dir);
    const fs::path bcc = dir / "g.bcc", work = dir / "work";
    REQUIRE(runQuiet("gen --pattern plain --crossings 16 -o " + bcc.string()) == 0);
    REQUIRE(runQuiet("voxelize " + bcc.string() + " -o " + (dir / "a.vdb").string() +
                     " --backend gl --resolution 32 --quiet --work-dir " + work.string()) == 0);
    // Valid JSON, but the resolution is no number.
    std::string manifest = readFile(work / "manifest");
    const std::string field = "\"resolution\": 32";
    const std::size_t at = manifest.find(field);
    REQUIRE(at != std::string::npos);
    manifest.replace(at, field.size(), "\"resolution\": \"x2\"");
    {
        std::ofstream out(work / "manifest", std::ios::binary | std::ios::trunc);
        out << manifest;
    }
    const std::string cmd = yarnvox() + " merge " + work.string() + " -o " + (dir / "b.vdb").string() + " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    REQUIRE(pipe);
    std::string output;
    char buf[4096];
    while (std::size_t n = std::fread(buf, 1, sizeof buf, pipe)) output.append(buf, n);
    const int status = pclose(pipe);
    INFO(output);
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 1);
    CHECK(output.find("yarnvox: error:") == 0);
    CHECK(output.find("\"resolution\": expected an integer") != std::string::npos);
    CHECK(std::count(output.begin(), output.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(dir / "b.vdb"));
}
