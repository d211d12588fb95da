// Bad input, end to end: every case builds its input in code, runs the binary
// (or the reader), and checks the exit code, that the message names the
// thing, and that no output was left. docs/reliability.md lists them.
#include "bcc.h"

#include "core/error.h"
#include "garment/catmull_rom.h"
#include "garment/curve_check.h"
#include "garment/radius_estimate.h"
#include "plan/resource_estimate.h"
#include "run_cli.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>
#include <openvdb/openvdb.h>
#include <png.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

using yv::test::RunResult;
using yv::test::runShell;

const std::string kBinary = std::string(YV_BINARY_DIR) + "/yarnvox";

RunResult run(const std::string& args) { return yv::test::runYarnvox(args); }

fs::path scratch(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("yv_bad_input_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    return dir / name;
}

std::size_t lineCount(const std::string& s) { return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')); }

/// A curve as a BCC file stores it: float points, closed or not.
struct RawCurve {
    std::vector<std::array<float, 3>> points;
    bool closed = false;
};

void put(std::vector<std::uint8_t>& out, std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

/// BCC bytes written by hand, so that values encodeBcc refuses can be stored.
std::vector<std::uint8_t> bccBytes(const std::string& type, const std::vector<RawCurve>& curves, const std::string& info = "") {
    std::vector<std::uint8_t> out = {'B', 'C', 'C', 0x44, std::uint8_t(type[0]), std::uint8_t(type[1]), 3, 2};
    std::uint64_t points = 0;
    for (const RawCurve& c : curves) points += c.points.size();
    put(out, curves.size(), 8);
    put(out, points, 8);
    out.insert(out.end(), info.begin(), info.end());
    out.resize(64, 0);
    for (const RawCurve& c : curves) {
        const auto n = static_cast<std::int32_t>(c.points.size());
        put(out, static_cast<std::uint32_t>(c.closed ? -n : n), 4);
        for (const auto& p : c.points)
            for (float v : p) {
                std::uint32_t bits;
                std::memcpy(&bits, &v, 4);
                put(out, bits, 4);
            }
    }
    return out;
}

fs::path writeBytes(const std::string& name, const std::vector<std::uint8_t>& bytes) {
    const fs::path path = scratch(name);
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    return path;
}

/// A straight open yarn along x from 0 to `length`, one point per unit.
RawCurve straight(int length, float y = 0.0f, float z = 0.0f) {
    RawCurve c;
    for (int i = 0; i <= length; ++i) c.points.push_back({float(i), y, z});
    return c;
}

fs::path writeBcc(const std::string& name, const std::string& type, const std::vector<RawCurve>& curves,
                  const std::string& info = "") {
    return writeBytes(name, bccBytes(type, curves, info));
}

/// A grey + alpha PNG of size x size, `alpha` everywhere inside radius
/// `size / 2` (0 outside); optional tEXt "yarn-radius".
fs::path writePng(const std::string& name, int size, std::uint8_t alpha, const char* radiusText = nullptr) {
    const fs::path path = scratch(name);
    FILE* f = std::fopen(path.c_str(), "wb");
    REQUIRE(f);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    png_init_io(png, f);
    png_set_IHDR(png, info, size, size, 8, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_text text{};
    if (radiusText) {
        text.compression = PNG_TEXT_COMPRESSION_NONE;
        text.key = const_cast<char*>("yarn-radius");
        text.text = const_cast<char*>(radiusText);
        png_set_text(png, info, &text, 1);
    }
    png_write_info(png, info);
    std::vector<png_byte> row(2 * size);
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const double u = (x + 0.5) / size * 2 - 1, v = (y + 0.5) / size * 2 - 1;
            row[2 * x] = 255;
            row[2 * x + 1] = u * u + v * v < 1.0 ? alpha : 0;
        }
        png_write_row(png, row.data());
    }
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
    return path;
}

std::vector<std::uint8_t> readBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::vector<std::uint8_t>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::string readText(const fs::path& p) {
    std::ifstream in(p);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

double jsonNumber(const std::string& json, const std::string& key) {
    const std::size_t at = json.find("\"" + key + "\"");
    REQUIRE(at != std::string::npos);
    return std::stod(json.substr(json.find(':', at) + 1));
}

/// Runs `voxelize INPUT -o OUT ARGS` expecting a refusal: exit 1 (or CLI11's
/// code for a bad option), every word of `names` in the message, one line,
/// and no output file or temporary left.
void expectRefused(const fs::path& input, const std::string& args, const std::vector<std::string>& names) {
    const fs::path vdb = scratch("refused.vdb");
    fs::remove(vdb);
    const auto start = std::chrono::steady_clock::now();
    const RunResult r = run("voxelize " + input.string() + " -o " + vdb.string() + " --backend cpu " + args);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    INFO("voxelize " << input.filename().string() << " " << args << "\n" << r.output);
    CHECK(r.exitCode != 0);
    CHECK(r.output.find("yarnvox: error: ") != std::string::npos);
    for (const std::string& n : names) CHECK(r.output.find(n) != std::string::npos);
    CHECK(r.output.find("wrote") == std::string::npos);
    CHECK(lineCount(r.output) == 1);
    CHECK_FALSE(fs::exists(vdb));
    CHECK(seconds < 20.0); // refused before any real work
    for (const auto& e : fs::directory_iterator(vdb.parent_path()))
        CHECK(e.path().filename().string().rfind("refused.vdb", 0) != 0);
}

/// Runs a voxelize that must succeed and returns its --stats JSON and output.
std::pair<std::string, std::string> voxelizeOk(const fs::path& input, const std::string& args, const std::string& tag) {
    const fs::path vdb = scratch(tag + ".vdb"), json = scratch(tag + ".json");
    fs::remove(vdb);
    const RunResult r = run("voxelize " + input.string() + " -o " + vdb.string() + " --backend cpu --stats " +
                            json.string() + " " + args);
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    REQUIRE(fs::exists(vdb));
    return {readText(json), r.output};
}

std::string vdbStringMeta(const fs::path& vdb, const std::string& key) {
    openvdb::initialize();
    openvdb::io::File file(vdb.string());
    file.open();
    const auto meta = file.getMetadata();
    file.close();
    return meta->metaValue<std::string>(key);
}

} // namespace

// ---- item 3: numbers ----------------------------------------------------------

TEST_CASE("bad input: non-finite and absurd option values name the option and the value", "[bad-input][cli]") {
    const fs::path bcc = writeBcc("options.bcc", "C0", {straight(4)}, "yarn-radius=0.2");
    struct Case {
        std::string args, option, value;
    };
    const Case cases[] = {
        {"--resolution 32 --twist nan", "--twist", "nan"},
        {"--resolution 32 --twist inf", "--twist", "inf"},
        {"--resolution 32 --twist -inf", "--twist", "-inf"},
        {"--resolution 32 --twist 1e300", "--twist", "1e300"},
        {"--resolution 32 --yarn-radius nan", "--yarn-radius", "nan"},
        {"--resolution 32 --yarn-radius inf", "--yarn-radius", "inf"},
        {"--resolution 32 --yarn-radius 1e30", "--yarn-radius", "1e30"},
        {"--resolution 32 --yarn-radius 1e-30", "--yarn-radius", "1e-30"},
        {"--resolution 32 --yarn-radius 0", "--yarn-radius", "0"},
        {"--resolution 32 --yarn-radius -0.1", "--yarn-radius", "-0.1"},
        {"--resolution 32 --yarn-radius 0.1cm", "--yarn-radius", "0.1cm"},
        {"--resolution 32 --slice-spacing nan", "--slice-spacing", "nan"},
        {"--resolution 32 --slice-spacing 1e-30", "--slice-spacing", "1e-30"},
        {"--voxel-size nan", "--voxel-size", "nan"},
        {"--voxel-size 1e30", "--voxel-size", "1e30"},
        {"--voxel-size 1e-30", "--voxel-size", "1e-30"},
        // The GL append counter is 32 bits; a device index is not negative.
        {"--resolution 32 --fragment-budget -5", "--fragment-budget", "-5"},
        {"--resolution 32 --fragment-budget 0", "--fragment-budget", "0"},
        {"--resolution 32 --fragment-budget 3000000000", "--fragment-budget", "3000000000"},
        {"--resolution 32 --device -3", "--device", "-3"},
    };
    for (const Case& c : cases) expectRefused(bcc, c.args, {c.option, c.value});

    // gen checks its lengths the same way.
    for (const char* bad : {"--spacing nan", "--yarn-radius inf", "--yarn-radius 1e-30"}) {
        const fs::path out = scratch("gen-bad.bcc");
        fs::remove(out);
        const RunResult r = run(std::string("gen --crossings 4 ") + bad + " -o " + out.string());
        INFO(bad << "\n" << r.output);
        CHECK(r.exitCode != 0);
        CHECK(r.output.find(std::string(bad).substr(0, std::string(bad).find(' '))) != std::string::npos);
        CHECK(lineCount(r.output) == 1);
        CHECK_FALSE(fs::exists(out));
    }
}

TEST_CASE("bad input: a yarn radius in the BCC file's info that is no sane length names the file and byte", "[bad-input][bcc]") {
    for (const char* bad : {"nan", "inf", "1e30", "1e-30", "-1", "0", "abc"}) {
        const fs::path bcc = writeBcc("info-radius.bcc", "C0", {straight(4)}, std::string("x yarn-radius=") + bad);
        expectRefused(bcc, "--resolution 32", {"info-radius.bcc", "byte 26", std::string("yarn-radius=") + bad});
    }
    // --yarn-radius does not rescue a file that contradicts itself: the file is wrong either way.
    const fs::path bcc = writeBcc("info-radius.bcc", "C0", {straight(4)}, "yarn-radius=nan");
    expectRefused(bcc, "--resolution 32 --yarn-radius 0.2", {"info-radius.bcc", "yarn-radius=nan"});
}

TEST_CASE("bad input: coordinates that are not finite or beyond 1e12 name the curve, point and axis", "[bad-input][bcc]") {
    struct Case {
        float value;
        std::string says;
    };
    const Case cases[] = {{std::nanf(""), "nan"}, {INFINITY, "inf"}, {-INFINITY, "-inf"}, {1e38f, "1e+38"}, {-3e20f, "-3e+20"}};
    for (const Case& c : cases) {
        RawCurve curve = straight(4);
        curve.points[2][1] = c.value;
        const fs::path bcc = writeBcc("coordinate.bcc", "C0", {straight(3), curve}, "yarn-radius=0.2");
        expectRefused(bcc, "--resolution 32", {"coordinate.bcc", "curve 1 point 2", "y coordinate", c.says});
    }
}

TEST_CASE("bad input: a cross-section PNG with an absurd radius, no density, or corrupt bytes is refused", "[bad-input][png]") {
    const fs::path bcc = writeBcc("png-garment.bcc", "C0", {straight(4)}, "yarn-radius=0.2");
    for (const char* bad : {"1e30", "1e-30", "nan", "-2", "0.1 cm"})
        expectRefused(bcc, "--resolution 32 --cross-section " + writePng("radius.png", 16, 255, bad).string(),
                      {"radius.png", "yarn-radius", bad});
    expectRefused(bcc, "--resolution 32 --cross-section " + writePng("clear.png", 16, 0).string(),
                  {"clear.png", "density 0", "fully transparent"});

    // A corrupt image: a flipped byte inside the image data (the chunk's CRC
    // fails), a PNG cut short, and a PNG cut inside its header.
    const fs::path good = writePng("good.png", 32, 200);
    std::vector<std::uint8_t> bytes = readBytes(good);
    const std::string idat = "IDAT";
    const auto at = std::search(bytes.begin(), bytes.end(), idat.begin(), idat.end()) - bytes.begin();
    std::vector<std::uint8_t> flipped = bytes;
    flipped.at(at + 6) ^= 0x5a;
    expectRefused(bcc, "--resolution 32 --cross-section " + writeBytes("flipped.png", flipped).string(),
                  {"flipped.png", "corrupt or truncated PNG"});
    expectRefused(bcc, "--resolution 32 --cross-section " +
                           writeBytes("cut.png", std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + at + 8)).string(),
                  {"cut.png", "corrupt or truncated PNG"});
    expectRefused(bcc, "--resolution 32 --cross-section " +
                           writeBytes("cut-header.png", std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + 20)).string(),
                  {"cut-header.png", "corrupt or truncated PNG"});
    // The intact file works, and its radius is used.
    const auto [stats, out] = voxelizeOk(bcc, "--resolution 32 --cross-section " + writePng("ok.png", 32, 200, "0.25").string(), "png-ok");
    CHECK(jsonNumber(stats, "active_voxels") > 0);
}

