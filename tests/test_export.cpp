// Renderer outputs (src/export): Mitsuba .vol files read back by a reader
// written here from the format's spec, NanoVDB files read back by NanoVDB's
// own reader and printer, against grids whose every voxel is known.
#include "core/error.h"
#include "core/interrupt.h"
#include "cpu/cpu_voxelizer.h"
#include "export/mitsuba_vol.h"
#include "export/nanovdb_output.h"
#include "garment/cross_section.h"
#include "run_cli.h"
#include "store/brick_store.h"
#include "test_helpers.h"
#include "vdb/vdb_writer.h"

#include <catch2/catch.hpp>
#include <nanovdb/util/IO.h>
#include <openvdb/openvdb.h>

#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>

using namespace yv;
namespace fs = std::filesystem;

namespace {

/// A scratch file; tests that count leftover temporaries give a folder of
/// their own, since CTest runs tests in parallel.
fs::path scratch(const std::string& name, const std::string& folder = "") {
    const fs::path dir = yv::test::processScratchDir("yv_export_test") / folder;
    fs::create_directories(dir);
    return dir / name;
}

/// A .vol file as the spec (formats/mitsuba-vol.md) lays it out, decoded
/// independently of the writer: values as floats, channel c of voxel (x, y, z)
/// at ((z * ny + y) * nx + x) * channels + c.
struct VolFile {
    std::int32_t encoding = 0, channels = 0;
    glm::ivec3 dims{0};
    float box[6] = {};
    std::vector<std::uint8_t> raw; ///< the data after the header
    std::size_t size = 0;          ///< file bytes

