#include "gpu/radix_sort.h"

#include "gpu/gl_bindings.h"

#include <algorithm>

namespace yv {
namespace {

constexpr std::uint64_t kScanBlock = 1024; // counts one scan work group covers (radix_scan.comp)
constexpr int kPasses = 4;                 // 8 bits each

std::vector<std::string> tileDefines() {
    return {"RADIX_PER_THREAD " + std::to_string(RadixSort::kTile / 256) + "u"};
}

std::uint64_t tilesFor(std::uint64_t pairs) { return (pairs + RadixSort::kTile - 1) / RadixSort::kTile; }

} // namespace

RadixSort::RadixSort(std::uint64_t capacity, GLuint maxGroups)
    : maxGroups_(maxGroups), histogram_(GlProgram::compute("radix_histogram.comp", tileDefines())),
      scan_(GlProgram::compute("radix_scan.comp")), scatter_(GlProgram::compute("radix_scatter.comp", tileDefines())) {
    const std::uint64_t pairs = std::max<std::uint64_t>(capacity, 1);
    const std::uint64_t counts = 256 * tilesFor(pairs);
    for (int i = 0; i < 2; ++i) {
        keys_[i].reserve(pairs * 4, nullptr);
        values_[i].reserve(pairs * 4, nullptr);
    }
    histogramCounts_.reserve(counts * 4, nullptr);
    blockSums_.reserve((counts + kScanBlock - 1) / kScanBlock * 4, nullptr);
    kept_.reserve(16, nullptr);
    kept_.clear(16);
}

GLuint RadixSort::groupsFor(std::uint64_t groups) const {
    return static_cast<GLuint>(std::clamp<std::uint64_t>(groups, 1, maxGroups_));
}

void RadixSort::scan(std::uint32_t tiles, bool firstPass) {
    const std::uint64_t counts = 256ull * tiles, blocks = (counts + kScanBlock - 1) / kScanBlock;
    histogramCounts_.bindStorage(kSortHistogramBinding);
    blockSums_.bindStorage(kSortBlockSumsBinding);
    kept_.bindStorage(kSortKeptBinding);
    scan_.use();
    glUniform1ui(scan_.uniform("uCounts"), GLuint(counts));
    glUniform1ui(scan_.uniform("uBlockCount"), GLuint(blocks));
    glUniform1i(scan_.uniform("uWriteTotal"), firstPass ? 1 : 0);
    for (int phase = 0; phase < 3; ++phase) {
        glUniform1i(scan_.uniform("uPhase"), phase);
        glDispatchCompute(phase == 1 ? 1 : groupsFor(blocks), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
}

void RadixSort::sort(std::uint32_t count, const GlBuffer& out) {
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
        scan(tiles, first);
        keysIn.bindStorage(kSortKeysInBinding);
        valuesIn.bindStorage(kSortValuesInBinding);
        keysOut.bindStorage(kSortKeysOutBinding);
        valuesOut.bindStorage(kSortValuesOutBinding);
        histogramCounts_.bindStorage(kSortHistogramBinding);
        kept_.bindStorage(kSortKeptBinding);
        scatter_.use();
        glUniform1i(scatter_.uniform("uWriteKeys"), last ? 0 : 1);
        glDispatchCompute(groupsFor(tiles), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
}

} // namespace yv