TEST_CASE("bad input: a yarn too thin for the voxels, or a slice spacing far below them, is refused before slicing", "[bad-input][cli]") {
    const fs::path bcc = writeBcc("thin.bcc", "C0", {straight(8)});
    // The disk: fibre area under 1/65536 of a voxel face rounds to nothing.
    expectRefused(bcc, "--voxel-size 0.1 --yarn-radius 1e-5 --cross-section disk", {"yarn radius 1e-05", "--yarn-radius", "empty"});
    // A texture narrower than a quarter of a sample pixel is missed.
    expectRefused(bcc, "--voxel-size 1 --yarn-radius 0.1", {"yarn radius 0.1", "sample pixels wide", "fibers"});
    // At 0.4 pixels this straight yarn falls between the sample rows: the run
    // warns, finds the volume empty, and keeps no file.
    const fs::path vdb = scratch("between.vdb");
    const RunResult r = run("voxelize " + bcc.string() + " -o " + vdb.string() + " --backend cpu --voxel-size 1 --yarn-radius 0.2");
    INFO(r.output);
    CHECK(r.exitCode == 1);
    CHECK(r.output.find("warning: yarn radius 0.2") != std::string::npos);
    CHECK(r.output.find("yarnvox: error: " + bcc.string() + ": no yarn reached a voxel's samples") != std::string::npos);
    CHECK(r.output.find("wrote") == std::string::npos);
    CHECK_FALSE(fs::exists(vdb));
    // --slice-spacing below 1/64 voxel: nothing gained but slices.
    expectRefused(bcc, "--voxel-size 0.1 --yarn-radius 0.2 --slice-spacing 1e-6", {"--slice-spacing 1e-06", "64 slices"});
    // Just above the texture limit the run works, with a warning that names the aliasing.
    const auto [stats, out] = voxelizeOk(bcc, "--voxel-size 1 --yarn-radius 0.3", "thin-ok");
    CHECK(out.find("warning: yarn radius 0.3") != std::string::npos);
    CHECK(out.find("aliased") != std::string::npos);
    CHECK(jsonNumber(stats, "active_voxels") > 0);
}

