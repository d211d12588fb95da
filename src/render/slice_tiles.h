// The slices render composited in compute, tile by tile of the picture, with
// no raster: where the slabs are many and small on screen (a whole garment
// of 41 M slices at 1280x720), setting up a primitive for each, point or
// box, is what a frame waits for on a GPU whose raster is slow next to its
// compute. As a tiled splatting renderer does:
//   1. the keys pass (inspect_slices_keys.comp) has each slab it keeps count
//      the 16 x 16 tiles holding pixels its screen box holds, and the counts
//      are scanned;
//   2. each writes a (tile, depth) pair for each (inspect_slices_tiles.comp),
//      sorted by the radix sort: each tile's slabs nearest first;
//   3. one work group a tile, one thread a pixel, casts the pixel's ray
//      through the tile's slabs in that order and blends front to back,
//      stopping once the tile's pixels are opaque
//      (inspect_slices_composite.comp), then one full-screen draw blends the
//      picture over the frame.
// The host waits once a frame, for three words (the pairs, the slabs kept,
// whether one spans too many tiles), to size the sort. A picture of more
// than 256 tiles (4096 pixels) across is drawn otherwise. A slab reaching the
// eye's plane touches every tile. A frame whose pairs would pass 32 bits
// (a slab over 2^32 / slices tiles) or the limit of pairs a slice is not
// drawn here: prepare() says so and the renderer draws points or boxes.
// (The context must be current.)
#pragma once

#include "gpu/gl_buffer.h"
#include "gpu/gl_objects.h"
#include "gpu/gl_program.h"
#include "gpu/gpu_scan.h"
#include "gpu/radix_sort.h"
#include "inspect/camera.h"

#include <cstdint>

namespace yv {

/// The most pairs a frame may make for each slice (and a million more):
/// the sort's buffers never grow beyond it.
constexpr std::uint64_t kMaxTilePairsPerSlice = 4;
/// That limit for `slices` slices.
constexpr std::uint64_t defaultMaxTilePairs(std::uint64_t slices) { return kMaxTilePairsPerSlice * slices + (1u << 20); }

class SliceTiles {
  public:
    /// For up to `slices` slices; `maxGroups`: the work groups a dispatch
    /// may have; `maxPairs`: the most pairs a frame composited here may make.
    SliceTiles(std::uint64_t slices, GLuint maxGroups, std::uint64_t maxPairs);

    /// Before the keys pass: has `keys` (inspect_slices_keys.comp, in use)
    /// count each slab's tiles for this frame, or not (uTiles) where the
    /// picture cannot be composited by tiles (false).
    bool setUpKeysPass(const GlProgram& keys, const Camera& camera, std::uint32_t slices);
    /// After the keys pass, with its pairs in `keysPass`'s keys() and
    /// values() (kept slices and their distances) and the tiles it counted:
    /// where the frame may be composited by tiles, sorts its pairs. Waits for
    /// the counts. False: the keys pass counted no tiles, a slab spans too
    /// many or the pairs exceed the limit, and nothing more was queued.
    bool prepare(const Camera& camera, const RadixSort& keysPass, std::uint32_t slices);
    /// The slabs the last prepare() kept (drawn or not).
    std::uint64_t kept() const { return kept_; }
    /// The pairs the last prepare() made (one a slab and tile).
    std::uint64_t pairs() const { return pairs_; }

    /// The compositing program, for the caller to set the slabs' look on
    /// (uniforms viewProjection, eye, lightDirection, albedo, radius,
    /// twist, opacityPerVoxel, as the raster programs have them).
    const GlProgram& compositeProgram() const { return composite_; }
    /// Composites the frame last prepared into a picture of its own and
    /// blends it over the bound frame ("over", premultiplied: blending as
    /// the caller set it). The slice table and spans stay bound.
    void draw(const Camera& camera);

  private:
    GLuint maxGroups_;
    std::uint64_t slices_, maxPairs_;
    GlProgram tiles_, composite_, blend_;
    GpuScan scan_;
    RadixSort sort_;
    GlBuffer counts_, rects_, totals_, entries_, ranges_;
    GlTexture picture_;
    GlVertexArray emptyArray_;
    ReadbackBuffer readback_;
    int pictureWidth_ = 0, pictureHeight_ = 0;
    bool counting_ = false; ///< the keys pass set up last counts tiles
    std::uint64_t kept_ = 0, pairs_ = 0;
};

} // namespace yv
