#include "view/jpeg_frame.h"

#include "core/error.h"

#include <turbojpeg.h>

#include <memory>

namespace yv {

JpegEncoder::JpegEncoder() : handle_(tjInitCompress()) {
    if (!handle_) throw Error(std::string("TurboJPEG: cannot make a compressor: ") + tjGetErrorStr2(nullptr));
}

JpegEncoder::~JpegEncoder() { tjDestroy(handle_); }

std::vector<std::uint8_t> JpegEncoder::encode(const RgbImage& image, int quality) {
    if (image.width <= 0 || image.height <= 0) throw Error("TurboJPEG: an empty picture");
    unsigned char* out = nullptr;
    unsigned long size = 0;
    const int rc = tjCompress2(handle_, image.pixels.data(), image.width, 0, image.height, TJPF_RGB, &out, &size,
                               TJSAMP_420, quality, TJFLAG_FASTDCT);
    const std::unique_ptr<unsigned char, decltype(&tjFree)> owned(out, &tjFree);
    if (rc != 0) throw Error(std::string("TurboJPEG: ") + tjGetErrorStr2(handle_));
    return std::vector<std::uint8_t>(out, out + size);
}

RgbImage decodeJpeg(const std::vector<std::uint8_t>& bytes) {
    const std::unique_ptr<void, decltype(&tjDestroy)> handle(tjInitDecompress(), &tjDestroy);
    if (!handle) throw Error("TurboJPEG: cannot make a decompressor");
    int width = 0, height = 0, subsampling = 0, colourspace = 0;
    auto* data = const_cast<unsigned char*>(bytes.data());
    if (tjDecompressHeader3(handle.get(), data, bytes.size(), &width, &height, &subsampling, &colourspace) != 0)
        throw Error(std::string("not a JPEG: ") + tjGetErrorStr2(handle.get()));
    if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
        throw Error("a JPEG of " + std::to_string(width) + "x" + std::to_string(height) + " pixels");
    RgbImage image(width, height);
    if (tjDecompress2(handle.get(), data, bytes.size(), image.pixels.data(), width, 0, height, TJPF_RGB, 0) != 0)
        throw Error(std::string("a damaged JPEG: ") + tjGetErrorStr2(handle.get()));
    return image;
}

} // namespace yv