TEST_CASE("bad input: a grid over 2^24 voxels on an axis is refused at once, naming the limit", "[bad-input][cli]") {
    const fs::path bcc = writeBcc("huge-grid.bcc", "C0", {straight(100)}, "yarn-radius=0.2");
    // 1e-7 per voxel over 100 units: 1e9 voxels on x; refused before slicing (else 1e9 slices).
    expectRefused(bcc, "--voxel-size 1e-7 --cross-section disk", {"2^24", "1e-07"});
    // Far coordinates with a fine voxel size: the same limit, not an overflow.
    const fs::path far = writeBcc("far.bcc", "PL", {RawCurve{{{-1e11f, 0, 0}, {1e11f, 0, 0}}, false}}, "yarn-radius=0.2");
    expectRefused(far, "--voxel-size 1 --cross-section disk", {"2^24"});
}

// ---- item 5: reading ----------------------------------------------------------

TEST_CASE("bad input: /dev/zero, huge counts and wrong sizes are refused from the header, without allocating", "[bad-input][bcc]") {
    // Under a 1 GiB address-space limit: the old reader grew a buffer until
    // /dev/zero ran out; reading must stop at the 64-byte header.
    const std::string limited = "ulimit -v 1048576; exec timeout 20 " + kBinary + " voxelize ";
    const fs::path vdb = scratch("zero.vdb");
    fs::remove(vdb);
    RunResult r = runShell(limited + "/dev/zero -o " + vdb.string() + " --backend cpu --resolution 32");
    INFO(r.output);
    CHECK(r.exitCode == 1);
    CHECK(r.output.find("/dev/zero: byte 0: expected signature \"BCC\"") != std::string::npos);
    CHECK_FALSE(fs::exists(vdb));

    // A real header followed by endless zeros (a device or pipe: no size to
    // check up front): reading stops at the size the header's counts allow.
    const std::vector<std::uint8_t> header = bccBytes("C0", {straight(2)});
    const fs::path headerFile = writeBytes("header-only.bcc", header);
    r = runShell("cat " + headerFile.string() + " /dev/zero | (ulimit -v 1048576; exec timeout 20 " + kBinary +
                 " voxelize /dev/stdin -o " + vdb.string() + " --backend cpu --resolution 32)");
    INFO(r.output);
    CHECK(r.exitCode == 1);
    CHECK(r.output.find("/dev/stdin: byte 104: ") != std::string::npos);
    CHECK(r.output.find("trailing bytes") != std::string::npos);
    CHECK_FALSE(fs::exists(vdb));

    // Header counts that claim more than the file holds, or more than any
    // file can: each refused under the same limit, naming the field.
    struct Case {
        std::string name;
        std::size_t offset;
        std::uint64_t value;
        std::string says;
    };
    const Case cases[] = {
        {"huge-curves.bcc", 8, 0x7fffffffffffffffull, "curve count"},
        {"huge-points.bcc", 16, 0x0fffffffffffffffull, "control-point count"},
        {"small-curves.bcc", 8, 1, "bytes past the"},
        {"more-points.bcc", 16, 1ull << 40, "control-point count"},
    };
    for (const Case& c : cases) {
        std::vector<std::uint8_t> bytes = bccBytes("C0", {straight(4), straight(3)}, "yarn-radius=0.2");
        for (int i = 0; i < 8; ++i) bytes[c.offset + i] = static_cast<std::uint8_t>(c.value >> (8 * i));
        const fs::path bcc = writeBytes(c.name, bytes);
        r = runShell(limited + bcc.string() + " -o " + vdb.string() + " --backend cpu --resolution 32");
        INFO(c.name << "\n" << r.output);
        CHECK(r.exitCode == 1);
        CHECK(r.output.find(c.name + ": byte ") != std::string::npos);
        CHECK(r.output.find(c.says) != std::string::npos);
        CHECK_FALSE(fs::exists(vdb));
    }
    // A curve whose count runs past the end of the file.
    std::vector<std::uint8_t> bytes = bccBytes("C0", {straight(4)}, "yarn-radius=0.2");
    bytes[64] = 0xff, bytes[65] = 0xff, bytes[66] = 0xff, bytes[67] = 0x7f;
    expectRefused(writeBytes("long-curve.bcc", bytes), "--resolution 32", {"long-curve.bcc", "byte 68", "truncated curve 0"});
}

