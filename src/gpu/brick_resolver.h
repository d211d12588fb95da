// The GPU resolve: turns accumulated brick slots into finished bricks (what
// resolveBrick does on the CPU), drops the empty ones, compacts the active
// voxels and reads back only those, packed (src/core/packed_bricks.h).
#pragma once

#include "core/bricks.h"
#include "core/packed_bricks.h"
#include "gpu/gl_buffer.h"
#include "gpu/gl_program.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace yv {

/// GPU bytes the resolve's output needs per brick slot, at most (`albedo`: with each voxel's colour).
constexpr std::uint64_t resolveBytesPerBrick(bool albedo) {
    return sizeof(PackedBrickHeader) + kBrickVoxels * (sizeof(PackedVoxel) + (albedo ? sizeof(PackedAlbedo) : 0));
}

/// Where the key of each brick slot comes from.
struct BrickKeys {
    GLuint buffer = 0;             ///< region brick index per slot (fromRegion), else two key words per slot
    bool fromRegion = false;
    glm::ivec3 brickMin{0};        ///< the region's first brick (fromRegion)
    glm::ivec3 regionBricks{0};    ///< bricks along each axis of the region (fromRegion)
};

/// Resolves bricks on a live GL 4.5 context (needs double precision in
/// shaders, core since 4.0).
class GlBrickResolver {
  public:
    /// `gpuBytes`, where given, tracks the sum of yarnvox's GPU buffers.
    /// `albedo` (mean only): the slots carry the albedo words, and the packed
    /// bricks get each active voxel's colour.
    GlBrickResolver(Reduce reduce, Overlap overlap, std::uint64_t* gpuBytes = nullptr, bool albedo = false);

    /// Resolves `count` slots of `words` (wordsPerVoxel(reduce, albedo) channels of
    /// 512 words per slot, channel-major, as BrickAccumulator) and appends the
    /// bricks with an active voxel to `out`, in slot order. Waits twice for
    /// the GPU: for the totals (a few bytes), then for the packed bricks.
    /// `maxActiveVoxels` bounds the active voxels (the pass's fragment count
    /// does: every active voxel got one), so the output needs less GPU memory.
    void resolve(GLuint words, std::uint32_t count, const BrickKeys& keys, PackedBricks& out,
                 std::uint64_t maxActiveVoxels = ~std::uint64_t(0)) {
        startResolve(words, count, keys, maxActiveVoxels);
        finishResolve(out);
    }
    /// The same in two halves, so that the host can queue the next pass's
    /// work between them: startResolve waits for the totals only and queues
    /// the copy of the packed bricks; finishResolve waits for that copy and
    /// appends the bricks. A second host buffer takes the copy of a resolve
    /// that starts while the one before is still to finish; a third start
    /// finishes nothing for you (call finishResolve in between).
    void startResolve(GLuint words, std::uint32_t count, const BrickKeys& keys,
                      std::uint64_t maxActiveVoxels = ~std::uint64_t(0));
    /// Appends the oldest started resolve's bricks to `out`; nothing when none is started.
    void finishResolve(PackedBricks& out);
    /// True while a started resolve has not been finished.
    bool resolvePending() const { return pendingCount_ > 0; }
    /// The same for accumulators on the host (uploaded first), in their order.
    void resolve(const std::vector<BrickAccumulator>& accumulators, PackedBricks& out);

    std::uint64_t bytesRead() const { return small_.bytesRead() + readback_[0].bytesRead() + readback_[1].bytesRead(); }
    /// Time from the first resolve pass until its totals were read back (the GPU's resolve work).
    double gpuSeconds() const { return gpuSeconds_; }
    /// Time of copying the packed bricks to the host.
    double readbackSeconds() const { return readbackSeconds_; }

  private:
    Reduce reduce_;
    bool albedo_;
    std::uint64_t* gpuBytes_;
    GlProgram count_, scan_, resolve_;
    GlBuffer places_, blockSums_, totals_, output_, uploadWords_, uploadKeys_;
    /// A resolve whose packed bricks are being copied to readback_[buffer].
    struct Pending {
        int buffer = 0;
        std::uint32_t bricks = 0, voxels = 0; ///< the totals
    };
    ReadbackBuffer small_, readback_[2];
    Pending pending_[2];        ///< oldest first
    int pendingCount_ = 0;
    GLuint maxGroups_ = 65535;
    double gpuSeconds_ = 0.0, readbackSeconds_ = 0.0;
};

} // namespace yv