    std::size_t index(int x, int y, int z, int c) const {
        return ((std::size_t(z) * dims.y + y) * dims.x + x) * channels + c;
    }
    /// The stored value as written: float32 and float16 decoded, uint8 as its byte.
    float value(int x, int y, int z, int c) const {
        const std::size_t i = index(x, y, z, c);
        if (encoding == 1) {
            float f;
            std::memcpy(&f, raw.data() + 4 * i, 4);
            return f;
        }
        if (encoding == 2) {
            std::uint16_t bits;
            std::memcpy(&bits, raw.data() + 2 * i, 2);
            openvdb::math::half h;
            h.setBits(bits);
            return float(h);
        }
        return float(raw[i]);
    }
};

VolFile readVol(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    REQUIRE(in);
    std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    REQUIRE(bytes.size() >= 48);
    CHECK(bytes[0] == 'V');
    CHECK(bytes[1] == 'O');
    CHECK(bytes[2] == 'L');
    CHECK(bytes[3] == 3);
    VolFile v;
    // Little-endian int32 and float32, read byte by byte.
    const auto i32 = [&](std::size_t at) {
        return std::int32_t(std::uint32_t(bytes[at]) | std::uint32_t(bytes[at + 1]) << 8 |
                            std::uint32_t(bytes[at + 2]) << 16 | std::uint32_t(bytes[at + 3]) << 24);
    };
    v.encoding = i32(4);
    v.dims = {i32(8), i32(12), i32(16)};
    v.channels = i32(20);
    for (int i = 0; i < 6; ++i) v.box[i] = std::bit_cast<float>(std::uint32_t(i32(24 + 4 * i)));
    v.raw.assign(bytes.begin() + 48, bytes.end());
    v.size = bytes.size();
    const int width = v.encoding == 1 ? 4 : v.encoding == 2 ? 2 : 1;
    CHECK(v.raw.size() == std::size_t(v.dims.x) * v.dims.y * v.dims.z * v.channels * width);
    return v;
}

constexpr double kH = 0.5;
const glm::dvec3 kOrigin{1.0, -2.0, 3.0};

/// Voxel (i, j, k) of the known volume: density encodes its indices, the axis
/// is a unit vector that depends on them too (sign and all).
float knownDensity(int i, int j, int k) { return float(i + 10 * j + 100 * k) / 1000.0f; }
openvdb::Vec3s knownAxis(int i, int j, int k) {
    openvdb::Vec3s a(float(i) - 3.5f, float(j) + 0.25f, -float(k));
    a.normalize();
    return a;
}

/// Active voxels [2, 7) x [3, 6) x [4, 9): 5 x 3 x 5, so a swapped axis shows.
/// Transform as yarnvox writes it: voxel (i, j, k) has its centre at origin + (i + 0.5) h.
FiberGrids knownGrids() {
    openvdb::initialize();
    auto transform = openvdb::math::Transform::createLinearTransform(kH);
    transform->postTranslate(openvdb::Vec3d(kOrigin.x + 0.5 * kH, kOrigin.y + 0.5 * kH, kOrigin.z + 0.5 * kH));
    FiberGrids g;
    g.density = openvdb::FloatGrid::create(0.0f);
    g.density->setName("density");
    g.density->setGridClass(openvdb::GRID_FOG_VOLUME);
    g.density->setTransform(transform);
    g.orientation = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    g.orientation->setName("orientation");
    g.orientation->setVectorType(openvdb::VEC_INVARIANT);
    g.orientation->setTransform(transform);
    auto d = g.density->getAccessor();
    auto o = g.orientation->getAccessor();
    for (int i = 2; i < 7; ++i)
        for (int j = 3; j < 6; ++j)
            for (int k = 4; k < 9; ++k) {
                d.setValue(openvdb::Coord(i, j, k), knownDensity(i, j, k));
                o.setValue(openvdb::Coord(i, j, k), knownAxis(i, j, k));
            }
    return g;
}

bool inKnown(int i, int j, int k) { return i >= 2 && i < 7 && j >= 3 && j < 6 && k >= 4 && k < 9; }

/// What `encoding` stores for a density or an axis component.
float expectedStored(float v, int encoding, bool component) {
    if (encoding == 1) return v;
    if (encoding == 2) return float(openvdb::math::half(v));
    return component ? float(128 + std::lround(v * 127.0f)) : float(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

/// Checks every voxel of a density and an orientation .vol over voxel box
/// `box` against the known volume.
void checkKnownVolumes(const VolFile& dv, const VolFile& ov, const VoxelBox& box, int encoding, int orientationEncoding) {
    REQUIRE(dv.dims == box.dims());
    REQUIRE(ov.dims == box.dims());
    CHECK(dv.channels == 1);
    CHECK(ov.channels == 3);
    CHECK(dv.encoding == encoding);
    CHECK(ov.encoding == orientationEncoding);
    std::size_t mismatches = 0;
    for (int z = 0; z < dv.dims.z; ++z)
        for (int y = 0; y < dv.dims.y; ++y)
            for (int x = 0; x < dv.dims.x; ++x) {
                const int i = box.min.x + x, j = box.min.y + y, k = box.min.z + z;
                const bool on = inKnown(i, j, k);
                const float d = on ? knownDensity(i, j, k) : 0.0f;
                const openvdb::Vec3s a = on ? knownAxis(i, j, k) : openvdb::Vec3s(0.0f);
                mismatches += dv.value(x, y, z, 0) != expectedStored(d, encoding, false);
                for (int c = 0; c < 3; ++c) mismatches += ov.value(x, y, z, c) != expectedStored(a[c], orientationEncoding, true);
            }
    CHECK(mismatches == 0);
}

void checkBox(const VolFile& v, glm::dvec3 lo, glm::dvec3 hi) {
    for (int i = 0; i < 3; ++i) {
        CHECK(v.box[i] == Approx(lo[i]).margin(1e-6));
        CHECK(v.box[3 + i] == Approx(hi[i]).margin(1e-6));
    }
}

/// Writes grids to a .vdb through OpenVDB's own writer.
void writeGrids(const FiberGrids& g, const fs::path& path) {
    openvdb::GridPtrVec grids{g.density, g.orientation};
    openvdb::io::File file(path.string());
    file.write(grids);
    file.close();
}

std::size_t partialFiles(const fs::path& dir) {
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir)) n += e.path().filename().string().find(".partial") != std::string::npos;
    return n;
}

} // namespace