TEST_CASE("bad input: the reader checks the signature before reading the rest", "[bad-input][bcc]") {
    const fs::path path = scratch("not-bcc.bcc");
    {
        // 64 MiB of something else: refused from its first bytes.
        std::ofstream f(path, std::ios::binary | std::ios::trunc);
        f << "PK\x03\x04";
        f.seekp((64 << 20) - 1);
        f.put('\0');
    }
    CHECK_THROWS_WITH(yv::readBcc(path.string()), Contains("not-bcc.bcc: byte 0: expected signature \"BCC\", found \"PK\\x03\""));
    const std::string limited = "ulimit -v 1048576; exec " + kBinary + " voxelize " + path.string() + " -o " +
                                scratch("not-bcc.vdb").string() + " --backend cpu --resolution 32";
    const RunResult r = runShell(limited);
    CHECK(r.exitCode == 1);
    CHECK(r.output.find("expected signature") != std::string::npos);
    fs::remove(path);
}

// ---- item 4: real garments ------------------------------------------------------

TEST_CASE("bad input: repeated control points are dropped and counted, and the volume is the same", "[bad-input][cli]") {
    RawCurve doubled = straight(6);
    doubled.points.insert(doubled.points.begin() + 3, doubled.points[3]);
    doubled.points.insert(doubled.points.begin() + 5, doubled.points[4]);
    const fs::path plain = writeBcc("plain-yarn.bcc", "C0", {straight(6)}, "yarn-radius=0.25");
    const fs::path repeated = writeBcc("repeated.bcc", "C0", {doubled}, "yarn-radius=0.25");
    const std::string args = "--voxel-size 0.05 --cross-section disk";
    const auto [want, wantOut] = voxelizeOk(plain, args, "plain-yarn");
    const auto [got, gotOut] = voxelizeOk(repeated, args, "repeated");
    CHECK(wantOut.find("dropped") == std::string::npos);
    CHECK(gotOut.find("repeated.bcc: dropped 2 zero-length spans (repeated control points)") != std::string::npos);
    CHECK(jsonNumber(got, "fiber_volume") == Approx(jsonNumber(want, "fiber_volume")).epsilon(1e-9));
    CHECK(jsonNumber(got, "active_voxels") == jsonNumber(want, "active_voxels"));
    // pi r^2 L for the straight yarn.
    CHECK(jsonNumber(want, "fiber_volume") == Approx(M_PI * 0.25 * 0.25 * 6).epsilon(0.01));
}

