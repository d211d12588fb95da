// A rendered picture as the JPEG bytes a frame message carries, through
// TurboJPEG (libjpeg-turbo's SIMD encoder: a few milliseconds a 720p frame
// on one core). One encoder a thread: a handle is not shared.
#pragma once

#include "inspect/png_image.h"

#include <cstdint>
#include <vector>

namespace yv {

class JpegEncoder {
  public:
    /// Throws yv::Error when TurboJPEG cannot make a compressor.
    JpegEncoder();
    ~JpegEncoder();
    JpegEncoder(const JpegEncoder&) = delete;
    JpegEncoder& operator=(const JpegEncoder&) = delete;

    /// `image` as a baseline JPEG of `quality` (1 to 100), 4:2:0 chroma.
    /// Throws yv::Error with TurboJPEG's message.
    std::vector<std::uint8_t> encode(const RgbImage& image, int quality = 85);

  private:
    void* handle_;
};

/// Decodes a JPEG into RGB (tests and the benchmark compare pictures with
/// it). Throws yv::Error when the bytes are not a JPEG TurboJPEG reads.
RgbImage decodeJpeg(const std::vector<std::uint8_t>& bytes);

} // namespace yv