TEST_CASE("Export: .vol header, x-fastest order and box hold the known volume, in every encoding", "[export]") {
    const FiberGrids grids = knownGrids();
    // The active voxels [2, 7) x [3, 6) x [4, 9) and one empty voxel around them.
    const VoxelBox active{{1, 2, 3}, {8, 7, 10}};
    for (const VolEncoding e : {VolEncoding::Float32, VolEncoding::Float16, VolEncoding::UInt8}) {
        INFO(toString(e));
        const fs::path out = scratch(std::string("known-") + toString(e) + ".vol");
        VolExportOptions options;
        options.densityEncoding = options.orientationEncoding = e;
        const VolExportResult r = exportMitsubaVol(grids, out.string(), options);
        REQUIRE(r.paths.size() == 2);
        CHECK(r.paths[1] == scratch(std::string("known-") + toString(e) + ".orientation.vol").string());
        CHECK(r.box.min == active.min);
        CHECK(r.box.max == active.max);
        const VolFile dv = readVol(out), ov = readVol(r.paths[1]);
        CHECK(r.bytes == dv.size + ov.size);
        checkKnownVolumes(dv, ov, active, int(e), int(e));
        // Corners: the outer faces of the voxels, origin + index * h.
        checkBox(dv, kOrigin + kH * glm::dvec3(1, 2, 3), kOrigin + kH * glm::dvec3(8, 7, 10));
        checkBox(ov, kOrigin + kH * glm::dvec3(1, 2, 3), kOrigin + kH * glm::dvec3(8, 7, 10));
    }
    SECTION("centres: the box spans the first and last voxel centres (Mitsuba 0.6)") {
        VolExportOptions options;
        options.boxConvention = VolBoxConvention::Centres;
        const fs::path out = scratch("known-centres.vol");
        exportMitsubaVol(grids, out.string(), options);
        checkBox(readVol(out), kOrigin + kH * glm::dvec3(1.5, 2.5, 3.5), kOrigin + kH * glm::dvec3(7.5, 6.5, 9.5));
    }
    SECTION("mixed: uint8 density with a float32 orientation") {
        VolExportOptions options;
        options.densityEncoding = VolEncoding::UInt8;
        const fs::path out = scratch("known-mixed.vol");
        const VolExportResult r = exportMitsubaVol(grids, out.string(), options);
        checkKnownVolumes(readVol(out), readVol(r.paths[1]), active, 3, 1);
    }
}

TEST_CASE("Export: a voxel box crops, also beyond the active voxels, and a world box takes the voxels it overlaps", "[export]") {
    const FiberGrids grids = knownGrids();
    VolExportOptions options;
    options.box = VoxelBox{{0, 4, 3}, {4, 9, 6}}; // partly outside the active voxels: zeros there
    const fs::path out = scratch("crop.vol");
    const VolExportResult r = exportMitsubaVol(grids, out.string(), options);
    const VolFile dv = readVol(out);
    checkKnownVolumes(dv, readVol(r.paths[1]), *options.box, 1, 1);
    checkBox(dv, kOrigin + kH * glm::dvec3(0, 4, 3), kOrigin + kH * glm::dvec3(4, 9, 6));

    // Voxel n covers world [origin + n h, origin + (n + 1) h).
    const VoxelBox w = voxelBoxFromWorld(grids.density->transform(), kOrigin + kH * glm::dvec3(2.0, 3.2, 4.9),
                                         kOrigin + kH * glm::dvec3(5.0, 3.8, 6.1));
    CHECK(w.min == glm::ivec3(2, 3, 4)); // a box starting on a face includes that voxel
    CHECK(w.max == glm::ivec3(5, 4, 7)); // a box ending on a face excludes the next one
    CHECK_THROWS_AS(voxelBoxFromWorld(grids.density->transform(), kOrigin, kOrigin), Error);
}

