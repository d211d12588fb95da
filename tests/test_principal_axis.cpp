// Two tensors' principal axes at once (principalAxisPair) against one at a
// time (principalAxis): the same bits, whichever lane converges first.
#include "core/bricks.h"
#include "core/principal_axis_pair.h"

#include <catch2/catch.hpp>

#include <array>
#include <cstring>
#include <random>
#include <vector>

using namespace yv;

TEST_CASE("principalAxisPair gives principalAxis's bits in both lanes", "[cpu][resolve]") {
    // Accumulator-like tensors (whole numbers, a positive diagonal), and the
    // awkward ones: zero, diagonal (no rotation), equal eigenvalues, one
    // off-diagonal entry only, huge and tiny entries.
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
    std::size_t mismatches = 0, pairs = 0;
    for (std::size_t i = 0; i < tensors.size(); ++i) {
        const std::size_t j = (i * 7919 + 1) % tensors.size(); // every tensor beside several others
        glm::dvec3 a, b;
        principalAxisPair(tensors[i].data(), tensors[j].data(), a, b);
        const glm::dvec3 wantA = principalAxis(tensors[i].data()), wantB = principalAxis(tensors[j].data());
        mismatches += std::memcmp(&a, &wantA, sizeof a) != 0 || std::memcmp(&b, &wantB, sizeof b) != 0;
        ++pairs;
    }
    INFO(pairs << " pairs");
    CHECK(mismatches == 0);
}
