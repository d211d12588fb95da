// Many tensors' principal axes at once (principalAxes, in SSE2's two lanes
// and AVX's four) against one at a time (principalAxis): the same bits,
// whichever lane converges first, for any count.
#include "core/bricks.h"
#include "core/cpu_features.h"
#include "core/principal_axes.h"

#include <catch2/catch.hpp>

#include <array>
#include <cstring>
#include <random>
#include <vector>

using namespace yv;

namespace {

/// Accumulator-like tensors (whole numbers, a positive diagonal), and the
/// awkward ones: zero, diagonal (no rotation), equal eigenvalues, one
/// off-diagonal entry only, huge and tiny entries.
std::vector<std::array<double, 6>> testTensors() {
    std::mt19937_64 rng(31);
    std::uniform_int_distribution<int> diagonal(0, 1 << 24), offDiagonal(-(1 << 23), 1 << 23);
    std::vector<std::array<double, 6>> tensors = {
        {0, 0, 0, 0, 0, 0},       {5, 5, 5, 0, 0, 0}, {1, 2, 3, 0, 0, 0},         {4, 4, 1, 3, 0, 0},
        {7, 7, 7, 7, 7, 7},       {1, 0, 0, 0, 0, 0}, {0, 0, 0, 0, 0, 1},         {1e-300, 1, 1, 0, 1e-300, 0},
        {16777216, 1, 1, 1, 1, 1}, {2, 2, 2, -1, -1, -1}};
    for (int i = 0; i < 20000; ++i) {
        std::array<double, 6> t;
        for (int k = 0; k < 3; ++k) t[k] = diagonal(rng);
        for (int k = 3; k < 6; ++k) t[k] = i % 7 == 0 && k != 3 ? 0.0 : double(offDiagonal(rng));
        tensors.push_back(t);
    }
    return tensors;
}

/// Tensors of `all` mixed so that each lands in a group beside several others.
std::vector<std::array<double, 6>> shuffled(const std::vector<std::array<double, 6>>& all) {
    std::vector<std::array<double, 6>> out(all.size());
    for (std::size_t i = 0; i < all.size(); ++i) out[i] = all[(i * 7919 + 1) % all.size()];
    return out;
}

std::size_t mismatches(const std::vector<std::array<double, 6>>& tensors, AxisLanes lanes) {
    std::vector<glm::dvec3> axes(tensors.size());
    principalAxes(reinterpret_cast<const double(*)[6]>(tensors.data()), axes.data(), int(tensors.size()), lanes);
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < tensors.size(); ++i) {
        const glm::dvec3 want = principalAxis(tensors[i].data());
        wrong += std::memcmp(&axes[i], &want, sizeof want) != 0;
    }
    return wrong;
}

} // namespace

TEST_CASE("principalAxes gives principalAxis's bits in every lane", "[cpu][resolve]") {
    const auto tensors = testTensors();
    for (const auto& order : {tensors, shuffled(tensors)}) {
        CHECK(mismatches(order, AxisLanes::Sse2) == 0);
        CHECK(mismatches(order, AxisLanes::Auto) == 0);
        if (cpuHasAvx())
            CHECK(mismatches(order, AxisLanes::Avx) == 0);
        else
            WARN("this CPU has no AVX: the four-lane path is not checked here");
    }
}

TEST_CASE("principalAxes takes any count, the groups' remainders one by one", "[cpu][resolve]") {
    const auto tensors = testTensors();
    for (int count = 0; count <= 9; ++count) {
        const std::vector<std::array<double, 6>> some(tensors.begin() + 3, tensors.begin() + 3 + count);
        for (AxisLanes lanes : {AxisLanes::Sse2, AxisLanes::Auto}) {
            INFO("count " << count);
            CHECK(mismatches(some, lanes) == 0);
        }
    }
}
