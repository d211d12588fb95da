#include "garment/cross_section.h"

#include "core/error.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <random>

namespace yv {

double CrossSection::meanDensity() const {
    double sum = 0.0;
    for (std::uint8_t d : density) sum += d;
    return density.empty() ? 0.0 : sum / (255.0 * density.size());
}

CrossSection makeDiskCrossSection(int size) {
    CrossSection xs;
    xs.size = size;
    xs.name = "disk";
    xs.analyticDisk = true;
    xs.density.resize(static_cast<std::size_t>(size) * size);
    // 8x8 samples per texel give each edge texel its covered fraction, so the
    // texture integrates to pi within 8-bit quantisation.
    constexpr int kSub = 8;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            int inside = 0;
            for (int sy = 0; sy < kSub; ++sy)
                for (int sx = 0; sx < kSub; ++sx) {
                    const double u = ((x + (sx + 0.5) / kSub) / size) * 2.0 - 1.0;
                    const double v = ((y + (sy + 0.5) / kSub) / size) * 2.0 - 1.0;
                    inside += u * u + v * v < 1.0;
                }
            xs.density[static_cast<std::size_t>(y) * size + x] =
                static_cast<std::uint8_t>(std::lround(255.0 * inside / (kSub * kSub)));
        }
    return xs;
}

CrossSection makeFiberCrossSection(int size, std::uint64_t seed) {
    CrossSection xs;
    xs.size = size;
    xs.name = "fibers";
    std::vector<float> acc(static_cast<std::size_t>(size) * size, 0.0f);
    std::mt19937_64 rng(seed);
    auto uniform = [&rng] { return (rng() >> 11) * (1.0 / 9007199254740992.0); };

    // Three plies around the yarn centre; fibres scattered in each ply, more
    // of them near the ply centre (the migration profile of spun yarn).
    constexpr int kPlies = 3;
    constexpr double kPlyRadius = 0.46, kPlyOffset = 0.5, kFiberRadius = 0.045;
    constexpr int kFibersPerPly = 90;
    for (int p = 0; p < kPlies; ++p) {
        const double a = 2.0 * M_PI * p / kPlies;
        const double cx = kPlyOffset * std::cos(a), cy = kPlyOffset * std::sin(a);
        for (int f = 0; f < kFibersPerPly; ++f) {
            const double r = kPlyRadius * std::sqrt(uniform()) * (0.6 + 0.4 * uniform());
            const double b = 2.0 * M_PI * uniform();
            const double fx = cx + r * std::cos(b), fy = cy + r * std::sin(b);
            const int x0 = std::max(0, int(std::floor((fx - kFiberRadius + 1) * 0.5 * size)));
            const int x1 = std::min(size - 1, int(std::ceil((fx + kFiberRadius + 1) * 0.5 * size)));
            const int y0 = std::max(0, int(std::floor((fy - kFiberRadius + 1) * 0.5 * size)));
            const int y1 = std::min(size - 1, int(std::ceil((fy + kFiberRadius + 1) * 0.5 * size)));
            for (int y = y0; y <= y1; ++y)
                for (int x = x0; x <= x1; ++x) {
                    const double u = (x + 0.5) / size * 2 - 1, v = (y + 0.5) / size * 2 - 1;
                    const double d2 = (u - fx) * (u - fx) + (v - fy) * (v - fy);
                    if (d2 < kFiberRadius * kFiberRadius) acc[static_cast<std::size_t>(y) * size + x] += 1.0f;
                }
        }
    }
    xs.density.resize(acc.size());
    for (std::size_t i = 0; i < acc.size(); ++i) {
        const double u = (i % size + 0.5) / size * 2 - 1, v = (i / size + 0.5) / size * 2 - 1;
        const bool inYarn = u * u + v * v < 1.0; // fibres never leave the yarn's radius
        xs.density[i] = inYarn ? static_cast<std::uint8_t>(std::min(1.0f, acc[i]) * 255.0f) : 0;
    }
    return xs;
}

CrossSection loadCrossSectionPng(const std::string& path) {
    std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!file) throw Error(path + ": cannot open cross-section PNG: " + std::strerror(errno));
    png_byte signature[8];
    if (std::fread(signature, 1, 8, file.get()) != 8 || png_sig_cmp(signature, 0, 8) != 0)
        throw Error(path + ": byte 0: not a PNG file (expected the PNG signature)");

    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!info) throw Error(path + ": out of memory reading PNG");
    CrossSection xs;
    xs.name = path;
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, nullptr);
        throw Error(path + ": corrupt or truncated PNG");
    }
    png_init_io(png, file.get());
    png_set_sig_bytes(png, 8);
    png_read_info(png, info);
    const png_uint_32 width = png_get_image_width(png, info), height = png_get_image_height(png, info);
    if (width != height || width < 2 || width > 8192) {
        png_destroy_read_struct(&png, &info, nullptr);
        throw Error(path + ": cross-section must be square, 2 to 8192 pixels (is " + std::to_string(width) + "x" +
                    std::to_string(height) + ")");
    }
    png_textp text = nullptr;
    int textCount = 0;
    png_get_text(png, info, &text, &textCount);
    for (int i = 0; i < textCount; ++i)
        if (std::strcmp(text[i].key, "yarn-radius") == 0) xs.radius = std::atof(text[i].text);

    // Normalise every PNG flavour to 8-bit grey + alpha.
    png_set_strip_16(png);
    png_set_packing(png);
    const int colorType = png_get_color_type(png, info);
    if (colorType == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    if (png_get_valid(png, info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png);
    if (colorType == PNG_COLOR_TYPE_GRAY && png_get_bit_depth(png, info) < 8) png_set_expand_gray_1_2_4_to_8(png);
    const bool hasAlpha = (colorType & PNG_COLOR_MASK_ALPHA) || png_get_valid(png, info, PNG_INFO_tRNS);
    if (colorType & PNG_COLOR_MASK_COLOR || colorType == PNG_COLOR_TYPE_PALETTE) png_set_rgb_to_gray(png, 1, -1, -1);
    if (!hasAlpha) png_set_add_alpha(png, 0xff, PNG_FILLER_AFTER);
    png_read_update_info(png, info);

    std::vector<png_byte> rows(static_cast<std::size_t>(width) * height * 2);
    std::vector<png_bytep> rowPointers(height);
    // PNG rows run top to bottom; slice-local v runs bottom to top.
    for (png_uint_32 y = 0; y < height; ++y) rowPointers[y] = rows.data() + static_cast<std::size_t>(height - 1 - y) * width * 2;
    png_read_image(png, rowPointers.data());
    png_destroy_read_struct(&png, &info, nullptr);

    xs.size = static_cast<int>(width);
    xs.density.resize(static_cast<std::size_t>(width) * height);
    for (std::size_t i = 0; i < xs.density.size(); ++i) xs.density[i] = hasAlpha ? rows[2 * i + 1] : rows[2 * i];
    return xs;
}

CrossSection makeCrossSection(const std::string& spec) {
    if (spec == "disk") return makeDiskCrossSection();
    if (spec == "fibers") return makeFiberCrossSection();
    if (spec.size() > 4 && spec.compare(spec.size() - 4, 4, ".png") == 0) return loadCrossSectionPng(spec);
    throw Error("--cross-section: expected fibers, disk or a .png file, got '" + spec + "'");
}

} // namespace yv
