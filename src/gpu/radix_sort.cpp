#include "gpu/radix_sort.h"

#include "gpu/gl_bindings.h"

#include <algorithm>

namespace yv {
namespace {

constexpr int kPasses = 4;                 // 8 bits each

std::vector<std::string> tileDefines() {
    return {"RADIX_PER_THREAD " + std::to_string(RadixSort::kTile / 256) + "u"};
}

std::uint64_t tilesFor(std::uint64_t pairs) { return (pairs + RadixSort::kTile - 1) / RadixSort::kTile; }

} // namespace

RadixSort::RadixSort(std::uint64_t capacity, GLuint maxGroups)
    : maxGroups_(maxGroups), histogram_(GlProgram::compute("radix_histogram.comp", tileDefines())),
      scatter_(GlProgram::compute("radix_scatter.comp", tileDefines())),
      scan_(256 * tilesFor(std::max<std::uint64_t>(capacity, 1)), maxGroups) {
    reserve(capacity);
    kept_.reserve(16, nullptr);
    kept_.clear(16);
}

void RadixSort::reserve(std::uint64_t capacity) {
    const std::uint64_t pairs = std::max<std::uint64_t>(capacity, 1);
    const std::uint64_t counts = 256 * tilesFor(pairs);
    for (int i = 0; i < 2; ++i) {
        keys_[i].reserve(pairs * 4, nullptr);
        values_[i].reserve(pairs * 4, nullptr);
    }
    histogramCounts_.reserve(counts * 4, nullptr);
    scan_.reserve(counts);
}

GLuint RadixSort::groupsFor(std::uint64_t groups) const {
    return static_cast<GLuint>(std::clamp<std::uint64_t>(groups, 1, maxGroups_));
}

void RadixSort::sort(std::uint32_t count, const GlBuffer& out, bool withKeys) {
    const std::uint32_t tiles = std::uint32_t(std::max<std::uint64_t>(tilesFor(count), 1));
    for (int pass = 0; pass < kPasses; ++pass) {
        const bool first = pass == 0, last = pass == kPasses - 1;
        const GlBuffer &keysIn = keys_[pass % 2], &valuesIn = values_[pass % 2];
        const GlBuffer &keysOut = keys_[(pass + 1) % 2], &valuesOut = last ? out : values_[(pass + 1) % 2];
        const GLuint shift = GLuint(8 * pass);
        keysIn.bindStorage(kSortKeysInBinding);
        valuesIn.bindStorage(kSortValuesInBinding);
        histogramCounts_.bindStorage(kSortHistogramBinding);
        kept_.bindStorage(kSortKeptBinding);
        for (const GlProgram* program : {&histogram_, &scatter_}) {
            program->use();
            glUniform1ui(program->uniform("uCount"), count);
            glUniform1i(program->uniform("uFirstPass"), first ? 1 : 0);
            glUniform1ui(program->uniform("uShift"), shift);
            glUniform1ui(program->uniform("uTiles"), tiles);
        }
        histogram_.use();
        glDispatchCompute(groupsFor(tiles), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        // The histograms' places, and the first pass's kept pairs to `kept`.
        scan_.run(histogramCounts_, GLuint(256ull * tiles), first ? &kept_ : nullptr);
        keysIn.bindStorage(kSortKeysInBinding);
        valuesIn.bindStorage(kSortValuesInBinding);
        keysOut.bindStorage(kSortKeysOutBinding);
        valuesOut.bindStorage(kSortValuesOutBinding);
        histogramCounts_.bindStorage(kSortHistogramBinding);
        kept_.bindStorage(kSortKeptBinding);
        scatter_.use();
        glUniform1i(scatter_.uniform("uWriteKeys"), last && !withKeys ? 0 : 1);
        glDispatchCompute(groupsFor(tiles), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
}

} // namespace yv
