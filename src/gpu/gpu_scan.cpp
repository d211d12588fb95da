#include "gpu/gpu_scan.h"

#include "gpu/gl_bindings.h"

#include <algorithm>

namespace yv {
namespace {

constexpr std::uint64_t kScanBlock = 1024; // counts one work group covers (radix_scan.comp)

std::uint64_t blocksFor(std::uint64_t counts) { return (counts + kScanBlock - 1) / kScanBlock; }

} // namespace

GpuScan::GpuScan(std::uint64_t capacity, GLuint maxGroups)
    : maxGroups_(maxGroups), program_(GlProgram::compute("radix_scan.comp")) {
    reserve(capacity);
}

void GpuScan::reserve(std::uint64_t capacity) {
    blockSums_.reserve(blocksFor(std::max<std::uint64_t>(capacity, 1)) * 4, nullptr); // grows, never shrinks
}

void GpuScan::run(const GlBuffer& counts, std::uint32_t count, const GlBuffer* total) {
    const std::uint64_t blocks = blocksFor(count);
    counts.bindStorage(kSortHistogramBinding);
    blockSums_.bindStorage(kSortBlockSumsBinding);
    if (total) total->bindStorage(kSortKeptBinding);
    program_.use();
    glUniform1ui(program_.uniform("uCounts"), GLuint(count));
    glUniform1ui(program_.uniform("uBlockCount"), GLuint(blocks));
    glUniform1i(program_.uniform("uWriteTotal"), total ? 1 : 0);
    const GLuint groups = GLuint(std::clamp<std::uint64_t>(blocks, 1, maxGroups_));
    for (int phase = 0; phase < 3; ++phase) {
        glUniform1i(program_.uniform("uPhase"), phase);
        glDispatchCompute(phase == 1 ? 1 : groups, 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
}

} // namespace yv
