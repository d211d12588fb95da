// BCC reader/writer: golden layout, round trips, and that every corruption is caught and located.
#include "bcc.h"

#include "core/error.h"

#include <catch2/catch.hpp>

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using Bytes = std::vector<std::uint8_t>;

namespace {

// Three yarns (open 4, closed 5, open 2 points) with float-representable
// coordinates, so a round trip must be exact. Encoded layout:
// header 0..64, yarn 0 count at 64, yarn 1 count at 116, yarn 2 count at 180, end at 208.
yv::Garment sampleGarment(yv::CurveType type) {
    yv::Garment g;
    g.curveType = type;
    g.yarns.push_back({{{0, 0, 0}, {1, 0.5, -0.25}, {2, 1, 0}, {3, 0.5, 0.125}}, false});
    g.yarns.push_back({{{-1, -1, 4}, {1, -1, 4}, {1.5, 0, 4}, {1, 1, 4}, {-1, 1, 4.75}}, true});
    g.yarns.push_back({{{1e6, -1e-3f, 3.0e-5f}, {-65536.5, 0.1f, 7}}, false});
    return g;
}

void requireSame(const yv::Garment& got, const yv::Garment& want) {
    REQUIRE(got.curveType == want.curveType);
    REQUIRE(got.yarns.size() == want.yarns.size());
    for (std::size_t i = 0; i < want.yarns.size(); ++i) {
        INFO("yarn " << i);
        CHECK(got.yarns[i].closed == want.yarns[i].closed);
        CHECK(got.yarns[i].points == want.yarns[i].points);
    }
    CHECK(got.yarnRadius == want.yarnRadius);
}

void poke(Bytes& b, std::size_t at, std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) b.at(at + i) = static_cast<std::uint8_t>(v >> (8 * i));
}

std::string parseError(const Bytes& bytes) {
    try {
        yv::parseBcc(bytes, "t.bcc");
    } catch (const yv::Error& e) {
        return e.what();
    }
    FAIL("parseBcc accepted a corrupt buffer");
    return {};
}

// A fresh directory per test, so leftover temporary files can be counted.
struct TempDir {
    fs::path path;
    TempDir() {
        std::random_device rd;
        path = fs::temp_directory_path() /
               ("yv_test_bcc_" + std::to_string(::getpid()) + "_" + std::to_string(rd()));
        fs::create_directories(path);
    }
    ~TempDir() { fs::remove_all(path); }
    std::size_t entries() const {
        return static_cast<std::size_t>(std::distance(fs::directory_iterator(path), fs::directory_iterator()));
    }
};

} // namespace

TEST_CASE("bcc: golden bytes of a one-curve file", "[bcc]") {
    // One closed C0 curve of 3 points: (1,2,3), (0.5,-1,0), (-2,0.25,8).
    const Bytes golden = {
        'B', 'C', 'C', 0x44, 'C', '0', 3, 2,             // signature, byteCount, curveType, dims, up
        1, 0, 0, 0, 0, 0, 0, 0,                          // curveCount = 1
        3, 0, 0, 0, 0, 0, 0, 0,                          // totalControlPointCount = 3
        'y', 'a', 'r', 'n', 'v', 'o', 'x', 0, 0, 0,      // fileInfo[40]
        0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
        0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
        0xfd, 0xff, 0xff, 0xff,                          // count = -3: closed, 3 points
        0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x00, 0x40, 0x00, 0x00, 0x40, 0x40, // 1, 2, 3
        0x00, 0x00, 0x00, 0x3f, 0x00, 0x00, 0x80, 0xbf, 0x00, 0x00, 0x00, 0x00, // 0.5, -1, 0
        0x00, 0x00, 0x00, 0xc0, 0x00, 0x00, 0x80, 0x3e, 0x00, 0x00, 0x00, 0x41, // -2, 0.25, 8
    };
    REQUIRE(golden.size() == 64 + 4 + 36);

    yv::Garment g;
    g.yarns.push_back({{{1, 2, 3}, {0.5, -1, 0}, {-2, 0.25, 8}}, true});
    CHECK(yv::encodeBcc(g) == golden);
    requireSame(yv::parseBcc(golden, "golden.bcc"), g);

    g.curveType = yv::CurveType::Polyline;
    const Bytes pl = yv::encodeBcc(g);
    CHECK(pl[4] == 'P');
    CHECK(pl[5] == 'L');
}

TEST_CASE("bcc: round trip is exact for open and closed curves", "[bcc]") {
    const auto type = GENERATE(yv::CurveType::CatmullRom, yv::CurveType::Polyline);
    yv::Garment g = sampleGarment(type);
    g.yarnRadius = 0.3; // stored in fileInfo: reads back exactly
    const Bytes bytes = yv::encodeBcc(g);
    CHECK(bytes.size() == 208);
    requireSame(yv::parseBcc(bytes, "rt.bcc"), g);
}