TEST_CASE("bad input: a closed curve whose last point repeats the first loses that span, not the garment", "[bad-input][cli]") {
    RawCurve loop;
    for (int i = 0; i < 12; ++i)
        loop.points.push_back({float(3 * std::cos(2 * M_PI * i / 12)), float(3 * std::sin(2 * M_PI * i / 12)), 0.0f});
    loop.closed = true;
    RawCurve repeating = loop;
    repeating.points.push_back(loop.points.front());
    const std::string args = "--voxel-size 0.05 --cross-section disk";
    const auto [want, wantOut] = voxelizeOk(writeBcc("loop.bcc", "C0", {loop}, "yarn-radius=0.2"), args, "loop");
    const auto [got, gotOut] = voxelizeOk(writeBcc("loop-rep.bcc", "C0", {repeating}, "yarn-radius=0.2"), args, "loop-rep");
    CHECK(gotOut.find("loop-rep.bcc: dropped 1 zero-length span (repeated control points; 1 of them closing closed "
                      "curves whose last point repeats the first)") != std::string::npos);
    CHECK(jsonNumber(got, "fiber_volume") == Approx(jsonNumber(want, "fiber_volume")).epsilon(1e-9));
}

TEST_CASE("bad input: what cannot be a curve is refused naming the file, the curve and the point", "[bad-input][cli]") {
    const RawCurve good = straight(3);
    // Every point in one place.
    expectRefused(writeBcc("one-place.bcc", "C0", {good, RawCurve{{{1, 1, 1}, {1, 1, 1}, {1, 1, 1}}, false}}, "yarn-radius=0.2"),
                  "--resolution 32", {"one-place.bcc: curve 1", "point 0", "not a curve"});
    // (A knot whose neighbours coincide, where the curve turns straight back,
    // is a cusp and is voxelized: tests/test_cusps.cpp.)
    // A closed Catmull-Rom curve of two distinct points only goes back and forth.
    expectRefused(writeBcc("two-point-loop.bcc", "C0", {RawCurve{{{0, 0, 0}, {1, 0, 0}}, true}}, "yarn-radius=0.2"),
                  "--resolution 32", {"two-point-loop.bcc: curve 0", "back and forth"});
    // Point counts a Bezier or B-spline curve cannot use.
    expectRefused(writeBcc("bezier-count.bcc", "BZ", {RawCurve{{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}}, false}},
                           "yarn-radius=0.2"),
                  "--resolution 32", {"bezier-count.bcc: curve 0", "5 control points", "3k+1"});
    expectRefused(writeBcc("bspline-count.bcc", "BS", {RawCurve{{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, false}}, "yarn-radius=0.2"),
                  "--resolution 32", {"bspline-count.bcc: curve 0", "at least 4"});
    // A B-spline with a quadruple point does not move there.
    expectRefused(writeBcc("bspline-still.bcc", "BS",
                           {RawCurve{{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 0, 0}, {2, 0, 0}, {2, 0, 0}, {3, 1, 0}}, false}},
                           "yarn-radius=0.2"),
                  "--resolution 32", {"bspline-still.bcc: curve 0 point", "does not move", "not a curve"});
    // An unknown curve type names the types there are.
    expectRefused(writeBcc("type.bcc", "CC", {good}, "yarn-radius=0.2"), "--resolution 32", {"type.bcc: byte 4", "\"BS\"", "\"BZ\""});
}

