// Floats to halves in bulk (core/half_floats.h) give OpenVDB's math::half
// bits for every float tried: a sweep over the whole 32-bit range, every
// float near the halves' limits and ties, whatever the count (the eight-wide
// lanes' tails) and the output's alignment.
#include "core/cpu_features.h"
#include "core/half_floats.h"

#include <openvdb/Types.h>

#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

using namespace yv;

namespace {

/// Floats from a stride over all 2^32 bit patterns, and the neighbourhoods of
/// the values where rounding to a half changes kind: zero, the smallest
/// subnormal half, the smallest normal half, 1 (ties at 2^-11), the largest
/// half and where rounding overflows to infinity.
std::vector<float> probes() {
    std::vector<float> v;
    for (std::uint64_t bits = 0; bits < (std::uint64_t(1) << 32); bits += 4099)
        v.push_back(std::bit_cast<float>(std::uint32_t(bits)));
    for (float centre : {0.0f, 5.9604645e-8f, 6.1035156e-5f, 1.0f, 65504.0f, 65520.0f}) {
        const std::uint32_t c = std::bit_cast<std::uint32_t>(centre);
        for (std::uint32_t d = 0; d < 8192; ++d) {
            v.push_back(std::bit_cast<float>(c + d));
            v.push_back(-std::bit_cast<float>(c + d));
            if (c >= d) v.push_back(std::bit_cast<float>(c - d));
        }
    }
    v.push_back(std::numeric_limits<float>::infinity());
    v.push_back(-std::numeric_limits<float>::infinity());
    v.push_back(std::numeric_limits<float>::max());
    v.push_back(std::numeric_limits<float>::denorm_min());
    return v;
}

} // namespace

TEST_CASE("floatsToHalves gives OpenVDB's half bits for every float tried", "[half_floats]") {
    INFO("F16C: " << cpuHasF16c());
    const std::vector<float> in = probes();
    std::vector<std::uint16_t> out(in.size());
    floatsToHalves(in.data(), out.data(), in.size());
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < in.size(); ++i) {
        const openvdb::math::half expected(in[i]);
        if (std::isnan(in[i])) {
            // Either keeps a NaN a NaN; the payload's bits are not part of the format's promise.
            if (!std::isnan(float(openvdb::math::half(openvdb::math::half::FromBits, out[i])))) ++wrong;
            continue;
        }
        if (out[i] != expected.bits()) {
            if (wrong < 5) UNSCOPED_INFO("float bits " << std::bit_cast<std::uint32_t>(in[i]) << ": " << out[i]
                                                      << " against " << expected.bits());
            ++wrong;
        }
    }
    CHECK(wrong == 0);
    CHECK(in.size() > 1000000);
}

TEST_CASE("roundThroughHalves gives a half grid's values in place or not", "[half_floats]") {
    const std::vector<float> in = probes();
    std::vector<float> out(in.size()), inPlace = in;
    roundThroughHalves(in.data(), out.data(), in.size());
    roundThroughHalves(inPlace.data(), inPlace.data(), inPlace.size());
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < in.size(); ++i) {
        if (std::isnan(in[i])) {
            wrong += !std::isnan(out[i]) || !std::isnan(inPlace[i]);
            continue;
        }
        const float expected = float(openvdb::math::half(in[i]));
        wrong += std::bit_cast<std::uint32_t>(out[i]) != std::bit_cast<std::uint32_t>(expected) ||
                 std::bit_cast<std::uint32_t>(inPlace[i]) != std::bit_cast<std::uint32_t>(expected);
    }
    CHECK(wrong == 0);
}

TEST_CASE("floatsToHalves writes exactly 2n bytes at any alignment for counts off the lanes' width", "[half_floats]") {
    std::vector<float> in(37);
    for (std::size_t i = 0; i < in.size(); ++i) in[i] = 0.1f * float(i) - 1.3f;
    for (std::size_t n = 0; n <= in.size(); ++n) {
        for (std::size_t offset = 0; offset < 3; ++offset) {
            std::vector<unsigned char> bytes(2 * in.size() + 8, 0xCD);
            floatsToHalves(in.data(), bytes.data() + offset, n);
            INFO("n " << n << ", offset " << offset);
            for (std::size_t i = 0; i < n; ++i) {
                std::uint16_t bits;
                std::memcpy(&bits, bytes.data() + offset + 2 * i, 2);
                CHECK(bits == openvdb::math::half(in[i]).bits());
            }
            for (std::size_t b = 0; b < bytes.size(); ++b)
                if (b < offset || b >= offset + 2 * n) CHECK(bytes[b] == 0xCD);
        }
    }
}
