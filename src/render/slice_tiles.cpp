#include "render/slice_tiles.h"

#include "core/error.h"
#include "core/trace.h"
#include "gpu/gl_bindings.h"

#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <bit>
#include <cstring>
#include <limits>

namespace yv {
namespace {

constexpr int kTilePixels = 16;          // slabs.glsl's slabTiles (>> 4), the composite's group size
constexpr std::uint64_t kGroup = 256;    // inspect_slices_tiles.comp's local_size_x
constexpr std::uint32_t kMinDepthBits = 12; // fewer depth steps than this: too many tiles for one key

int tilesAcross(int pixels) { return (pixels + kTilePixels - 1) / kTilePixels; }

/// The picture's tiles, and whether it may be composited by tiles at all.
struct TileGrid {
    int across = 0, down = 0;
    std::uint64_t count = 0;
    std::uint32_t bits = 0; ///< of a pair's key, for the tile
    bool usable = false;
};

TileGrid tileGridOf(const Camera& camera) {
    TileGrid g;
    g.across = tilesAcross(camera.width);
    g.down = tilesAcross(camera.height);
    g.count = std::uint64_t(g.across) * std::uint64_t(g.down);
    g.bits = std::uint32_t(std::max(1, int(std::bit_width(std::max<std::uint64_t>(g.count, 1) - 1))));
    // A slab's tiles are kept a byte a coordinate (inspect_slices_keys.comp).
    g.usable = g.count > 0 && g.across <= 256 && g.down <= 256 && 32 - g.bits >= kMinDepthBits;
    return g;
}

} // namespace

SliceTiles::SliceTiles(std::uint64_t slices, GLuint maxGroups, std::uint64_t maxPairs)
    : maxGroups_(maxGroups), slices_(std::max<std::uint64_t>(slices, 1)), maxPairs_(maxPairs),
      tiles_(GlProgram::compute("inspect_slices_tiles.comp")),
      composite_(GlProgram::compute("inspect_slices_composite.comp")),
      blend_(GlProgram::graphics("inspect_fullscreen.vert", "inspect_slices_composite.frag")), scan_(slices_, maxGroups),
      sort_(slices_, maxGroups), emptyArray_(createVertexArray()) {
    counts_.reserve(slices_ * 4, nullptr);
    rects_.reserve(slices_ * 4, nullptr);
    totals_.reserve(8 * 4, nullptr);
    entries_.reserve(slices_ * 4, nullptr);
}

bool SliceTiles::setUpKeysPass(const GlProgram& keys, const Camera& camera, std::uint32_t slices) {
    YV_CHECK(slices <= slices_);
    const TileGrid grid = tileGridOf(camera);
    counting_ = grid.usable;
    glUniform1i(keys.uniform("uTiles"), counting_ ? 1 : 0);
    if (!counting_) return false;
    // The pairs stay within the scan's 32 bits whatever the slices.
    const std::uint32_t maxTiles = std::uint32_t(std::min<std::uint64_t>(
        grid.count, std::numeric_limits<std::uint32_t>::max() / std::max<std::uint64_t>(slices, 1)));
    const GLuint cleared[5] = {0, 0, 0, 0, 0xffffffffu}; // pairs, kept, too wide, nearest, farthest
    glNamedBufferSubData(totals_.id(), 0, sizeof cleared, cleared);
    const glm::mat4 vp(camera.viewProjection());
    glUniformMatrix4fv(keys.uniform("uViewProjection"), 1, GL_FALSE, glm::value_ptr(vp));
    glUniform2f(keys.uniform("uPixels"), float(camera.width), float(camera.height));
    glUniform1ui(keys.uniform("uMaxTilesPerSlab"), maxTiles);
    counts_.bindStorage(kSliceTileCountsBinding);
    totals_.bindStorage(kSliceTileTotalsBinding);
    rects_.bindStorage(kSliceTileRectsBinding);
    return true;
}

bool SliceTiles::prepare(const Camera& camera, const RadixSort& keysPass, std::uint32_t slices) {
    YV_CHECK(slices <= slices_);
    kept_ = pairs_ = 0;
    if (!counting_) return false;
    counting_ = false;
    const TileGrid grid = tileGridOf(camera);
    const GLuint groups = GLuint(std::clamp<std::uint64_t>((slices + kGroup - 1) / kGroup, 1, maxGroups_));
    scan_.run(counts_, slices, &totals_);

    GLuint totals[3];
    {
        const TraceSpan span("slices: wait for the tiles' counts");
        std::memcpy(totals, readback_.read(totals_.id(), sizeof totals, nullptr), sizeof totals);
    }
    kept_ = totals[1];
    pairs_ = totals[0];
    if (totals[2] != 0 || pairs_ > maxPairs_) return false;
    if (pairs_ == 0) return true;

    sort_.reserve(pairs_);
    entries_.reserve(pairs_ * 4, nullptr);
    tiles_.use();
    glUniform1ui(tiles_.uniform("uSlices"), slices);
    glUniform1i(tiles_.uniform("uTilesX"), grid.across);
    glUniform1ui(tiles_.uniform("uDepthBits"), 32 - grid.bits);
    counts_.bindStorage(kSliceTileCountsBinding);
    totals_.bindStorage(kSliceTileTotalsBinding);
    keysPass.keys().bindStorage(kSortKeysInBinding);
    keysPass.values().bindStorage(kSortValuesInBinding);
    sort_.keys().bindStorage(kSliceTileKeysBinding);
    sort_.values().bindStorage(kSliceTileValuesBinding);
    rects_.bindStorage(kSliceTileRectsBinding);
    glUniform1i(tiles_.uniform("uPhase"), 1);
    glDispatchCompute(groups, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    sort_.sort(GLuint(pairs_), entries_, /*withKeys=*/true);

    ranges_.reserve(grid.count * 2 * 4, nullptr);
    ranges_.clear(grid.count * 2 * 4);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    tiles_.use();
    glUniform1i(tiles_.uniform("uPhase"), 2);
    glUniform1ui(tiles_.uniform("uSlices"), GLuint(pairs_));
    sort_.keys().bindStorage(kSliceTileKeysBinding);
    ranges_.bindStorage(kSliceTileRangesBinding);
    glDispatchCompute(GLuint(std::clamp<std::uint64_t>((pairs_ + kGroup - 1) / kGroup, 1, maxGroups_)), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    checkGlError("the slices' tiles");
    return true;
}

void SliceTiles::draw(const Camera& camera) {
    const int width = camera.width, height = camera.height;
    if (width != pictureWidth_ || height != pictureHeight_) {
        picture_ = createTexture(GL_TEXTURE_2D);
        glTextureStorage2D(picture_.id(), 1, GL_RGBA16F, width, height);
        pictureWidth_ = width;
        pictureHeight_ = height;
    }
    const TileGrid grid = tileGridOf(camera);
    if (pairs_ == 0) {
        const float clear[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        glClearTexImage(picture_.id(), 0, GL_RGBA, GL_FLOAT, clear);
    } else {
        composite_.use(); // the caller has set the look
        const glm::mat4 inverseVp(glm::inverse(camera.viewProjection()));
        glUniformMatrix4fv(composite_.uniform("inverseViewProjection"), 1, GL_FALSE, glm::value_ptr(inverseVp));
        glUniform2f(composite_.uniform("viewportPixels"), float(width), float(height));
        glUniform1i(composite_.uniform("tilesX"), grid.across);
        entries_.bindStorage(kSliceTileEntriesBinding);
        ranges_.bindStorage(kSliceTileRangesBinding);
        glBindImageTexture(kSliceTilesImageUnit, picture_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
        glDispatchCompute(GLuint(grid.across), GLuint(grid.down), 1);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    }
    blend_.use();
    glBindTextureUnit(kSliceTilesPictureUnit, picture_.id());
    glBindVertexArray(emptyArray_.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    checkGlError("compositing the slices by tiles");
}

} // namespace yv