TEST_CASE("bcc: an empty garment round-trips", "[bcc]") {
    const yv::Garment g;
    const Bytes bytes = yv::encodeBcc(g);
    CHECK(bytes.size() == 64);
    CHECK(yv::parseBcc(bytes, "empty.bcc").yarns.empty());
}

TEST_CASE("bcc: every truncated prefix is rejected", "[bcc]") {
    const Bytes full = yv::encodeBcc(sampleGarment(yv::CurveType::CatmullRom));
    REQUIRE_NOTHROW(yv::parseBcc(full, "full.bcc"));
    for (std::size_t len = 0; len < full.size(); ++len) {
        INFO("prefix length " << len);
        const Bytes prefix(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(len));
        CHECK_THROWS_AS(yv::parseBcc(prefix, "cut.bcc"), yv::Error);
    }
}

TEST_CASE("bcc: corruptions name the offset and the reason", "[bcc]") {
    const Bytes good = yv::encodeBcc(sampleGarment(yv::CurveType::CatmullRom));
    Bytes b = good;

    SECTION("short non-BCC file") {
        CHECK_THAT(parseError({'P', 'K'}), Contains("t.bcc: byte 0: expected signature \"BCC\", found \"PK\""));
    }
    SECTION("signature") {
        b[0] = 'X';
        CHECK_THAT(parseError(b), Contains("byte 0: expected signature \"BCC\", found \"XCC\""));
    }
    SECTION("truncated header") {
        b.resize(10);
        CHECK_THAT(parseError(b), Equals("t.bcc: byte 10: truncated header: expected 64-byte header, file ends"));
    }
    SECTION("byteCount") {
        b[3] = 0x48;
        CHECK_THAT(parseError(b), Contains("byte 3: unsupported byteCount 0x48: expected 0x44"));
    }
    SECTION("curveType") {
        b[5] = '1';
        CHECK_THAT(parseError(b), Contains("byte 4: unsupported curve type \"C1\""));
    }
    SECTION("dimensions") {
        b[6] = 2;
        CHECK_THAT(parseError(b), Contains("byte 6: unsupported dimensions 2: expected 3"));
    }
    SECTION("curve count too large: data ends") {
        poke(b, 8, 4, 8);
        CHECK_THAT(parseError(b),
                   Equals("t.bcc: byte 208: truncated curve 3: expected 4-byte control-point count, file ends"));
    }
    SECTION("curve count too small: trailing bytes") {
        poke(b, 8, 2, 8);
        CHECK_THAT(parseError(b), Contains("byte 180: 28 trailing bytes after the last of 2 curves"));
    }
    SECTION("huge curve count is refused before allocating") {
        poke(b, 8, std::numeric_limits<std::uint64_t>::max(), 8);
        CHECK_THAT(parseError(b), Contains("byte 8: curve count 18446744073709551615 cannot fit"));
    }
    SECTION("total point count disagrees with the curves") {
        poke(b, 16, 12, 8);
        CHECK_THAT(parseError(b), Contains("byte 16: header total control-point count 12") &&
                                      Contains("curves' sum 11"));
        poke(b, 16, std::numeric_limits<std::uint64_t>::max(), 8);
        CHECK_THAT(parseError(b), Contains("byte 16:"));
    }
    SECTION("curve with fewer than 2 points") {
        poke(b, 116, 1, 4);
        CHECK_THAT(parseError(b), Contains("byte 116: curve 1 has 1 control points: expected at least 2"));
        poke(b, 116, 0, 4);
        CHECK_THAT(parseError(b), Contains("byte 116: curve 1 has 0 control points"));
        poke(b, 116, static_cast<std::uint32_t>(-1), 4);
        CHECK_THAT(parseError(b), Contains("byte 116: curve 1 has 1 control points"));
    }
    SECTION("INT32_MIN count is not negated into garbage") {
        poke(b, 116, 0x80000000u, 4);
        CHECK_THAT(parseError(b), Contains("byte 120: truncated curve 1: expected 2147483648 control points"));
    }
    SECTION("points run past the end") {
        b.resize(b.size() - 4);
        CHECK_THAT(parseError(b),
                   Contains("byte 184: truncated curve 2: expected 2 control points (24 bytes), file ends after 20"));
    }
    SECTION("NaN coordinate") {
        poke(b, 120 + 2 * 12 + 4, 0x7fc00000u, 4); // curve 1, point 2, y
        CHECK_THAT(parseError(b), Contains("byte 148: curve 1 point 2: y coordinate is nan"));
    }
    SECTION("infinite coordinate") {
        poke(b, 68 + 8, 0xff800000u, 4); // curve 0, point 0, z
        CHECK_THAT(parseError(b), Contains("byte 76: curve 0 point 0: z coordinate is -inf"));
    }
    // Counts are read first and points on every core; the first problem in
    // file order is still the one said.
    SECTION("a bad point before a broken count: the point") {
        poke(b, 120 + 2 * 12 + 4, 0x7fc00000u, 4); // curve 1, point 2, y
        b.resize(b.size() - 4);                    // curve 2 truncated
        CHECK_THAT(parseError(b), Contains("byte 148: curve 1 point 2: y coordinate is nan"));
    }
    SECTION("a broken count before a bad point: the count") {
        poke(b, 116, 1, 4);                   // curve 1's count
        poke(b, 196, 0x7f800000u, 4);         // curve 2, point 1, x
        CHECK_THAT(parseError(b), Contains("byte 116: curve 1 has 1 control points"));
    }
    SECTION("bad points in several curves: the first curve's") {
        poke(b, 196, 0x7f800000u, 4);         // curve 2, point 1, x
        poke(b, 68 + 12 + 4, 0x7fc00000u, 4); // curve 0, point 1, y
        CHECK_THAT(parseError(b), Contains("byte 84: curve 0 point 1: y coordinate is nan"));
    }
}

