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

constexpr int kTilePixels = 16;          // inspect_slices_tiles.comp's kTileShift, the composite's group size
constexpr std::uint64_t kGroup = 256;    // inspect_slices_tiles.comp's local_size_x
constexpr std::uint32_t kMinDepthBits = 12; // fewer depth steps than this: too many tiles for one key

int tilesAcross(int pixels) { return (pixels + kTilePixels - 1) / kTilePixels; }

} // namespace

SliceTiles::SliceTiles(std::uint64_t slices, GLuint maxGroups, std::uint64_t maxPairs)
    : maxGroups_(maxGroups), slices_(std::max<std::uint64_t>(slices, 1)), maxPairs_(maxPairs),
      tiles_(GlProgram::compute("inspect_slices_tiles.comp")),
      composite_(GlProgram::compute("inspect_slices_composite.comp")),
      blend_(GlProgram::graphics("inspect_fullscreen.vert", "inspect_slices_composite.frag")), scan_(slices_, maxGroups),
      sort_(slices_, maxGroups), emptyArray_(createVertexArray()) {
    counts_.reserve(slices_ * 4, nullptr);
    totals_.reserve(8 * 4, nullptr);
    entries_.reserve(slices_ * 4, nullptr);
}

bool SliceTiles::prepare(const Camera& camera, const RadixSort& keysPass, std::uint32_t slices, float radius) {
    YV_CHECK(slices <= slices_);
    kept_ = pairs_ = 0;
    const int tilesX = tilesAcross(camera.width), tilesY = tilesAcross(camera.height);
    const std::uint64_t tiles = std::uint64_t(tilesX) * std::uint64_t(tilesY);
    const std::uint32_t tileBits = std::max(1, int(std::bit_width(tiles - 1)));
    if (tiles == 0 || 32 - tileBits < kMinDepthBits) return false;
    // The pairs stay within the scan's 32 bits whatever the slices.
    const std::uint32_t maxTiles = std::uint32_t(std::min<std::uint64_t>(
        tiles, std::numeric_limits<std::uint32_t>::max() / std::max<std::uint64_t>(slices, 1)));

    const GLuint groups = GLuint(std::clamp<std::uint64_t>((slices + kGroup - 1) / kGroup, 1, maxGroups_));
    const GLuint cleared[5] = {0, 0, 0, 0, 0xffffffffu}; // pairs, kept, too wide, nearest, farthest
    glNamedBufferSubData(totals_.id(), 0, sizeof cleared, cleared);
    tiles_.use();
    glUniform1ui(tiles_.uniform("uSlices"), slices);
    const glm::mat4 vp(camera.viewProjection());
    glUniformMatrix4fv(tiles_.uniform("uViewProjection"), 1, GL_FALSE, glm::value_ptr(vp));
    glUniform2f(tiles_.uniform("uPixels"), float(camera.width), float(camera.height));
    glUniform1i(tiles_.uniform("uTilesX"), tilesX);
    glUniform1f(tiles_.uniform("uRadius"), radius);
    glUniform1ui(tiles_.uniform("uMaxTilesPerSlab"), maxTiles);
    glUniform1ui(tiles_.uniform("uDepthBits"), 32 - tileBits);
    keysPass.keys().bindStorage(kSortKeysInBinding);
    keysPass.values().bindStorage(kSortValuesInBinding);
    counts_.bindStorage(kSliceTileCountsBinding);
    totals_.bindStorage(kSliceTileTotalsBinding);
    glUniform1i(tiles_.uniform("uPhase"), 0);
    glDispatchCompute(groups, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
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
    counts_.bindStorage(kSliceTileCountsBinding);
    totals_.bindStorage(kSliceTileTotalsBinding);
    keysPass.keys().bindStorage(kSortKeysInBinding);
    keysPass.values().bindStorage(kSortValuesInBinding);
    sort_.keys().bindStorage(kSliceTileKeysBinding);
    sort_.values().bindStorage(kSliceTileValuesBinding);
    glUniform1i(tiles_.uniform("uPhase"), 1);
    glDispatchCompute(groups, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    sort_.sort(GLuint(pairs_), entries_, /*withKeys=*/true);

    ranges_.reserve(tiles * 2 * 4, nullptr);
    ranges_.clear(tiles * 2 * 4);
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
    const int tilesX = tilesAcross(width), tilesY = tilesAcross(height);
    if (pairs_ == 0) {
        const float clear[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        glClearTexImage(picture_.id(), 0, GL_RGBA, GL_FLOAT, clear);
    } else {
        composite_.use(); // the caller has set the look
        const glm::mat4 inverseVp(glm::inverse(camera.viewProjection()));
        glUniformMatrix4fv(composite_.uniform("inverseViewProjection"), 1, GL_FALSE, glm::value_ptr(inverseVp));
        glUniform2f(composite_.uniform("viewportPixels"), float(width), float(height));
        glUniform1i(composite_.uniform("tilesX"), tilesX);
        entries_.bindStorage(kSliceTileEntriesBinding);
        ranges_.bindStorage(kSliceTileRangesBinding);
        glBindImageTexture(kSliceTilesImageUnit, picture_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
        glDispatchCompute(GLuint(tilesX), GLuint(tilesY), 1);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    }
    blend_.use();
    glBindTextureUnit(kSliceTilesPictureUnit, picture_.id());
    glBindVertexArray(emptyArray_.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    checkGlError("compositing the slices by tiles");
}

} // namespace yv