TEST_CASE("bad input: a span far longer than the rest of its curve is warned about", "[bad-input][cli]") {
    // An open yarn stored as closed: the closing span is a chord back to the start.
    RawCurve open = straight(30);
    open.closed = true;
    const auto [stats, out] =
        voxelizeOk(writeBcc("chord.bcc", "C0", {open}, "yarn-radius=0.2"), "--resolution 64 --cross-section disk", "chord");
    CHECK(out.find("warning: ") != std::string::npos);
    CHECK(out.find("chord.bcc: curve 0: the span from point 30 to point 0 is 30 long, 30 times the curve's median span 1 "
                   "(the closing span of a closed curve: is the closed flag right?)") != std::string::npos);
    // The same yarn, open: no warning.
    const auto [stats2, out2] = voxelizeOk(writeBcc("no-chord.bcc", "C0", {straight(30)}, "yarn-radius=0.2"),
                                           "--resolution 64 --cross-section disk", "no-chord");
    CHECK(out2.find("warning") == std::string::npos);
}

TEST_CASE("bad input: BZ curves are exact cubic Bezier curves", "[bad-input][curves]") {
    // A straight Bezier line with evenly spaced handles is the line at uniform speed.
    yv::Yarn line{{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}}, false};
    REQUIRE(yv::yarnSegmentCount(line, yv::CurveType::Bezier) == 1);
    const yv::SegmentPoints s = yv::segmentPoints(line, 0, yv::CurveType::Bezier);
    for (double t : {0.0, 0.25, 0.5, 0.9, 1.0}) {
        const glm::dvec3 p = yv::evalCatmullRom(s, t);
        CHECK(p.x == Approx(3 * t).margin(1e-12));
        CHECK(std::abs(p.y) + std::abs(p.z) < 1e-12);
    }
    // A general open curve of two segments, and a closed one: de Casteljau's positions.
    const std::vector<glm::dvec3> B = {{0, 0, 0}, {1, 2, 0}, {3, 2, 1}, {4, 0, 1}, {5, -2, 1}, {7, -1, 3}, {8, 0, 0}};
    auto bezier = [](const glm::dvec3* b, double t) {
        const double u = 1 - t;
        return u * u * u * b[0] + 3 * u * u * t * b[1] + 3 * u * t * t * b[2] + t * t * t * b[3];
    };
    yv::Yarn open{B, false};
    REQUIRE(yv::yarnSegmentCount(open, yv::CurveType::Bezier) == 2);
    for (std::size_t seg = 0; seg < 2; ++seg)
        for (double t : {0.0, 0.1, 0.37, 0.5, 0.83, 1.0}) {
            const glm::dvec3 got = yv::evalCatmullRom(yv::segmentPoints(open, seg, yv::CurveType::Bezier), t);
            CHECK(glm::length(got - bezier(&B[3 * seg], t)) < 1e-12);
        }
    yv::Yarn closed{{B.begin(), B.begin() + 6}, true};
    REQUIRE(yv::yarnSegmentCount(closed, yv::CurveType::Bezier) == 2);
    const glm::dvec3 last[4] = {B[3], B[4], B[5], B[0]};
    CHECK(glm::length(yv::evalCatmullRom(yv::segmentPoints(closed, 1, yv::CurveType::Bezier), 0.6) - bezier(last, 0.6)) < 1e-12);

    // Through the file and the voxelizer: a BZ straight yarn holds pi r^2 L, as the C0 one does.
    const fs::path bz = writeBcc("line.bcc", "BZ", {straight(6)}, "yarn-radius=0.25");
    REQUIRE(yv::readBcc(bz.string()).curveType == yv::CurveType::Bezier);
    const auto [stats, out] = voxelizeOk(bz, "--voxel-size 0.05 --cross-section disk", "bz-line");
    CHECK(jsonNumber(stats, "fiber_volume") == Approx(M_PI * 0.25 * 0.25 * 6).epsilon(0.01));
    // And writing keeps the type.
    CHECK(yv::parseBcc(yv::encodeBcc(yv::readBcc(bz.string())), "again").curveType == yv::CurveType::Bezier);
}