TEST_CASE("Export: SGGX matrices of fibre-like flakes have the fibre axis as the eigenvector of sigma^2", "[export]") {
    const FiberGrids grids = knownGrids();
    VolExportOptions options;
    options.sggxRoughness = 0.3;
    const fs::path out = scratch("sggx.vol");
    const VolExportResult r = exportMitsubaVol(grids, out.string(), options);
    REQUIRE(r.paths.size() == 3);
    CHECK(r.paths[2] == scratch("sggx.sggx.vol").string());
    const VolFile s = readVol(r.paths[2]);
    CHECK(s.channels == 6);
    CHECK(s.encoding == 1);
    std::size_t bad = 0;
    for (int z = 0; z < s.dims.z; ++z)
        for (int y = 0; y < s.dims.y; ++y)
            for (int x = 0; x < s.dims.x; ++x) {
                const int i = 1 + x, j = 2 + y, k = 3 + z; // the box has one empty voxel around the active ones
                if (!inKnown(i, j, k)) {
                    for (int c = 0; c < 6; ++c) bad += s.value(x, y, z, c) != 0.0f; // no flakes where no fibre
                    continue;
                }
                const openvdb::Vec3s t = knownAxis(i, j, k);
                const float m[3][3] = {{s.value(x, y, z, 0), s.value(x, y, z, 3), s.value(x, y, z, 4)},
                                       {s.value(x, y, z, 3), s.value(x, y, z, 1), s.value(x, y, z, 5)},
                                       {s.value(x, y, z, 4), s.value(x, y, z, 5), s.value(x, y, z, 2)}};
                // S t = sigma^2 t, and S u = u for u across the fibre.
                const openvdb::Vec3s u = t.cross(openvdb::Vec3s(0, 0, 1)).unitSafe();
                for (int i = 0; i < 3; ++i) {
                    const float st = m[i][0] * t[0] + m[i][1] * t[1] + m[i][2] * t[2];
                    const float su = m[i][0] * u[0] + m[i][1] * u[1] + m[i][2] * u[2];
                    bad += std::abs(st - 0.09f * t[i]) > 1e-5f || std::abs(su - u[i]) > 1e-5f;
                }
            }
    CHECK(bad == 0);
}

TEST_CASE("Export: SIGINT during an export stops it with an error and leaves no file", "[export]") {
    const FiberGrids grids = knownGrids();
    const fs::path dir = scratch("interrupted");
    fs::remove_all(dir);
    fs::create_directories(dir);
    {
        const InterruptScope interruptible;
        std::raise(SIGINT); // the handler only records it: the export sees it at its first piece
        VolExportOptions options;
        options.box = VoxelBox{{0, 0, 0}, {64, 64, 64}};
        CHECK_THROWS_WITH(exportMitsubaVol(grids, (dir / "i.vol").string(), options), Catch::Contains("interrupted by SIGINT"));
        CHECK_THROWS_WITH(exportNanoVdb(grids, (dir / "i.nvdb").string()), Catch::Contains("interrupted by SIGINT"));
    }
    { const InterruptScope clear; } // the request outlives its scope (voxelize reads it after); a new scope clears it
    CHECK(interruptSignal() == 0);
    CHECK(fs::is_empty(dir));
}

