#include "garment/cross_section.h"

#include "core/error.h"
#include "core/world_units.h"

#include <png.h>
#include <sys/stat.h>

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

namespace {

/// libpng's state for one read. libpng reports errors by longjmp, which must
/// not cross a frame holding C++ objects with destructors: every function
/// that calls libpng and may jump (the png* steps below) has trivially
/// destructible locals only, and returns false on error; the caller, which
/// owns the vectors, never sees a jump.
struct PngRead {
    png_structp png = nullptr;
    png_infop info = nullptr;
    char message[200] = "";
};

void onPngError(png_structp png, png_const_charp message) {
    auto* read = static_cast<PngRead*>(png_get_error_ptr(png));
    std::snprintf(read->message, sizeof read->message, "%s", message);
    png_longjmp(png, 1);
}

void onPngWarning(png_structp, png_const_charp) {} // warnings (a bad ancillary chunk) are not errors

/// Header and text chunks; then the transforms to 8-bit grey + alpha.
bool pngReadInfo(PngRead& r, FILE* file) {
    if (setjmp(png_jmpbuf(r.png))) return false;
    png_init_io(r.png, file);
    png_set_sig_bytes(r.png, 8);
    png_read_info(r.png, r.info);
    return true;
}

bool pngSetTransforms(PngRead& r, bool& hasAlpha) {
    if (setjmp(png_jmpbuf(r.png))) return false;
    png_set_strip_16(r.png);
    png_set_packing(r.png);
    const int colorType = png_get_color_type(r.png, r.info);
    if (colorType == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(r.png);
    if (png_get_valid(r.png, r.info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(r.png);
    if (colorType == PNG_COLOR_TYPE_GRAY && png_get_bit_depth(r.png, r.info) < 8) png_set_expand_gray_1_2_4_to_8(r.png);
    hasAlpha = (colorType & PNG_COLOR_MASK_ALPHA) || png_get_valid(r.png, r.info, PNG_INFO_tRNS);
    if (colorType & PNG_COLOR_MASK_COLOR || colorType == PNG_COLOR_TYPE_PALETTE) png_set_rgb_to_gray(r.png, 1, -1, -1);
    if (!hasAlpha) png_set_add_alpha(r.png, 0xff, PNG_FILLER_AFTER);
    png_read_update_info(r.png, r.info);
    return true;
}

bool pngReadRows(PngRead& r, png_bytepp rows) {
    if (setjmp(png_jmpbuf(r.png))) return false;
    png_read_image(r.png, rows);
    png_read_end(r.png, nullptr);
    return true;
}

/// Destroys libpng's state on every way out of the loader.
struct PngReadGuard {
    PngRead& r;
    ~PngReadGuard() { png_destroy_read_struct(&r.png, &r.info, nullptr); }
};

} // namespace

double srgbToLinear(std::uint8_t value) {
    const double c = value / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

namespace {

/// The PNG's colour as sRGB-encoded RGBA, through libpng's simplified API
/// (no longjmp; it converts grey, palettes and other gammas to 8-bit sRGB),
/// rows bottom to top as the density's.
std::vector<std::uint8_t> readPngRgba(const std::string& path, int size) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    std::vector<std::uint8_t> rgba;
    if (png_image_begin_read_from_file(&image, path.c_str())) {
        image.format = PNG_FORMAT_RGBA;
        if (int(image.width) == size && int(image.height) == size) {
            rgba.resize(PNG_IMAGE_SIZE(image));
            // A negative row stride stores the last row first.
            if (png_image_finish_read(&image, nullptr, rgba.data(), -int(PNG_IMAGE_ROW_STRIDE(image)), nullptr))
                return rgba;
        }
    }
    const std::string message = image.message[0] ? image.message : "size changed while reading";
    png_image_free(&image);
    throw Error(path + ": cannot read the PNG's colour for --albedo: " + message);
}

/// Fills xs.albedo from the PNG's RGB, or throws when it has no colour.
void loadAlbedo(const std::string& path, CrossSection& xs) {
    const std::vector<std::uint8_t> rgba = readPngRgba(path, xs.size);
    bool coloured = false;
    double linear[256];
    for (int i = 0; i < 256; ++i) linear[i] = srgbToLinear(std::uint8_t(i));
    xs.albedo.resize(xs.density.size());
    for (std::size_t i = 0; i < xs.density.size(); ++i) {
        const std::uint8_t* p = &rgba[4 * i];
        if (xs.density[i] != 0 && (p[0] != p[1] || p[1] != p[2])) coloured = true;
        const double weight = xs.density[i] / 255.0;
        xs.albedo[i] = glm::vec3(float(weight * linear[p[0]]), float(weight * linear[p[1]]), float(weight * linear[p[2]]));
    }
    if (!coloured)
        throw Error(path + ": --albedo needs a colour cross-section, but every pixel with fibre is grey (R = G = B)");
}

} // namespace

CrossSection loadCrossSectionPng(const std::string& path, bool withAlbedo) {
    std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!file) throw Error(path + ": cannot open cross-section PNG: " + std::strerror(errno));
    png_byte signature[8];
    if (std::fread(signature, 1, 8, file.get()) != 8 || png_sig_cmp(signature, 0, 8) != 0)
        throw Error(path + ": byte 0: not a PNG file (expected the PNG signature)");

    PngRead r;
    r.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &r, onPngError, onPngWarning);
    r.info = r.png ? png_create_info_struct(r.png) : nullptr;
    const PngReadGuard guard{r};
    if (!r.info) throw Error(path + ": out of memory reading PNG");
    const auto corrupt = [&] { return Error(path + ": corrupt or truncated PNG: " + r.message); };
    if (!pngReadInfo(r, file.get())) throw corrupt();

    const png_uint_32 width = png_get_image_width(r.png, r.info), height = png_get_image_height(r.png, r.info);
    if (width != height || width < 2 || width > 8192)
        throw Error(path + ": cross-section must be square, 2 to 8192 pixels (is " + std::to_string(width) + "x" +
                    std::to_string(height) + ")");
    // Deflate packs at most 1032 bytes into one: a file too short for the
    // image its header claims is refused before the image is allocated (a
    // 60-byte file must not cost 128 MiB).
    const std::uint64_t rawBytes = std::uint64_t(height) * (png_get_rowbytes(r.png, r.info) + 1);
    struct stat st {};
    if (::fstat(::fileno(file.get()), &st) == 0 && S_ISREG(st.st_mode) &&
        std::uint64_t(st.st_size) * 1032 + 65536 < rawBytes)
        throw Error(path + ": corrupt or truncated PNG: " + std::to_string(st.st_size) + " bytes cannot hold the " +
                    std::to_string(width) + "x" + std::to_string(height) + " image its header describes");
    CrossSection xs;
    xs.name = path;
    png_textp text = nullptr;
    int textCount = 0;
    png_get_text(r.png, r.info, &text, &textCount);
    for (int i = 0; i < textCount; ++i) {
        if (std::strcmp(text[i].key, "yarn-radius") != 0) continue;
        char* end = nullptr;
        const double radius = std::strtod(text[i].text, &end);
        const std::string problem = end == text[i].text || *end != '\0' ? "is not a number" : lengthProblem(radius);
        if (!problem.empty())
            throw Error(path + ": text chunk yarn-radius '" + text[i].text + "': " + problem +
                        " (--yarn-radius overrides it)");
        xs.radius = radius;
    }

    bool hasAlpha = false;
    if (!pngSetTransforms(r, hasAlpha)) throw corrupt();
    std::vector<png_byte> rows(static_cast<std::size_t>(width) * height * 2);
    std::vector<png_bytep> rowPointers(height);
    // PNG rows run top to bottom; slice-local v runs bottom to top.
    for (png_uint_32 y = 0; y < height; ++y) rowPointers[y] = rows.data() + static_cast<std::size_t>(height - 1 - y) * width * 2;
    if (!pngReadRows(r, rowPointers.data())) throw corrupt();

    xs.size = static_cast<int>(width);
    xs.density.resize(static_cast<std::size_t>(width) * height);
    for (std::size_t i = 0; i < xs.density.size(); ++i) xs.density[i] = hasAlpha ? rows[2 * i + 1] : rows[2 * i];
    if (std::all_of(xs.density.begin(), xs.density.end(), [](std::uint8_t d) { return d == 0; }))
        throw Error(path + ": every pixel of the cross-section has density 0 (" +
                    (hasAlpha ? std::string("fully transparent") : std::string("black")) +
                    "): the volume would be empty (density is the alpha channel, or the grey level without one)");
    if (withAlbedo) loadAlbedo(path, xs);
    return xs;
}

CrossSection makeCrossSection(const std::string& spec, bool withAlbedo) {
    const bool png = spec.size() > 4 && spec.compare(spec.size() - 4, 4, ".png") == 0;
    if (withAlbedo && !png)
        throw Error("--albedo: the colour comes from a --cross-section PNG, and '" + spec + "' has none");
    if (spec == "disk") return makeDiskCrossSection();
    if (spec == "fibers") return makeFiberCrossSection();
    if (png) return loadCrossSectionPng(spec, withAlbedo);
    throw Error("--cross-section: expected fibers, disk or a .png file, got '" + spec + "'");
}

double textureSupport(const CrossSection& xs) {
    if (xs.analyticDisk) return 1.0;
    double farthest = -1.0;
    for (int y = 0; y < xs.size; ++y)
        for (int x = 0; x < xs.size; ++x)
            if (xs.density[static_cast<std::size_t>(y) * xs.size + x] != 0) {
                const double u = (x + 0.5) / xs.size * 2.0 - 1.0, v = (y + 0.5) / xs.size * 2.0 - 1.0;
                farthest = std::max(farthest, std::sqrt(u * u + v * v));
            }
    if (farthest < 0.0) return 0.0; // no fibre anywhere: every lookup reads 0
    return farthest + 2.0 * std::sqrt(2.0) / xs.size + 1e-3;
}

} // namespace yv
