// Writes the fuzz targets' seed inputs into tests/fuzz-corpus/<target>/ (the
// directory given), from the encoders of the real code: a few small valid
// files per format and a few broken ones (truncated, a flipped byte).
//   build-fuzz/make_corpus tests/fuzz-corpus
#include "bcc.h"
#include "store/manifest.h"
#include "store/region_file.h"

#include <png.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;

namespace {

void put(const fs::path& dir, const std::string& name, const Bytes& bytes) {
    fs::create_directories(dir);
    std::ofstream(dir / name, std::ios::binary | std::ios::trunc)
        .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

/// A valid file, its first half, and the file with one byte flipped.
void putVariants(const fs::path& dir, const std::string& name, const Bytes& valid, std::size_t flipAt) {
    put(dir, name, valid);
    put(dir, name + "-truncated", Bytes(valid.begin(), valid.begin() + valid.size() / 2));
    Bytes flipped = valid;
    flipped[flipAt % flipped.size()] ^= 0x5a;
    put(dir, name + "-flipped", flipped);
}

yv::Garment twoYarns(bool closed) {
    yv::Garment g;
    g.yarnRadius = 0.25;
    for (int y = 0; y < 2; ++y) {
        yv::Yarn yarn;
        yarn.closed = closed;
        for (int i = 0; i < 5; ++i) yarn.points.push_back({double(i), double(y), 0.1 * i});
        g.yarns.push_back(yarn);
    }
    return g;
}

Bytes png(int size, int colorType, int bitDepth, const char* radius) {
    Bytes out;
    png_structp p = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(p);
    if (setjmp(png_jmpbuf(p))) std::abort();
    png_set_write_fn(p, &out, [](png_structp s, png_bytep data, png_size_t n) {
        auto* o = static_cast<Bytes*>(png_get_io_ptr(s));
        o->insert(o->end(), data, data + n);
    }, nullptr);
    png_set_IHDR(p, info, size, size, bitDepth, colorType, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (radius) {
        png_text text{};
        text.compression = PNG_TEXT_COMPRESSION_NONE;
        text.key = const_cast<char*>("yarn-radius");
        text.text = const_cast<char*>(radius);
        png_set_text(p, info, &text, 1);
    }
    png_write_info(p, info);
    const int channels = colorType == PNG_COLOR_TYPE_GRAY_ALPHA ? 2 : colorType == PNG_COLOR_TYPE_RGBA ? 4 : 1;
    Bytes row(std::size_t(size) * channels * (bitDepth == 16 ? 2 : 1));
    for (int y = 0; y < size; ++y) {
        for (std::size_t i = 0; i < row.size(); ++i) row[i] = std::uint8_t((i * 37 + y * 11) & 0xff);
        png_write_row(p, row.data());
    }
    png_write_end(p, info);
    png_destroy_write_struct(&p, &info);
    return out;
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: make_corpus DIR\n");
        return 2;
    }
    const fs::path root = argv[1];

    putVariants(root / "bcc", "open.bcc", yv::encodeBcc(twoYarns(false)), 70);
    putVariants(root / "bcc", "closed.bcc", yv::encodeBcc(twoYarns(true)), 3);

    putVariants(root / "png", "gray.png", png(8, PNG_COLOR_TYPE_GRAY, 8, "0.3"), 40);
    putVariants(root / "png", "gray-alpha-16.png", png(4, PNG_COLOR_TYPE_GRAY_ALPHA, 16, nullptr), 60);
    put(root / "png", "not-square.png", png(2, PNG_COLOR_TYPE_RGBA, 8, "abc"));

    yv::StoreManifest m;
    m.fingerprint = 0x0123456789abcdefull;
    m.samplingCode = 0x89abcdef01234567ull;
    m.grid.origin = {-1.5, 0.25, 3.0};
    m.grid.voxelSize = 0.0125;
    m.grid.dims = {32, 16, 24};
    const std::string plain = yv::formatManifest(m);
    putVariants(root / "manifest", "plain", Bytes(plain.begin(), plain.end()), 40);
    m.reduce = yv::Reduce::Max;
    m.run.input = "knit.bcc";
    m.run.backend = "gl";
    m.stageSeconds = {{"read", 0.25}, {"voxelize", 4.5}, {"voxelize.store_write", 0.75}};
    m.completeRegions = 17;
    const std::string full = yv::formatManifest(m);
    putVariants(root / "manifest", "metadata-complete", Bytes(full.begin(), full.end()), 100);

    m.reduce = yv::Reduce::Mean;
    for (int n : {0, 1, 3}) {
        std::vector<yv::VoxelBrick> bricks(n);
        for (int i = 0; i < n; ++i) {
            bricks[i].key = yv::brickKey({i, 1, 2});
            bricks[i].activeMask[0] = 0x8000000000000001ull;
            bricks[i].density[0] = 0.5f;
            bricks[i].density[63] = 1.0f;
            bricks[i].orientation[0] = {0, 0, 1};
        }
        const yv::EncodedRegion r = yv::encodeRegion(m, 7, {0, 0, 0}, {32, 16, 24}, bricks, "seed");
        Bytes file(r.header.begin(), r.header.end());
        file.insert(file.end(), r.table.begin(), r.table.end());
        for (const Bytes& c : r.chunks) file.insert(file.end(), c.begin(), c.end());
        putVariants(root / "region", "bricks-" + std::to_string(n) + ".yvb", file, 170 + 13 * n);
    }
    return 0;
}
