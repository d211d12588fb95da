// 8-bit RGB images, top row first, as the renders produce them, and PNG
// files through libpng's simplified API. Writes go through a temporary name
// and a rename (core/atomic_file.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace yv {

struct RgbImage {
    int width = 0, height = 0;
    std::vector<std::uint8_t> pixels; ///< 3 bytes a pixel, rows top to bottom

    RgbImage() = default;
    RgbImage(int w, int h) : width(w), height(h), pixels(std::size_t(w) * std::size_t(h) * 3u, 0) {}
    std::uint8_t* at(int x, int y) { return &pixels[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3u]; }
    const std::uint8_t* at(int x, int y) const {
        return &pixels[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3u];
    }
};

/// Writes `image` as an RGB PNG at `path` atomically; throws yv::Error naming the path.
void writePng(const std::string& path, const RgbImage& image);

/// Reads any PNG as 8-bit RGB; throws yv::Error naming the path.
RgbImage readPng(const std::string& path);

} // namespace yv
