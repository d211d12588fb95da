// What the --bbox tests share: a generated flat garment with a colour
// cross-section (so albedo is checked too), the voxels of a .vdb read back
// through OpenVDB, and the per-voxel check that a box run is the whole run
// restricted to its box.
#pragma once

#include "export/fiber_grids.h"
#include "run_cli.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <openvdb/openvdb.h>
#include <png.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace yv::test {

/// One active voxel of a .vdb: its density, fibre axis and colour.
struct BoxTestVoxel {
    float density = 0.0f;
    openvdb::Vec3f axis{0.0f}, albedo{0.0f};
    bool operator==(const BoxTestVoxel& o) const { return density == o.density && axis == o.axis && albedo == o.albedo; }
};
using BoxTestVoxels = std::map<std::array<int, 3>, BoxTestVoxel>;

/// Every active voxel of the level-0 density grid of `vdb`, keyed by index.
inline BoxTestVoxels readActiveVoxels(const std::filesystem::path& vdb) {
    const FiberGrids grids = readFiberGrids(vdb.string());
    REQUIRE(grids.orientation);
    const auto axes = grids.orientation->getConstAccessor();
    BoxTestVoxels out;
    for (auto it = grids.density->cbeginValueOn(); it; ++it) {
        const openvdb::Coord c = it.getCoord();
        BoxTestVoxel v;
        v.density = *it;
        v.axis = axes.getValue(c);
        if (grids.albedo) v.albedo = grids.albedo->getConstAccessor().getValue(c);
        out[{c.x(), c.y(), c.z()}] = v;
    }
    return out;
}

/// A box in voxel indices, max exclusive, as --bbox takes it.
struct TestBox {
    std::array<int, 3> min{}, max{};
    bool contains(const std::array<int, 3>& v) const {
        for (int a = 0; a < 3; ++a)
            if (v[a] < min[a] || v[a] >= max[a]) return false;
        return true;
    }
    std::string text() const {
        std::ostringstream s;
        s << min[0] << ',' << min[1] << ',' << min[2] << ',' << max[0] << ',' << max[1] << ',' << max[2];
        return s.str();
    }
};

/// Checks, voxel by voxel, that `box` (the box run's voxels) holds exactly
/// the whole run's voxels inside `b`, with the same values, and none outside
/// it. Returns how many voxels matched, and (in `onFaces`) how many of them
/// lie on a face of the box that cuts into the grid.
inline std::uint64_t checkBoxIsWholeRestricted(const BoxTestVoxels& whole, const BoxTestVoxels& box, const TestBox& b,
                                               std::uint64_t* onFaces = nullptr) {
    std::uint64_t matched = 0, faces = 0;
    for (const auto& [coord, voxel] : box) {
        INFO("voxel " << coord[0] << "," << coord[1] << "," << coord[2] << " of the box run");
        REQUIRE(b.contains(coord));
        const auto it = whole.find(coord);
        REQUIRE(it != whole.end());
        REQUIRE(voxel.density == it->second.density);
        REQUIRE(voxel.axis == it->second.axis);
        REQUIRE(voxel.albedo == it->second.albedo);
    }
    for (const auto& [coord, voxel] : whole) {
        if (!b.contains(coord)) continue;
        INFO("voxel " << coord[0] << "," << coord[1] << "," << coord[2] << " of the whole run");
        REQUIRE(box.count(coord) == 1);
        ++matched;
        for (int a = 0; a < 3; ++a) faces += coord[a] == b.min[a] || coord[a] == b.max[a] - 1;
    }
    if (onFaces) *onFaces = faces;
    return matched;
}

inline nlohmann::json readStats(const std::filesystem::path& p) {
    std::ifstream in(p);
    return nlohmann::json::parse(in);
}

/// A square RGBA PNG, two colours split at x = size / 2, alpha 255 inside
/// the unit disk: a cross-section that gives every run an albedo grid.
inline std::filesystem::path writeTwoColourPng(const std::filesystem::path& path, int size) {
    std::vector<std::uint8_t> pixels(std::size_t(size) * size * 4);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const double u = (x + 0.5) / size * 2 - 1, v = (y + 0.5) / size * 2 - 1;
            std::uint8_t* p = &pixels[(std::size_t(y) * size + x) * 4];
            p[0] = x < size / 2 ? 230 : 15, p[1] = x < size / 2 ? 20 : 40, p[2] = x < size / 2 ? 10 : 220;
            p[3] = u * u + v * v < 1.0 ? 255 : 0;
        }
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = image.height = std::uint32_t(size);
    image.format = PNG_FORMAT_RGBA;
    REQUIRE(png_image_write_to_file(&image, path.c_str(), 0, pixels.data(), 0, nullptr));
    return path;
}

/// A flat twill, small zoom regions (several in the whole run and in the
/// box), and a box whose six faces lie off the brick lattice and cut
/// through the yarns (z from the middle of the cloth).
struct BoxFixture {
    ScratchDir dir{"yv_bbox"};
    std::string bcc = (dir.path / "g.bcc").string();
    std::string png = writeTwoColourPng(dir.path / "xs.png", 32).string();
    std::string options;
    explicit BoxFixture(const std::string& backend)
        : options(" --backend " + backend + " --resolution 80 --fragment-budget 20000 --quiet --albedo --cross-section " +
                  (dir.path / "xs.png").string()) {
        REQUIRE(runYarnvox("gen --pattern twill --shape flat --crossings 100 --quiet -o " + bcc).exitCode == 0);
    }
    std::filesystem::path path(const std::string& name) const { return dir.path / name; }
    /// `yarnvox voxelize` of the garment with the fixture's options and `more`; checks it succeeded.
    void voxelize(const std::filesystem::path& out, const std::string& more) const {
        const RunResult r = runYarnvox("voxelize " + bcc + " -o " + out.string() + options + " " + more);
        INFO(r.output);
        REQUIRE(r.exitCode == 0);
    }
    /// The grid's dims, from a run's --stats ("80x80x16").
    static std::array<int, 3> dims(const nlohmann::json& stats) {
        std::array<int, 3> d{};
        char x1 = 0, x2 = 0;
        std::istringstream(stats["grid_dims"].get<std::string>()) >> d[0] >> x1 >> d[1] >> x2 >> d[2];
        return d;
    }
    /// The box the tests cut: off the brick lattice on every face, through the yarns.
    static TestBox cuttingBox(const std::array<int, 3>& d) {
        return {{d[0] / 4 + 3, d[1] / 3 + 1, d[2] / 2 - 1}, {d[0] * 2 / 3 + 2, d[1] * 3 / 4 - 3, d[2] - 5}};
    }
};

} // namespace yv::test
