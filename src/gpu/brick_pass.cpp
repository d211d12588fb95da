#include "gpu/brick_pass.h"

#include "core/sampling.h"
#include "core/trace.h"
#include "gpu/gl_bindings.h"

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

namespace yv {
namespace {

constexpr GLuint kWorkGroup = 256;          // the brick passes' local_size_x
constexpr std::uint64_t kScanBlock = 1024;  // bricks one scan work group covers (brick_scan.comp)

std::vector<std::string> scatterDefines(Reduce reduce, bool albedo) {
    std::vector<std::string> defines;
    if (reduce == Reduce::Max) defines.push_back("REDUCE_MAX 1");
    if (albedo) defines.push_back("ALBEDO 1");
    return defines;
}

} // namespace

BrickPass::BrickPass(Reduce reduce, bool albedo, GLuint maxGroups, bool timerQueries, std::uint64_t* gpuBytes)
    : reduce_(reduce), albedo_(albedo), wordsPerVoxel_(wordsPerVoxel(reduce, albedo)), maxGroups_(maxGroups),
      gpuBytes_(gpuBytes), flag_(GlProgram::compute("brick_flag.comp")),
      clear_(GlProgram::compute("buffer_clear.comp")), scan_(GlProgram::compute("brick_scan.comp")),
      scatter_(GlProgram::compute("brick_scatter.comp", scatterDefines(reduce, albedo))), timer_(timerQueries) {
    if (reduce_ == Reduce::Max) maxOrient_ = GlProgram::compute("brick_max_orient.comp");
    counts_.reserve(16, gpuBytes_);
}

GLuint BrickPass::groupsFor(std::uint64_t threads) const {
    const std::uint64_t groups = (threads + kWorkGroup - 1) / kWorkGroup;
    return static_cast<GLuint>(std::clamp<std::uint64_t>(groups, 1, maxGroups_));
}

void BrickPass::zero(const GlBuffer& buffer, std::uint64_t bytes) {
    clear_.use();
    glUniform1ui(clear_.uniform("uWords"), static_cast<GLuint>(bytes / 4));
    buffer.bindStorage(kClearedWordsBinding);
    glDispatchCompute(groupsFor(bytes / 4), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

std::optional<GLuint> BrickPass::build(const WorkItem& item, GLuint fragments, const SampleLists& lists,
                                       ReadbackBuffer& small, std::uint64_t brickBudget) {
    const glm::ivec3 bricks = item.bricks();
    const std::uint64_t regionBricks = std::uint64_t(bricks.x) * bricks.y * bricks.z;
    timer_.begin();
    // Flag the touched bricks.
    const std::uint64_t blocks = (regionBricks + kScanBlock - 1) / kScanBlock;
    flags_.reserve(regionBricks * 4, gpuBytes_);
    blockSums_.reserve(blocks * 4, gpuBytes_);
    zero(flags_, regionBricks * 4);
    flags_.bindStorage(kBrickSlotsBinding);
    lists.fragments().bindStorage(kFragmentsBinding);
    flag_.use();
    glUniform1ui(flag_.uniform("uCount"), fragments);
    glDispatchCompute(groupsFor(fragments), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

    // Scan the flags into slots, in three phases: per block, the blocks' sums, per block again.
    slotBricks_.reserve(std::min<std::uint64_t>(regionBricks, fragments) * 4, gpuBytes_);
    blockSums_.bindStorage(kBrickBlockSumsBinding);
    counts_.bindStorage(kBrickCountsBinding);
    slotBricks_.bindStorage(kSlotBricksBinding);
    scan_.use();
    glUniform1ui(scan_.uniform("uBrickCount"), static_cast<GLuint>(regionBricks));
    glUniform1ui(scan_.uniform("uBlockCount"), static_cast<GLuint>(blocks));
    for (int phase = 0; phase < 3; ++phase) {
        glUniform1i(scan_.uniform("uPhase"), phase);
        glDispatchCompute(phase == 1 ? 1 : static_cast<GLuint>(blocks), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    }
    GLuint activeBricks = 0;
    {
        const TraceSpan span("wait for the touched bricks");
        std::memcpy(&activeBricks, small.read(counts_.id(), 4, gpuBytes_), 4);
    }
    if (activeBricks > brickBudget) {
        timer_.end();
        return std::nullopt;
    }

    // Scatter the fragments into the touched bricks only.
    const std::uint64_t brickWords = std::uint64_t(activeBricks) * wordsPerVoxel_ * kBrickVoxels;
    brickWords_.reserve(brickWords * 4, gpuBytes_);
    zero(brickWords_, brickWords * 4);
    scatter(fragments, lists);
    timer_.end();
    checkGlError("brick passes");
    return activeBricks;
}

void BrickPass::scatter(GLuint fragments, const SampleLists& lists) {
    brickWords_.bindStorage(kBrickWordsBinding);
    // (The scan's block sums were bound where the colours go.)
    if (albedo_) lists.albedoFragments().bindStorage(kAlbedoFragmentsBinding);
    scatter_.use();
    glUniform1ui(scatter_.uniform("uCount"), fragments);
    glDispatchCompute(groupsFor(fragments), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    if (reduce_ == Reduce::Max) {
        maxOrient_.use();
        glUniform1ui(maxOrient_.uniform("uCount"), fragments);
        glDispatchCompute(groupsFor(fragments), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    }
}

} // namespace yv
