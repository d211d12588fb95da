#include "inspect/slice_instances.h"

#include "core/error.h"
#include "core/trace.h"
#include "garment/slice_measures.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include <algorithm>
#include <bit>
#include <limits>

namespace yv {

SliceInstances sliceInstances(const SlicePlan& plan, const VoxelGrid& grid) {
    // The order is drawn through 32-bit instance indices.
    if (plan.sliceCount > std::numeric_limits<std::uint32_t>::max())
        throw Error("--render slices: " + std::to_string(plan.sliceCount) + " slices are more than 2^32 (draw a region)");
    SliceInstances out;
    out.records.resize(std::size_t(plan.sliceCount) * 2u);
    const double h = grid.voxelSize;
    const float radius = float(plan.options.radius / h);
    const TraceSpan span("place the slices for drawing");
    tbb::parallel_for(std::size_t(0), plan.segments.size(), [&](std::size_t s) {
        const SegmentRecord& seg = plan.segments[s];
        // Centre, tangent and thickness only (the frame is the shader's),
        // several slices at a time.
        constexpr std::uint32_t kChunk = 64;
        SliceAxis chunk[kChunk];
        for (std::uint32_t first = 0; first < seg.sliceCount; first += kChunk) {
            const std::uint32_t count = std::min(kChunk, seg.sliceCount - first);
            sliceAxes(seg, first, count, chunk);
            for (std::uint32_t j = 0; j < count; ++j) {
                const std::uint32_t k = first + j;
                const glm::dvec3 c = (chunk[j].centre - grid.origin) / h;
                const std::size_t i = std::size_t(seg.firstSlice + k) * 2u;
                out.records[i] = glm::vec4(glm::vec3(c), float(chunk[j].thickness / h));
                out.records[i + 1] = glm::vec4(glm::vec3(chunk[j].tangent), float(k % kRunPlaces));
            }
        }
    });
    out.radius = radius;
    out.twist = float(plan.options.twist * h);
    return out;
}

void keepSlicesWithin(SliceInstances& slices, glm::dvec3 lo, glm::dvec3 hi) {
    std::size_t kept = 0;
    std::uint64_t previous = std::numeric_limits<std::uint64_t>::max(); // the last slice kept, before renumbering
    std::uint32_t previousPlace = 0;
    for (std::uint64_t i = 0; i < slices.count(); ++i) {
        const glm::dvec3 c(slices.center(i));
        if (glm::any(glm::lessThan(c, lo)) || glm::any(glm::greaterThanEqual(c, hi))) continue;
        // A slice continues the run of the one kept before it only where it
        // followed that one in the same run before the cut.
        const std::uint32_t place = slices.place(i);
        const bool continues = kept > 0 && previous + 1 == i && place == previousPlace + 1;
        const std::uint32_t newPlace = continues ? slices.place(kept - 1) + 1 : 0;
        previous = i;
        previousPlace = place;
        slices.records[2 * kept] = slices.records[2 * i];
        slices.records[2 * kept + 1] = glm::vec4(glm::vec3(slices.records[2 * i + 1]), float(newPlace % kRunPlaces));
        ++kept;
    }
    slices.records.resize(2 * kept);
}

void sortBackToFront(const SliceInstances& slices, glm::dvec3 eye, std::vector<std::uint32_t>& order) {
    const std::size_t n = std::size_t(slices.count());
    // One 64-bit key a slice: the squared distance's bits, inverted so the
    // farthest sorts first (a non-negative float's bits order as the float),
    // then the index. Integers sort faster than pairs with a comparator.
    std::vector<std::uint64_t> keys(n);
    const glm::vec3 e(eye);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            const glm::vec3 d = slices.center(i) - e;
            const std::uint32_t bits = std::bit_cast<std::uint32_t>(glm::dot(d, d));
            keys[i] = (std::uint64_t(~bits) << 32) | std::uint64_t(i);
        }
    });
    tbb::parallel_sort(keys.begin(), keys.end());
    order.resize(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) order[i] = std::uint32_t(keys[i]);
    });
}

} // namespace yv