TEST_CASE("Export: NanoVDB's own reader gives back every voxel of both grids, names and class kept", "[export]") {
    SliceOptions opt;
    opt.radius = 0.2;
    opt.twist = 1.0;
    const SlicePlan plan = planSlices(test::straightYarn({0.5, -0.25, 1}, {1, 0.3, 0.1}, 4), opt);
    const BrickVolume volume = voxelizeCpu(plan, makeFiberCrossSection(), makeGrid(plan, 48, 0.0), VoxelizeSettings{});
    const fs::path vdb = scratch("yarn.vdb"), nvdb = scratch("yarn.nvdb");
    VolumeMetadata meta;
    writeVdb(vdb.string(), volume, meta);
    const FiberGrids grids = readFiberGrids(vdb.string());
    const NanoVdbExportResult r = exportNanoVdb(grids, nvdb.string());
    CHECK(r.grids == 2);
    CHECK(r.bytes == fs::file_size(nvdb));

    auto densityHandle = nanovdb::io::readGrid(nvdb.string(), "density");
    auto orientationHandle = nanovdb::io::readGrid(nvdb.string(), "orientation");
    const nanovdb::FloatGrid* density = densityHandle.grid<float>();
    const nanovdb::Vec3fGrid* orientation = orientationHandle.grid<nanovdb::Vec3f>();
    REQUIRE(density);
    REQUIRE(orientation);
    CHECK(std::string(density->gridName()) == "density");
    CHECK(std::string(orientation->gridName()) == "orientation");
    CHECK(density->gridClass() == nanovdb::GridClass::FogVolume);
    CHECK(density->activeVoxelCount() == grids.density->activeVoxelCount());
    CHECK(orientation->activeVoxelCount() == grids.orientation->activeVoxelCount());
    CHECK(density->voxelSize()[0] == Approx(grids.density->voxelSize()[0]));
    const openvdb::Vec3d w = grids.density->indexToWorld(openvdb::Coord(3, 4, 5));
    const nanovdb::Vec3d nw = density->indexToWorld(nanovdb::Vec3d(3, 4, 5));
    CHECK(nw[0] == Approx(w[0]));
    CHECK(nw[2] == Approx(w[2]));

    auto nd = density->getAccessor();
    auto no = orientation->getAccessor();
    std::size_t checked = 0, mismatches = 0;
    for (auto it = grids.density->cbeginValueOn(); it; ++it) {
        const openvdb::Coord c = it.getCoord();
        const nanovdb::Coord n(c.x(), c.y(), c.z());
        mismatches += nd.getValue(n) != *it || !nd.isActive(n);
        const openvdb::Vec3s a = grids.orientation->tree().getValue(c);
        const nanovdb::Vec3f b = no.getValue(n);
        mismatches += b[0] != a.x() || b[1] != a.y() || b[2] != a.z();
        ++checked;
    }
    CHECK(checked == volume.activeVoxelCount());
    CHECK(mismatches == 0);
    // Outside the yarn NanoVDB reads the background, as OpenVDB does.
    CHECK(nd.getValue(nanovdb::Coord(-100, -100, -100)) == 0.0f);
}

TEST_CASE("CLI: voxelize --format vol and nvdb convert the same voxels as the .vdb, leave no temporary, nanovdb_print reads the .nvdb", "[export][cli]") {
    const fs::path bcc = scratch("knit.bcc", "format"), vdb = scratch("knit.vdb", "format"), vol = scratch("knit.vol", "format"),
                   nvdb = scratch("knit.nvdb", "format");
    for (const fs::path& p : {vdb, vol, nvdb, scratch("knit.orientation.vol", "format")}) fs::remove(p);
    REQUIRE(test::runYarnvox("gen --pattern knit --crossings 20 --shape cylinder --seed 3 -o " + bcc.string()).exitCode == 0);
    const std::string options = " --backend cpu --resolution 48 --twist 1";
    // A .vol or .nvdb output is converted from a float .vdb (without --precision).
    REQUIRE(test::runYarnvox("voxelize " + bcc.string() + " -o " + vdb.string() + options + " --precision float")
                .exitCode == 0);
    const test::RunResult v = test::runYarnvox("voxelize " + bcc.string() + " -o " + vol.string() + options);
    INFO(v.output);
    REQUIRE(v.exitCode == 0);
    CHECK(v.output.find("wrote " + vol.string()) != std::string::npos);
    const test::RunResult n = test::runYarnvox("voxelize " + bcc.string() + " -o " + nvdb.string() + options);
    INFO(n.output);
    REQUIRE(n.exitCode == 0);
    CHECK(partialFiles(vol.parent_path()) == 0);

    // The .vol holds, voxel for voxel, what the .vdb holds over its active bounds and a voxel around them.
    const FiberGrids grids = readFiberGrids(vdb.string());
    openvdb::CoordBBox active = grids.density->evalActiveVoxelBoundingBox();
    active.expand(1);
    const VolFile dv = readVol(vol), ov = readVol(scratch("knit.orientation.vol", "format"));
    REQUIRE(dv.dims == glm::ivec3(active.dim().x(), active.dim().y(), active.dim().z()));
    auto d = grids.density->getConstAccessor();
    auto o = grids.orientation->getConstAccessor();
    std::size_t mismatches = 0;
    for (int z = 0; z < dv.dims.z; ++z)
        for (int y = 0; y < dv.dims.y; ++y)
            for (int x = 0; x < dv.dims.x; ++x) {
                const openvdb::Coord c = active.min() + openvdb::Coord(x, y, z);
                mismatches += dv.value(x, y, z, 0) != d.getValue(c);
                for (int k = 0; k < 3; ++k) mismatches += ov.value(x, y, z, k) != o.getValue(c)[k];
            }
    CHECK(mismatches == 0);
    const openvdb::Vec3d lo = grids.density->indexToWorld(active.min().asVec3d() - openvdb::Vec3d(0.5));
    checkBox(dv, {lo.x(), lo.y(), lo.z()}, {lo.x() + dv.dims.x * grids.density->voxelSize()[0],
                                            lo.y() + dv.dims.y * grids.density->voxelSize()[0],
                                            lo.z() + dv.dims.z * grids.density->voxelSize()[0]});

    // A conversion that fails (the orientation file passes a 200 KiB file-size
    // limit the .vdb stays under) leaves neither outputs nor the temporary .vdb.
    const fs::path failed = scratch("knit-full.vol", "format");
    const test::RunResult full = test::runShell("ulimit -f 200; trap '' XFSZ; exec " + std::string(YV_BINARY_DIR) +
                                                "/yarnvox voxelize " + bcc.string() + " -o " + failed.string() + options);
    INFO(full.output);
    CHECK(full.exitCode == 1);
    CHECK(full.output.find("cannot write") != std::string::npos);
    CHECK(full.output.find("wrote " + failed.string()) == std::string::npos);
    CHECK_FALSE(fs::exists(failed));
    CHECK_FALSE(fs::exists(scratch("knit-full.orientation.vol", "format")));
    CHECK(partialFiles(failed.parent_path()) == 0);

    const test::RunResult printed = test::runShell("nanovdb_print -l " + nvdb.string());
    INFO(printed.output);
    CHECK(printed.exitCode == 0);
    CHECK(printed.output.find("density") != std::string::npos);
    CHECK(printed.output.find("orientation") != std::string::npos);
    CHECK(printed.output.find(std::to_string(grids.density->activeVoxelCount())) != std::string::npos);
}