TEST_CASE("bad input: BS curves are exact uniform cubic B-splines", "[bad-input][curves]") {
    const std::vector<glm::dvec3> P = {{0, 0, 0}, {1, 2, 0}, {3, 2, 1}, {4, 0, 1}, {5, -2, 1}, {7, -1, 3}};
    auto bspline = [](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d, double t) {
        const double u = 1 - t;
        return (u * u * u * a + (3 * t * t * t - 6 * t * t + 4) * b + (-3 * t * t * t + 3 * t * t + 3 * t + 1) * c +
                t * t * t * d) /
               6.0;
    };
    yv::Yarn open{P, false};
    REQUIRE(yv::yarnSegmentCount(open, yv::CurveType::BSpline) == 3);
    for (std::size_t seg = 0; seg < 3; ++seg)
        for (double t : {0.0, 0.2, 0.5, 0.77, 1.0}) {
            const glm::dvec3 got = yv::evalCatmullRom(yv::segmentPoints(open, seg, yv::CurveType::BSpline), t);
            CHECK(glm::length(got - bspline(P[seg], P[seg + 1], P[seg + 2], P[seg + 3], t)) < 1e-12);
        }
    // Closed: n segments, segment s shaped by points s-1..s+2 (wrapping).
    yv::Yarn closed{P, true};
    REQUIRE(yv::yarnSegmentCount(closed, yv::CurveType::BSpline) == 6);
    for (std::size_t seg = 0; seg < 6; ++seg) {
        const glm::dvec3 got = yv::evalCatmullRom(yv::segmentPoints(closed, seg, yv::CurveType::BSpline), 0.3);
        CHECK(glm::length(got - bspline(P[(seg + 5) % 6], P[seg], P[(seg + 1) % 6], P[(seg + 2) % 6], 0.3)) < 1e-12);
    }
    // Collinear, evenly spaced B-spline points give the line between the
    // second and the second-to-last point: pi r^2 L with L = n - 3.
    const fs::path bs = writeBcc("bs-line.bcc", "BS", {straight(9)}, "yarn-radius=0.25");
    const auto [stats, out] = voxelizeOk(bs, "--voxel-size 0.05 --cross-section disk", "bs-line");
    CHECK(jsonNumber(stats, "fiber_volume") == Approx(M_PI * 0.25 * 0.25 * 7).epsilon(0.01));
}

TEST_CASE("bad input: no radius in the file is estimated from touching yarns, recorded, and overridable", "[bad-input][radius]") {
    // Two parallel straight yarns 2r apart touch along their length; a third
    // crosses above them, touching both.
    const double r = 0.15;
    const float gap = float(2 * r);
    yv::Garment g = yv::parseBcc(
        bccBytes("C0", {straight(10), straight(10, gap), RawCurve{{{5, -2, gap}, {5, -1, gap}, {5, 0, gap}, {5, 1, gap}, {5, 2, gap}}, false}}),
        "two.bcc");
    const yv::RadiusEstimate e = yv::estimateYarnRadius(g);
    CHECK(e.radius == Approx(r).epsilon(0.10));
    CHECK(e.contacts > 0);
    // Knit-like: one yarn folding back on itself 2r apart is a contact too.
    RawCurve hairpin;
    for (int i = 0; i <= 10; ++i) hairpin.points.push_back({float(i), 0, 0});
    for (int i = 10; i >= 0; --i) hairpin.points.push_back({float(i) + 0.5f, gap, 0});
    CHECK(yv::estimateYarnRadius(yv::parseBcc(bccBytes("PL", {hairpin}), "hairpin.bcc")).radius == Approx(r).epsilon(0.10));

    const fs::path bcc = writeBcc("no-radius.bcc", "C0", {straight(10), straight(10, gap)});
    const fs::path vdb = scratch("estimated.vdb");
    RunResult run1 = run("voxelize " + bcc.string() + " -o " + vdb.string() + " --backend cpu --resolution 64");
    INFO(run1.output);
    REQUIRE(run1.exitCode == 0);
    CHECK(run1.output.find("no-radius.bcc: the file gives no yarn radius; estimated 0.15") != std::string::npos);
    CHECK(vdbStringMeta(vdb, "yarn_radius_source") == "estimated");
    RunResult run2 = run("voxelize " + bcc.string() + " -o " + vdb.string() + " --backend cpu --resolution 64 --yarn-radius 0.1");
    REQUIRE(run2.exitCode == 0);
    CHECK(run2.output.find("gives no yarn radius") == std::string::npos);
    CHECK(vdbStringMeta(vdb, "yarn_radius_source") == "option");
    const fs::path withRadius = writeBcc("with-radius.bcc", "C0", {straight(10)}, "yarn-radius=0.2");
    REQUIRE(run("voxelize " + withRadius.string() + " -o " + vdb.string() + " --backend cpu --resolution 64").exitCode == 0);
    CHECK(vdbStringMeta(vdb, "yarn_radius_source") == "file");

    // One lone yarn gives nothing to estimate from: refused, saying what to pass.
    expectRefused(writeBcc("lone.bcc", "C0", {straight(10)}), "--resolution 64", {"lone.bcc", "no yarn radius", "--yarn-radius"});
}

