// Two volumes side by side with one camera (`yarnvox view A --beside B`):
// a volume beside itself is the same picture twice, and follows the camera
// in both halves; the same garment voxelized at another resolution lies in
// the same place of the other half (both record where they lie in the
// world), drawn from its own voxels.
#include "inspect/brick_level.h"
#include "inspect/volume_source.h"
#include "render/brick_atlas.h"
#include "served_view.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using Json = nlohmann::json;
using yv::test::Page;
using yv::test::ServedView;
using yv::test::meanDifference;

namespace {

/// One half of a side-by-side picture (the left `width / 2` columns, or the rest).
yv::RgbImage half(const yv::RgbImage& image, bool right) {
    const int x0 = right ? image.width / 2 : 0, w = right ? image.width - image.width / 2 : image.width / 2;
    yv::RgbImage out(w, image.height);
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) out.at(x, y)[c] = image.at(x0 + x, y)[c];
    return out;
}

/// Where the garment is in a picture: the mean of its lit pixels, and how many.
struct Lit {
    double x = 0.0, y = 0.0;
    int count = 0;
};
Lit lit(const yv::RgbImage& image) {
    Lit l;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const std::uint8_t* p = image.at(x, y);
            if (int(p[0]) + p[1] + p[2] < 40) continue; // JPEG's ringing around the background stays below
            l.x += x, l.y += y, ++l.count;
        }
    if (l.count) l.x /= l.count, l.y /= l.count;
    return l;
}

} // namespace

TEST_CASE("View: a volume beside itself is the same picture in both halves, and both follow the camera", "[view][gl]") {
    YV_REQUIRE_GL();
    ServedView view(true, [](yv::ViewRequest& r) {
        r.beside = r.input;
        r.initial.width = 256;
        r.initial.height = 128;
    });
    Page page(view.port.get_future().get());
    INFO(page.hello.dump());
    CHECK(page.hello["sideBySide"] == true);
    CHECK(page.hello["beside"] == "plain.vdb");
    const std::vector<std::string> modes = page.hello["modes"];
    CHECK(std::find(modes.begin(), modes.end(), "slices") == modes.end()); // both halves draw volumes
    std::uint64_t seq = 0;
    page.sendCamera(30, 20, 2.5, ++seq);
    const yv::RgbImage first = page.frameOf(seq).second;
    CHECK(lit(half(first, false)).count > 200);
    CHECK(meanDifference(half(first, false), half(first, true)) < 0.5);
    page.sendCamera(75, 40, 2.0, ++seq);
    const yv::RgbImage moved = page.frameOf(seq).second;
    CHECK(meanDifference(half(moved, false), half(moved, true)) < 0.5);
    CHECK(meanDifference(half(first, false), half(moved, false)) > 2.0);
    CHECK(meanDifference(half(first, true), half(moved, true)) > 2.0);
    // Every mode of both draws in both halves.
    for (const std::string& mode : modes) {
        page.send(Json{{"type", "mode"}, {"mode", mode}}.dump());
        page.sendCamera(30, 20, 2.5, ++seq);
        const auto [stats, picture] = page.frameOf(seq);
        INFO(mode);
        CHECK(stats["mode"] == mode);
        CHECK(lit(half(picture, true)).count > 100);
        CHECK(meanDifference(half(picture, false), half(picture, true)) < 0.5);
    }
    // Blending belongs to a garment's slices: two volumes stay side by side.
    page.send(R"({"type":"layout","blend":true})");
    page.sendCamera(30, 20, 2.5, ++seq);
    CHECK(page.frameOf(seq).first["blend"] == false);
    CHECK(!view.failure);
}

TEST_CASE("View: the same garment at another resolution lies in the same place of the other half", "[view][gl]") {
    YV_REQUIRE_GL();
    ServedView view(true, [](yv::ViewRequest& r) {
        const fs::path coarse = fs::path(r.saveDir) / "coarse.vdb";
        REQUIRE(yv::test::runYarnvox("voxelize " + (fs::path(r.saveDir) / "plain.bcc").string() +
                                     " --resolution 20 --quiet -o " + coarse.string())
                    .exitCode == 0);
        r.beside = coarse.string();
        r.initial.width = 256;
        r.initial.height = 128;
    });
    Page page(view.port.get_future().get());
    CHECK(page.hello["beside"] == "coarse.vdb");
    std::uint64_t seq = 0;
    for (const double azimuth : {30.0, 120.0}) {
        page.sendCamera(azimuth, 25, 2.5, ++seq);
        const yv::RgbImage picture = page.frameOf(seq).second;
        const Lit fine = lit(half(picture, false)), coarse = lit(half(picture, true));
        INFO("azimuth " << azimuth << ": fine at " << fine.x << "," << fine.y << " (" << fine.count << "), coarse at "
                        << coarse.x << "," << coarse.y << " (" << coarse.count << ")");
        REQUIRE(fine.count > 200);
        REQUIRE(coarse.count > 200);
        // The same place (within a couple of pixels of a 128-pixel-wide half) from other voxels.
        CHECK(std::abs(fine.x - coarse.x) < 3.0);
        CHECK(std::abs(fine.y - coarse.y) < 3.0);
        CHECK(meanDifference(half(picture, false), half(picture, true)) > 0.5);
    }
    CHECK(!view.failure);
}

TEST_CASE("View: two volumes side by side share the GPU budget, half each", "[view][gl]") {
    YV_REQUIRE_GL();
    // A budget that holds the volume's finest level once and a half: alone
    // it is drawn at level 0, beside another each half holds a coarser one.
    std::uint64_t budget = 0;
    int levelAtHalf = -1;
    const auto atBudget = [&](bool beside) {
        ServedView view(true, [&](yv::ViewRequest& r) {
            const std::unique_ptr<yv::VolumeSource> source = yv::openVolumeSource(r.input);
            const int bytesPerVoxel = yv::atlasBytesPerVoxel(false);
            const std::uint64_t finest = yv::planLevel(*source, source->bounds(), ~0ull, bytesPerVoxel, 1 << 14).gpuBytes;
            budget = finest + finest / 2;
            levelAtHalf = yv::planLevel(*source, source->bounds(), budget / 2, bytesPerVoxel, 1 << 14).level;
            r.gpuBudgetBytes = budget;
            if (beside) r.beside = r.input;
        });
        Page page(view.port.get_future().get());
        page.sendCamera(30, 20, 2.5, 1);
        const Json stats = page.frameOf(1).first;
        INFO(stats.dump());
        CHECK(!view.failure);
        return stats["level"].get<int>();
    };
    CHECK(atBudget(false) == 0);
    CHECK(levelAtHalf >= 1);
    CHECK(atBudget(true) == levelAtHalf);
}
