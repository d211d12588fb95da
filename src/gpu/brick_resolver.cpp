#include "gpu/brick_resolver.h"

#include "core/error.h"
#include "core/trace.h"
#include "gpu/gl_bindings.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <string>

namespace yv {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

constexpr std::uint64_t kScanBlock = 1024; // slots one scan work group covers (brick_resolve_scan.comp)

std::vector<std::string> variant(Reduce reduce, Overlap overlap, bool albedo, bool countOnly) {
    std::vector<std::string> defines;
    if (reduce == Reduce::Max) defines.push_back("REDUCE_MAX 1");
    if (albedo) defines.push_back("ALBEDO 1");
    if (overlap == Overlap::Sum) defines.push_back("OVERLAP_SUM 1");
    if (countOnly) defines.push_back("COUNT_ONLY 1");
    return defines;
}

} // namespace

GlBrickResolver::GlBrickResolver(Reduce reduce, Overlap overlap, std::uint64_t* gpuBytes, bool albedo)
    : reduce_(reduce), albedo_(albedo), gpuBytes_(gpuBytes),
      count_(GlProgram::compute("brick_resolve.comp", variant(reduce, overlap, albedo, true))),
      scan_(GlProgram::compute("brick_resolve_scan.comp")),
      resolve_(GlProgram::compute("brick_resolve.comp", variant(reduce, overlap, albedo, false))) {
    if (albedo && reduce != Reduce::Mean)
        throw Error("--albedo needs --reduce mean (a colour is averaged like the density, not maxed)");
    totals_.reserve(8, gpuBytes_);
    GLint maxGroups = 0;
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &maxGroups);
    maxGroups_ = static_cast<GLuint>(std::clamp(maxGroups, 1, 65535));
}

