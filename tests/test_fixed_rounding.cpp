// The fixed-point rounding of samples (core/sampling.h): roundHalfAway is
// std::lround, value for value, so the CPU backend's bytes do not move.
#include "core/sampling.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

TEST_CASE("roundHalfAway gives std::lround's result at halves, their neighbours and random values", "[cpu][sampling]") {
    std::vector<double> values = {0.0, -0.0, 0.5, -0.5, 1.5, -1.5, 2.5, -2.5, 0.49999999999999994, -0.49999999999999994,
                                  4503599627370495.5, -4503599627370495.5, 4503599627370496.0, 1e15 + 0.5,
                                  double(yv::kFixedScale), double(yv::kFixedScale) + 0.5, 65535.0 * 0.5 + 0.5};
    // Every half up to 2^20 and the doubles on either side of it.
    for (int i = -(1 << 20); i <= (1 << 20); i += 97) {
        const double half = i + 0.5;
        values.insert(values.end(), {half, std::nextafter(half, 0.0), std::nextafter(half, 1e300),
                                     std::nextafter(half, -1e300), double(i)});
    }
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> fraction(0.0, 1.0), wide(-1e12, 1e12);
    for (int i = 0; i < 200000; ++i) {
        values.push_back(fraction(random) * double(yv::kFixedScale)); // what toFixed rounds
        values.push_back(wide(random));
    }
    std::size_t wrong = 0;
    for (const double v : values) {
        if (yv::roundHalfAway(v) != std::llround(v)) {
            ++wrong;
            UNSCOPED_INFO("value " << v << ": " << yv::roundHalfAway(v) << " against " << std::llround(v));
        }
    }
    CHECK(wrong == 0);
    // The samples' fixed point and the axis code through it, against lround's.
    for (int i = 0; i <= 4096; ++i) {
        const double v = i / 4096.0;
        CHECK(yv::toFixed(v) == std::uint32_t(std::lround(v * yv::kFixedScale)));
        CHECK(yv::toFixedSigned(-v) == std::int32_t(std::lround(-v * yv::kFixedScale)));
    }
}
