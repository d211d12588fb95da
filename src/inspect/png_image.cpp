#include "inspect/png_image.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/interrupt.h"

#include <png.h>

#include <cstring>
#include <span>

namespace yv {

void writePng(const std::string& path, const RgbImage& image) {
    png_image desc;
    std::memset(&desc, 0, sizeof desc);
    desc.version = PNG_IMAGE_VERSION;
    desc.width = png_uint_32(image.width);
    desc.height = png_uint_32(image.height);
    desc.format = PNG_FORMAT_RGB;
    png_alloc_size_t size = 0;
    if (!png_image_write_to_memory(&desc, nullptr, &size, 0, image.pixels.data(), 0, nullptr))
        throw Error("cannot write " + path + ": " + desc.message);
    std::vector<std::uint8_t> bytes(size);
    if (!png_image_write_to_memory(&desc, bytes.data(), &size, 0, image.pixels.data(), 0, nullptr))
        throw Error("cannot write " + path + ": " + desc.message);
    bytes.resize(size);
    signalAtTestPoint("png-write");
    throwIfInterrupted("before " + path + " was written: it was not written; run the command again");
    writeFileAtomically(path, std::span<const std::uint8_t>(bytes));
}

RgbImage readPng(const std::string& path) {
    png_image desc;
    std::memset(&desc, 0, sizeof desc);
    desc.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&desc, path.c_str())) throw Error(path + ": not a PNG libpng can read (" + desc.message + ")");
    desc.format = PNG_FORMAT_RGB;
    RgbImage image(int(desc.width), int(desc.height));
    if (!png_image_finish_read(&desc, nullptr, image.pixels.data(), 0, nullptr)) {
        png_image_free(&desc);
        throw Error(path + ": cannot decode (" + desc.message + ")");
    }
    return image;
}

} // namespace yv