void GlBrickResolver::startResolve(GLuint words, std::uint32_t count, const BrickKeys& keys,
                                   std::uint64_t maxActiveVoxels) {
    YV_CHECK(pendingCount_ < 2);
    Pending& p = pending_[pendingCount_];
    // The first buffer unless a resolve still holds it: a run that finishes
    // each resolve before the next starts pins host memory for one buffer
    // only (pinning ran at about 1.3 GB/s on the H100).
    p = Pending{pendingCount_ == 0 ? 0 : 1 - pending_[0].buffer, 0, 0};
    if (count == 0) {
        readback_[p.buffer].startCopy({}, gpuBytes_);
        ++pendingCount_;
        return;
    }
    const auto start = Clock::now();
    const std::uint64_t blocks = (count + kScanBlock - 1) / kScanBlock;
    places_.reserve(std::uint64_t(count) * 8, gpuBytes_);
    blockSums_.reserve(blocks * 8, gpuBytes_);
    // Sized for the most it can take (every slot kept, every voxel within the
    // bound active) so that the resolve runs before its totals are known and
    // one wait covers all three passes.
    const std::uint64_t headerBytes = std::uint64_t(count) * sizeof(PackedBrickHeader);
    const std::uint64_t voxelCapacity = std::min<std::uint64_t>(std::uint64_t(count) * kBrickVoxels, maxActiveVoxels);
    // With albedo the colours follow the voxels, one PackedAlbedo per voxel.
    const std::uint64_t albedoOffset = headerBytes + voxelCapacity * sizeof(PackedVoxel);
    output_.reserve(albedoOffset + (albedo_ ? voxelCapacity * sizeof(PackedAlbedo) : 0), gpuBytes_);
    const GLuint groups = std::min<GLuint>(count, maxGroups_); // one work group a slot, looping past the limit

    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBrickWordsBinding, words);
    places_.bindStorage(kResolvePlacesBinding);
    count_.use();
    glUniform1ui(count_.uniform("uBrickCount"), count);
    glDispatchCompute(groups, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

    blockSums_.bindStorage(kResolveBlockSumsBinding);
    totals_.bindStorage(kResolveTotalsBinding);
    scan_.use();
    glUniform1ui(scan_.uniform("uBrickCount"), count);
    glUniform1ui(scan_.uniform("uBlockCount"), static_cast<GLuint>(blocks));
    for (int phase = 0; phase < 3; ++phase) {
        glUniform1i(scan_.uniform("uPhase"), phase);
        glDispatchCompute(phase == 1 ? 1 : static_cast<GLuint>(blocks), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    }

    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kResolveKeysBinding, keys.buffer);
    output_.bindStorage(kPackedHeadersBinding);
    output_.bindStorage(kPackedVoxelsBinding);
    resolve_.use();
    glUniform1ui(resolve_.uniform("uBrickCount"), count);
    glUniform1i(resolve_.uniform("uKeysFromRegion"), keys.fromRegion ? 1 : 0);
    glUniform3i(resolve_.uniform("uBrickMin"), keys.brickMin.x, keys.brickMin.y, keys.brickMin.z);
    glUniform3i(resolve_.uniform("uRegionBricks"), keys.regionBricks.x, keys.regionBricks.y, keys.regionBricks.z);
    glUniform1ui(resolve_.uniform("uVoxelBase"), static_cast<GLuint>(headerBytes / sizeof(PackedVoxel)));
    if (albedo_) {
        output_.bindStorage(kPackedAlbedoBinding);
        glUniform1ui(resolve_.uniform("uAlbedoBase"), static_cast<GLuint>(albedoOffset / sizeof(float)));
    }
    glDispatchCompute(groups, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    checkGlError("brick resolve passes");

    std::uint32_t totals[2] = {0, 0}; // kept bricks, active voxels
    {
        const TraceSpan span("wait for the resolve's totals");
        std::memcpy(totals, small_.read(totals_.id(), 8, gpuBytes_), 8);
    }
    YV_CHECK(totals[0] <= count && totals[1] <= std::uint64_t(totals[0]) * kBrickVoxels && totals[1] <= voxelCapacity);
    gpuSeconds_ += secondsSince(start);

    // The output buffer is rewritten by the next resolve only after this
    // copy, which the GL command order keeps ahead of it.
    const auto readStart = Clock::now();
    const std::uint64_t keptBytes = std::uint64_t(totals[0]) * sizeof(PackedBrickHeader);
    const std::uint64_t voxelBytes = std::uint64_t(totals[1]) * sizeof(PackedVoxel);
    const std::uint64_t albedoBytes = albedo_ ? std::uint64_t(totals[1]) * sizeof(PackedAlbedo) : 0;
    // Grown half as large again when a pass needs more: each growth pins
    // host memory anew (the sweater at 4096 spent 0.13 s on 11 of them).
    ReadbackBuffer& readback = readback_[p.buffer];
    if (const std::uint64_t bytes = keptBytes + voxelBytes + albedoBytes; bytes > readback.capacity())
        readback.reserve(std::max(bytes, readback.capacity() + readback.capacity() / 2), gpuBytes_);
    readback.startCopy(
        {{output_.id(), 0, keptBytes}, {output_.id(), headerBytes, voxelBytes}, {output_.id(), albedoOffset, albedoBytes}},
        gpuBytes_);
    p.bricks = totals[0];
    p.voxels = totals[1];
    readbackSeconds_ += secondsSince(readStart);
    ++pendingCount_;
}

void GlBrickResolver::finishResolve(PackedBricks& out) {
    if (pendingCount_ == 0) return;
    const Pending p = pending_[0];
    pending_[0] = pending_[1];
    --pendingCount_;
    const auto readStart = Clock::now();
    const unsigned char* bytes = nullptr;
    {
        const TraceSpan span("wait for the packed bricks' copy");
        bytes = static_cast<const unsigned char*>(readback_[p.buffer].waitForCopy());
    }
    if (p.bricks > 0) {
        const TraceSpan span("append the packed bricks");
        const std::uint64_t keptBytes = std::uint64_t(p.bricks) * sizeof(PackedBrickHeader);
        const std::uint64_t voxelBytes = std::uint64_t(p.voxels) * sizeof(PackedVoxel);
        out.append(reinterpret_cast<const PackedBrickHeader*>(bytes), p.bricks,
                   reinterpret_cast<const PackedVoxel*>(bytes + keptBytes), p.voxels,
                   albedo_ ? reinterpret_cast<const PackedAlbedo*>(bytes + keptBytes + voxelBytes) : nullptr);
    }
    readbackSeconds_ += secondsSince(readStart);
}

void GlBrickResolver::resolve(const std::vector<BrickAccumulator>& accumulators, PackedBricks& out) {
    if (accumulators.empty()) return;
    const std::size_t perBrick = std::size_t(wordsPerVoxel(reduce_, albedo_)) * kBrickVoxels;
    std::vector<std::uint32_t> words(accumulators.size() * perBrick), keyWords(accumulators.size() * 2);
    for (std::size_t i = 0; i < accumulators.size(); ++i) {
        const BrickAccumulator& a = accumulators[i];
        if (a.words.size() != perBrick)
            throw Error("accumulator of brick key " + std::to_string(a.key) + " has " + std::to_string(a.words.size()) +
                        " words, " + toString(reduce_) + " needs " + std::to_string(perBrick));
        std::copy(a.words.begin(), a.words.end(), words.begin() + i * perBrick);
        keyWords[2 * i] = static_cast<std::uint32_t>(a.key);
        keyWords[2 * i + 1] = static_cast<std::uint32_t>(a.key >> 32);
    }
    uploadWords_.upload(words.data(), words.size() * 4, gpuBytes_);
    uploadKeys_.upload(keyWords.data(), keyWords.size() * 4, gpuBytes_);
    resolve(uploadWords_.id(), static_cast<std::uint32_t>(accumulators.size()), BrickKeys{uploadKeys_.id()}, out);
}

} // namespace yv
