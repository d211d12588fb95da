// The fuzz targets' inputs (tests/fuzz-corpus/<target>/: the seeds, and every
// input that once crashed a reader) through the real readers, the way the
// targets in fuzz/ call them: each is read, or refused with yv::Error. This
// keeps what the fuzzer found in the normal suite, and in its sanitizer run.
#include "bcc.h"
#include "core/error.h"
#include "inspect/volume_source.h"
#include "garment/cross_section.h"
#include "inspect/transfer_function.h"
#include "store/manifest.h"
#include "store/region_file.h"
#include "vdb/vdb_file_check.h"
#include "view/view_message.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;

namespace {

Bytes fileBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return Bytes(std::istreambuf_iterator<char>(in), {});
}

/// Runs `read` on every file of the target's corpus; returns how many it accepted.
int replay(const std::string& target, const std::function<void(const fs::path&, const Bytes&)>& read) {
    const fs::path dir = fs::path(YV_SOURCE_DIR) / "tests" / "fuzz-corpus" / target;
    int files = 0, accepted = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
        ++files;
        INFO(e.path().string());
        try {
            read(e.path(), fileBytes(e.path()));
            ++accepted;
        } catch (const yv::Error& err) {
            CHECK(std::string(err.what()).size() > 0);
        }
    }
    CHECK(files >= 3);
    return accepted;
}

} // namespace

TEST_CASE("Fuzz corpus: every BCC input is read or refused with an error", "[fuzz-corpus][bcc]") {
    const int accepted = replay("bcc", [](const fs::path&, const Bytes& b) {
        (void)yv::parseBcc(yv::encodeBcc(yv::parseBcc(b, "corpus.bcc")), "roundtrip.bcc");
    });
    CHECK(accepted >= 2); // the valid seeds
}

TEST_CASE("Fuzz corpus: every PNG cross-section input is read or refused with an error", "[fuzz-corpus][png]") {
    CHECK(replay("png", [](const fs::path& p, const Bytes&) { (void)yv::loadCrossSectionPng(p.string()); }) >= 2);
}

TEST_CASE("Fuzz corpus: every manifest input is read or refused with an error", "[fuzz-corpus][store]") {
    const int accepted = replay("manifest", [](const fs::path&, const Bytes& b) {
        const yv::StoreManifest m = yv::parseManifest("corpus", std::string(b.begin(), b.end()));
        const yv::StoreManifest back = yv::parseManifest("again", yv::formatManifest(m));
        CHECK(yv::runDifference(m, back).empty());
        CHECK(yv::metadataFields(back.run) == yv::metadataFields(m.run));
    });
    CHECK(accepted >= 2);
}

TEST_CASE("Fuzz corpus: every region-file input is read or refused with an error", "[fuzz-corpus][store]") {
    const int accepted = replay("region", [](const fs::path&, const Bytes& b) {
        const yv::RegionHeader h = yv::parseRegionHeader(b.data(), b.size(), "region-0.yvb");
        yv::StoreManifest run;
        run.fingerprint = h.fingerprint;
        run.grid = h.grid;
        run.reduce = h.reduce;
        yv::checkRegionIdentity(h, run, h.id, &h.min, &h.max, "region-0.yvb");
        std::vector<yv::VoxelBrick> bricks;
        yv::decodeRegionBody(b.data(), h, "region-0.yvb", &bricks);
    });
    CHECK(accepted >= 3);
}

TEST_CASE("Fuzz corpus: every .vdb input is read whole or refused with an error", "[fuzz-corpus][vdb]") {
    const int accepted = replay("vdb", [](const fs::path& p, const Bytes&) {
        const auto source = yv::openVdbSource(p.string());
        std::uint64_t bricks = 0;
        for (int level : source->storedLevels())
            source->forEachLevelBrick(level, glm::ivec3(-(1 << 28)), glm::ivec3(1 << 28), [&](const yv::SourceBrick&) { ++bricks; });
        CHECK(bricks >= source->occupiedBricks().size());
    });
    CHECK(accepted >= 2); // the seeds yarnvox wrote whole
}

TEST_CASE("Fuzz corpus: every .vdb input is checked whole, checksums included, or refused with an error", "[fuzz-corpus][vdb]") {
    int checksummed = 0;
    const int accepted = replay("vdb", [&](const fs::path& p, const Bytes&) {
        checksummed += yv::checkVdbFile(p.string()).gridsChecked > 0;
    });
    CHECK(accepted >= 3);    // the seeds yarnvox wrote whole
    CHECK(checksummed >= 1); // the seed written since files record checksums
}

TEST_CASE("A PNG too short for the image its header claims is refused before the image is allocated", "[fuzz-corpus][png]") {
    // 8192 x 8192 16-bit RGBA (512 MiB raw) in under 100 bytes: deflate cannot
    // pack that tight, so the reader refuses it instead of allocating 128 MiB.
    const fs::path p = fs::path(YV_SOURCE_DIR) / "tests" / "fuzz-corpus" / "png" / "huge-header-tiny-file.png";
    CHECK_THROWS_WITH(yv::loadCrossSectionPng(p.string()),
                      Catch::Contains("corrupt or truncated PNG") && Catch::Contains("cannot hold the 8192x8192 image"));
}

TEST_CASE("Fuzz corpus: every colour map input is read or refused with an error", "[fuzz-corpus][inspect]") {
    const int accepted = replay("colour_map", [](const fs::path&, const Bytes& b) {
        const yv::TransferFunction tf = yv::parseColourMap(std::string(b.begin(), b.end()), "corpus");
        for (const auto& e : tf)
            for (int c = 0; c < 4; ++c) CHECK((e[c] >= 0.0f && e[c] <= 1.0f));
    });
    CHECK(accepted >= 2);
}

TEST_CASE("Fuzz corpus: every view message input is read or refused with an error", "[fuzz-corpus][view]") {
    const int accepted = replay("view_message", [](const fs::path&, const Bytes& b) {
        const yv::ViewMessage m = yv::parseViewMessage(std::string(b.begin(), b.end()));
        CHECK(yv::formatViewMessage(yv::parseViewMessage(yv::formatViewMessage(m))) == yv::formatViewMessage(m));
    });
    CHECK(accepted >= 5); // the valid seeds
}