TEST_CASE("bad input: checkCurves reports by file index, after drops", "[bad-input][curves]") {
    yv::Garment g;
    g.yarns.push_back({{{0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1, 0, 0}}, false});
    // Points 4 (2,0,0) and its neighbours: after the drops, knot (2,0,0) sits
    // between two (1,0,0), a cusp: the file's point 4 is named, not the tidied index 2.
    CHECK_THAT(yv::checkCurves(g, "idx.bcc").warnings.at(0), Contains("idx.bcc: curve 0 point 4:"));
    // And where a curve cannot be used, too: curve 1's point 0 is all there is.
    g.yarns.push_back({{{5, 5, 5}, {5, 5, 5}}, false});
    CHECK_THROWS_WITH(yv::checkCurves(g, "idx.bcc"), Contains("idx.bcc: curve 1:") && Contains("point 0"));
}

TEST_CASE("bad input: curves checked side by side report as in file order", "[bad-input][curves]") {
    // Many curves, so that they are checked on several threads: the long-span
    // warnings come in file order (five lines, then a count), and of two
    // curves that cannot be used, the first in the file is named.
    const auto zigzag = [](double x0, bool longSpan) {
        yv::Yarn y;
        for (int j = 0; j < 12; ++j) y.points.push_back({x0 + j, 0.3 * (j % 2), 0});
        if (longSpan) y.points.back().x += 100; // its last span is over 20 times the median
        return y;
    };
    yv::Garment g;
    for (int i = 0; i < 600; ++i) g.yarns.push_back(zigzag(0, i % 50 == 7));
    const yv::CurveCheckReport report = yv::checkCurves(g, "many.bcc");
    REQUIRE(report.warnings.size() == 6);
    for (int n = 0; n < 5; ++n)
        CHECK_THAT(report.warnings[n], Catch::StartsWith("many.bcc: curve " + std::to_string(50 * n + 7) + ": the span"));
    CHECK(report.warnings[5] == "many.bcc: 7 more curves have a span over 20 times their median span");

    yv::Garment bad = g;
    bad.yarns[431].points = {{0, 0, 0}, {0, 0, 0}};
    bad.yarns[123].points = {{5, 5, 5}};
    CHECK_THROWS_WITH(yv::checkCurves(bad, "many.bcc"), Contains("many.bcc: curve 123:"));
    // Repeats dropped on every thread add up.
    yv::Garment repeats;
    for (int i = 0; i < 500; ++i) {
        yv::Yarn y = zigzag(0, false);
        y.points.insert(y.points.begin() + 3, y.points[2]);
        repeats.yarns.push_back(y);
    }
    CHECK(yv::checkCurves(repeats, "r.bcc").droppedSpans == 500);
}

TEST_CASE("bad input: a run that needs more disk than the machine has is refused at the start, with the numbers", "[bad-input][cli]") {
    // The bound: a quarter of the yarn's disk along its length, over the voxel volume.
    yv::Garment g;
    yv::Yarn y;
    y.points = {{0, 0, 0}, {3, 0, 0}, {3, 4, 0}}; // length 7
    g.yarns.push_back(y);
    const yv::ResourceNeeds n = yv::estimateNeeds(g, 0.5, 0.1, false);
    CHECK(n.activeVoxels == Approx(0.25 * M_PI * 0.25 * 7.0 / 1e-3));
    CHECK(n.outputBytes == Approx(16.0 * n.activeVoxels));
    CHECK(yv::estimateNeeds(g, 0.5, 0.1, true).outputBytes == Approx(8.0 * n.activeVoxels));
    const std::string dir = fs::temp_directory_path().string();
    CHECK(yv::checkNeeds(n, {dir, ""}, "--resolution 64").empty());
    yv::ResourceNeeds disk = n;
    disk.outputBytes = 1e21;
    CHECK_THAT(yv::checkNeeds(disk, {dir, ""}, "--resolution 64"),
               Contains("the output needs at least 2e+12 GB of disk") && Contains("choose a coarser --resolution"));

    // End to end: refused before any slicing, nothing written.
    const fs::path bcc = fs::temp_directory_path() / ("yv_needs_" + std::to_string(getpid()) + ".bcc");
    const fs::path vdb = bcc.string() + ".vdb";
    REQUIRE(run("gen --pattern plain --crossings 400 --quiet -o " + bcc.string()).exitCode == 0);
    const RunResult r = run("voxelize " + bcc.string() + " -o " + vdb.string() + " --resolution 1000000");
    INFO(r.output);
    CHECK(r.exitCode == 1);
    CHECK_THAT(r.output, Contains("needs at least") && Contains("--resolution 1000000") && Contains("active voxels at least"));
    CHECK_FALSE(fs::exists(vdb));
    fs::remove(bcc);
}