TEST_CASE("CLI: export crops by --bbox and by --region of the run's work directory", "[export][cli]") {
    const FiberGrids grids = knownGrids();
    const fs::path vdb = scratch("known.vdb"), vol = scratch("known-cli.vol");
    writeGrids(grids, vdb);
    const test::RunResult r =
        test::runYarnvox("export " + vdb.string() + " -o " + vol.string() + " --bbox 1,2,3,6,5,8 --vol-type uint8");
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    checkKnownVolumes(readVol(vol), readVol(scratch("known-cli.orientation.vol")), VoxelBox{{1, 2, 3}, {6, 5, 8}}, 3, 3);

    const test::RunResult w = test::runYarnvox("export " + vdb.string() + " -o " + vol.string() + " --bbox-world " +
                                               "1.5,-0.5,5,2.5,0.5,7 --orientation-vol-type float16");
    INFO(w.output);
    REQUIRE(w.exitCode == 0);
    // x: [1.5, 2.5] -> voxels 1..2 (3 starts on 2.5), y: [-0.5, 0.5] -> 3..4, z: [5, 7] -> 4..7
    checkKnownVolumes(readVol(vol), readVol(scratch("known-cli.orientation.vol")), VoxelBox{{1, 3, 4}, {3, 5, 8}}, 1, 2);

    // A work directory whose two regions split the volume; the .vdb from the same bricks.
    SliceOptions opt;
    opt.radius = 0.2;
    const SlicePlan plan = planSlices(test::straightYarn({0, 0, 0}, {1, 0, 0}, 4), opt);
    const VoxelGrid grid = makeGrid(plan, 40, 0.0);
    const BrickVolume volume = voxelizeCpu(plan, makeFiberCrossSection(), grid, VoxelizeSettings{});
    const fs::path work = scratch("regions.work"), yarn = scratch("regions.vdb"), part = scratch("region1.vol");
    fs::remove_all(work);
    StoreManifest manifest;
    manifest.fingerprint = 42;
    manifest.grid = grid;
    const int half = grid.dims.x / 2;
    {
        BrickStore store(work.string(), manifest, false);
        std::vector<VoxelBrick> left, right;
        for (const VoxelBrick& b : volume.bricks) (brickCoord(b.key).x * 8 < half ? left : right).push_back(b);
        store.writeRegion(0, {0, 0, 0}, {half, grid.dims.y, grid.dims.z}, left);
        store.writeRegion(1, {half, 0, 0}, grid.dims, right);
        store.markComplete(2);
    }
    writeVdb(yarn.string(), volume, VolumeMetadata{});
    const test::RunResult g = test::runYarnvox("export " + yarn.string() + " -o " + part.string() + " --region 1 --work-dir " + work.string());
    INFO(g.output);
    REQUIRE(g.exitCode == 0);
    const VolFile pv = readVol(part);
    CHECK(pv.dims == glm::ivec3(grid.dims.x - half, grid.dims.y, grid.dims.z));
    test::VolumeIndex index(volume);
    std::size_t mismatches = 0, nonzero = 0;
    for (int z = 0; z < pv.dims.z; ++z)
        for (int y = 0; y < pv.dims.y; ++y)
            for (int x = 0; x < pv.dims.x; ++x) {
                mismatches += pv.value(x, y, z, 0) != index.density({half + x, y, z});
                nonzero += pv.value(x, y, z, 0) != 0.0f;
            }
    CHECK(mismatches == 0);
    CHECK(nonzero > 0);
    const double h = grid.voxelSize;
    checkBox(pv, grid.origin + h * glm::dvec3(half, 0, 0), grid.origin + h * glm::dvec3(grid.dims));

    const test::RunResult missing = test::runYarnvox("export " + yarn.string() + " -o " + part.string() + " --region 7 --work-dir " + work.string());
    CHECK(missing.exitCode == 1);
    CHECK(missing.output.find("no such region") != std::string::npos);
    const test::RunResult noDir = test::runYarnvox("export " + yarn.string() + " -o " + part.string() + " --region 1");
    CHECK(noDir.exitCode == 1);
    CHECK(noDir.output.find("needs --work-dir") != std::string::npos);
}