TEST_CASE("bcc: encoding refuses what the reader would reject", "[bcc]") {
    yv::Garment g = sampleGarment(yv::CurveType::CatmullRom);
    SECTION("one-point yarn") {
        g.yarns[1].points.resize(1);
        CHECK_THROWS_WITH(yv::encodeBcc(g), Contains("yarn 1 has 1 control points"));
    }
    SECTION("NaN") {
        g.yarns[2].points[1].x = std::numeric_limits<double>::quiet_NaN();
        CHECK_THROWS_WITH(yv::encodeBcc(g), Contains("yarn 2 point 1: x coordinate"));
    }
    SECTION("beyond float range") {
        g.yarns[0].points[3].z = 1e39;
        CHECK_THROWS_WITH(yv::encodeBcc(g), Contains("yarn 0 point 3: z coordinate"));
    }
}

TEST_CASE("bcc: writeBcc and readBcc through a file", "[bcc]") {
    TempDir dir;
    const std::string path = (dir.path / "garment.bcc").string();
    const yv::Garment g = sampleGarment(yv::CurveType::Polyline);

    yv::writeBcc(path, g);
    requireSame(yv::readBcc(path), g);
    CHECK(dir.entries() == 1); // no temporary left behind

    SECTION("overwriting replaces the file") {
        const yv::Garment other = sampleGarment(yv::CurveType::CatmullRom);
        yv::writeBcc(path, other);
        requireSame(yv::readBcc(path), other);
        CHECK(dir.entries() == 1);
    }
    SECTION("a failed write leaves the old file and no temporary") {
        yv::Garment bad = g;
        bad.yarns[0].points.resize(1);
        CHECK_THROWS_WITH(yv::writeBcc(path, bad), Contains(path));
        requireSame(yv::readBcc(path), g);
        CHECK(dir.entries() == 1);
    }
    SECTION("a missing directory is named") {
        const std::string missing = (dir.path / "no" / "such" / "x.bcc").string();
        CHECK_THROWS_WITH(yv::writeBcc(missing, g), Contains(missing));
        CHECK(dir.entries() == 1);
    }
    SECTION("a rename that fails removes the temporary") {
        // Renaming a file over a non-empty directory fails after the data is written.
        const fs::path blocker = dir.path / "blocker.bcc";
        fs::create_directories(blocker / "inside");
        CHECK_THROWS_WITH(yv::writeBcc(blocker.string(), g), Contains("cannot write " + blocker.string()));
        CHECK(dir.entries() == 2);
    }
    SECTION("errors from a file name the path") {
        std::ofstream(path, std::ios::binary | std::ios::trunc) << "BCC\x44";
        CHECK_THROWS_WITH(yv::readBcc(path), Contains(path + ": byte 4: truncated header"));
    }
}

TEST_CASE("bcc: reading a missing path names it", "[bcc]") {
    TempDir dir;
    const std::string path = (dir.path / "missing.bcc").string();
    CHECK_THROWS_AS(yv::readBcc(path), yv::Error);
    CHECK_THROWS_WITH(yv::readBcc(path), Contains("cannot open " + path));
    CHECK_THROWS_WITH(yv::readBcc(dir.path.string()), Contains(dir.path.string()));
}

TEST_CASE("BCC: the yarn radius travels in the free-text field", "[bcc]") {
    yv::Garment g;
    g.yarns.push_back(yv::Yarn{{{0, 0, 0}, {1, 0, 0}}, false});
    g.yarnRadius = 0.125;
    const std::vector<std::uint8_t> bytes = yv::encodeBcc(g);
    CHECK(std::string(reinterpret_cast<const char*>(bytes.data() + 24)) == "yarnvox yarn-radius=0.125");
    CHECK(yv::parseBcc(bytes, "r.bcc").yarnRadius == 0.125);
}