TEST_CASE("CLI: a dense export too large for the disk is refused up front, naming the size, with nothing written", "[export][cli]") {
    const FiberGrids grids = knownGrids();
    const fs::path vdb = scratch("big.vdb", "too-large"), vol = scratch("big.vol", "too-large");
    writeGrids(grids, vdb);
    fs::remove(vol);
    const test::RunResult r =
        test::runYarnvox("export " + vdb.string() + " -o " + vol.string() + " --bbox 0,0,0,1000000,1000000,1000000");
    INFO(r.output);
    CHECK(r.exitCode == 1);
    CHECK(r.output.find("needs 16000000.00 TB") != std::string::npos);
    CHECK(r.output.find("free: nothing was written") != std::string::npos);
    CHECK_FALSE(fs::exists(vol));
    CHECK_FALSE(fs::exists(scratch("big.orientation.vol", "too-large")));
    CHECK(partialFiles(vol.parent_path()) == 0);
}

TEST_CASE("CLI: an export whose write fails (the file-size limit, as a full disk) leaves no file", "[export][cli]") {
    const FiberGrids grids = knownGrids();
    const fs::path vdb = scratch("full.vdb", "full-disk"), vol = scratch("full.vol", "full-disk"), nvdb = scratch("full.nvdb", "full-disk");
    writeGrids(grids, vdb);
    for (const fs::path& p : {vol, nvdb, scratch("full.orientation.vol", "full-disk")}) fs::remove(p);
    // 64^3 voxels of float32: 1 MiB of density, past a 64 KiB limit.
    const std::string limit = "ulimit -f 64; trap '' XFSZ; exec " + std::string(YV_BINARY_DIR) + "/yarnvox export " + vdb.string();
    const test::RunResult r = test::runShell(limit + " -o " + vol.string() + " --bbox 0,0,0,64,64,64");
    INFO(r.output);
    CHECK(r.exitCode == 1);
    CHECK(r.output.find("cannot write") != std::string::npos);
    CHECK_FALSE(fs::exists(vol));
    CHECK_FALSE(fs::exists(scratch("full.orientation.vol", "full-disk")));
    CHECK(partialFiles(vol.parent_path()) == 0);
    // Without the limit the same export is whole.
    REQUIRE(test::runYarnvox("export " + vdb.string() + " -o " + vol.string() + " --bbox 0,0,0,64,64,64").exitCode == 0);
    CHECK(fs::file_size(vol) == 48 + 64 * 64 * 64 * 4);
}

TEST_CASE("CLI: export refuses what it cannot write with one line", "[export][cli]") {
    const FiberGrids grids = knownGrids();
    const fs::path vdb = scratch("known-bad.vdb");
    writeGrids(grids, vdb);
    const auto fails = [&](const std::string& args, const std::string& says) {
        const test::RunResult r = test::runYarnvox("export " + args);
        INFO(args << "\n" << r.output);
        CHECK(r.exitCode != 0);
        CHECK(r.output.find(says) != std::string::npos);
    };
    fails(vdb.string() + " -o " + scratch("x.txt").string(), "give --format vol or nvdb");
    fails(vdb.string() + " -o " + scratch("x.vol").string() + " --bbox 1,2,3", "expected six numbers");
    fails(vdb.string() + " -o " + scratch("x.vol").string() + " --bbox 4,4,4,4,5,5", "holds no voxel");
    fails(vdb.string() + " -o " + scratch("x.vol").string() + " --bbox 0.5,0,0,4,4,4", "whole numbers");
    fails(vdb.string() + " -o " + scratch("x.nvdb").string() + " --bbox 0,0,0,4,4,4", "apply to .vol exports");
    fails(scratch("absent.vdb").string() + " -o " + scratch("x.vol").string(), "no such file");
    fails(vdb.string() + " -o " + vdb.string() + ".vol --vol-type int16", "--vol-type");
    CHECK_FALSE(fs::exists(scratch("x.vol")));
}

TEST_CASE("CLI: a .vdb with only a density grid exports the density alone, and a grid of the wrong type is refused", "[export][cli]") {
    const FiberGrids grids = knownGrids();
    const fs::path vdb = scratch("density-only.vdb"), vol = scratch("density-only.vol"), nvdb = scratch("density-only.nvdb");
    for (const fs::path& p : {vol, nvdb, scratch("density-only.orientation.vol")}) fs::remove(p);
    {
        openvdb::io::File file(vdb.string());
        file.write(openvdb::GridPtrVec{grids.density});
        file.close();
    }
    const test::RunResult r = test::runYarnvox("export " + vdb.string() + " -o " + vol.string());
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    CHECK(r.output.find("only the density was exported") != std::string::npos);
    CHECK_FALSE(fs::exists(scratch("density-only.orientation.vol")));
    const VolFile dv = readVol(vol);
    CHECK(dv.channels == 1);
    CHECK(dv.value(1, 1, 1, 0) == knownDensity(2, 3, 4)); // the box starts one voxel before the first active one
    REQUIRE(test::runYarnvox("export " + vdb.string() + " -o " + nvdb.string()).exitCode == 0);
    CHECK(nanovdb::io::readGridMetaData(nvdb.string()).size() == 1);

    // 'density' of another type, and an 'orientation' that is not vec3s.
    const fs::path wrong = scratch("wrong-types.vdb");
    openvdb::Vec3SGrid::Ptr vectorDensity = openvdb::Vec3SGrid::create();
    vectorDensity->setName("density");
    openvdb::io::File(wrong.string()).write(openvdb::GridPtrVec{vectorDensity});
    const test::RunResult v = test::runYarnvox("export " + wrong.string() + " -o " + vol.string());
    CHECK(v.exitCode == 1);
    CHECK(v.output.find("has no float grid named 'density'") != std::string::npos);
    openvdb::FloatGrid::Ptr floatOrientation = openvdb::FloatGrid::create();
    floatOrientation->setName("orientation");
    openvdb::io::File(wrong.string()).write(openvdb::GridPtrVec{grids.density, floatOrientation});
    const test::RunResult o = test::runYarnvox("export " + wrong.string() + " -o " + vol.string());
    CHECK(o.exitCode == 1);
    CHECK(o.output.find("'orientation' grid is not a vec3s grid") != std::string::npos);
}
