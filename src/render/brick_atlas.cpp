#include "render/brick_atlas.h"

#include "core/default_init_allocator.h"
#include "core/error.h"
#include "core/huge_pages.h"
#include "core/trace.h"
#include "gpu/gl_program.h"

#include <Imath/half.h>
#include <tbb/combinable.h>
#include <glm/common.hpp>
#include <glm/vector_relational.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace yv {

namespace {

/// A level's texels on the host, filled by several threads at once.
template <typename T>
using Staging = std::vector<T, DefaultInitAllocator<T, HugePageAllocator<T>>>;

/// One voxel's texels: density as a half (rounded to nearest even; handed
/// floats for a 16-bit texture, NVIDIA's driver converts them on a slow path,
/// about 5 us a brick on the H200) and, where `colour` is given, |axis| as RGBA8.
void writeTexel(std::uint16_t* density, std::uint8_t* colour, std::size_t t, float d, glm::vec3 axisColour) {
    density[t] = imath_float_to_half(d);
    if (!colour) return;
    const glm::vec3 a = glm::clamp(axisColour, 0.0f, 1.0f);
    colour[4 * t + 0] = std::uint8_t(std::lround(255.0f * a.x));
    colour[4 * t + 1] = std::uint8_t(std::lround(255.0f * a.y));
    colour[4 * t + 2] = std::uint8_t(std::lround(255.0f * a.z));
    colour[4 * t + 3] = 255;
}

} // namespace

int atlasBytesPerVoxel(bool withOrientation) { return withOrientation ? 6 : 2; }

BrickAtlas::BrickAtlas(const LevelPlan& plan, bool withOrientation, int max3dTextureSize)
    : plan_(plan), withOrientation_(withOrientation) {
    const std::uint64_t n = std::max<std::uint64_t>(plan.bricks.size(), 1);
    const int side = std::max(1, max3dTextureSize / kBrickSize);
    slots_.x = int(std::min<std::uint64_t>(n, std::uint64_t(side)));
    slots_.y = int(std::min<std::uint64_t>((n + std::uint64_t(slots_.x) - 1) / std::uint64_t(slots_.x), std::uint64_t(side)));
    const std::uint64_t layer = std::uint64_t(slots_.x) * std::uint64_t(slots_.y);
    slots_.z = int((n + layer - 1) / layer);
    if (slots_.z > side) throw Error("the brick atlas needs more than " + std::to_string(side) + " bricks a side");
    slotOf_.assign(std::size_t(plan.brickDims.x) * std::size_t(plan.brickDims.y) * std::size_t(plan.brickDims.z), 0u);

    const glm::ivec3 texels = slots_ * kBrickSize;
    density_ = createTexture(GL_TEXTURE_3D);
    glTextureStorage3D(density_.id(), 1, GL_R16F, texels.x, texels.y, texels.z);
    if (withOrientation) {
        orientation_ = createTexture(GL_TEXTURE_3D);
        glTextureStorage3D(orientation_.id(), 1, GL_RGBA8, texels.x, texels.y, texels.z);
    }
    indirection_ = createTexture(GL_TEXTURE_3D);
    glTextureStorage3D(indirection_.id(), 1, GL_R32UI, plan.brickDims.x, plan.brickDims.y, plan.brickDims.z);
    for (GLuint t : {density_.id(), orientation_.id(), indirection_.id()}) {
        if (!t) continue;
        glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
    checkGlError("allocating the brick atlas (lower --gpu-budget?)");
}

void BrickAtlas::upload(const LevelBrick& brick) {
    const glm::ivec3 c = brick.coord, d = plan_.brickDims;
    if (glm::any(glm::lessThan(c, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(c, d)))
        throw Error("brick atlas: a brick outside the level's grid");
    std::uint32_t& slot = slotOf_[indirectionIndex(c)];
    if (slot != 0u) throw Error("brick atlas: a brick given twice");
    if (used_ >= std::uint64_t(slots_.x) * std::uint64_t(slots_.y) * std::uint64_t(slots_.z))
        throw Error("brick atlas: more bricks than the level plan counted");
    const std::uint64_t s = used_++;
    slot = std::uint32_t(s + 1);
    const std::size_t rowTexels = std::size_t(slots_.x) * kBrickSize;
    if (rowDensity_.empty()) {
        rowDensity_.assign(rowTexels * 64, 0);
        if (withOrientation_) rowOrientation_.assign(4 * rowTexels * 64, 0);
    }
    // The brick's voxels (x fastest) into its place along the row: texel
    // (8 slot + x, y, z) of a block slots_.x * 8 wide and 8 high.
    const std::size_t x0 = std::size_t(s - rowStart_) * kBrickSize;
    std::uint8_t* colour = withOrientation_ ? rowOrientation_.data() : nullptr;
    for (int z = 0; z < kBrickSize; ++z)
        for (int y = 0; y < kBrickSize; ++y)
            for (int x = 0; x < kBrickSize; ++x) {
                const std::size_t v = std::size_t(x + kBrickSize * (y + kBrickSize * z));
                const std::size_t t = x0 + std::size_t(x) + rowTexels * std::size_t(y + kBrickSize * z);
                writeTexel(rowDensity_.data(), colour, t, brick.density[v], brick.axisColour[v]);
                densityMax_ = std::max(densityMax_, brick.density[v]);
            }
    if (used_ - rowStart_ == std::uint64_t(slots_.x)) uploadRow();
}

void BrickAtlas::uploadRow() {
    const std::uint64_t filled = used_ - rowStart_;
    if (filled == 0) return;
    uploadRowTexels(rowStart_ / std::uint64_t(slots_.x), filled, rowDensity_.data(),
                    withOrientation_ ? rowOrientation_.data() : nullptr);
    rowStart_ = used_;
}

void BrickAtlas::uploadRowTexels(std::uint64_t row, std::uint64_t filled, const std::uint16_t* density,
                                 const std::uint8_t* colour) {
    const TraceSpan span("upload a row of bricks");
    const int y = int(row % std::uint64_t(slots_.y)) * kBrickSize, z = int(row / std::uint64_t(slots_.y)) * kBrickSize;
    const GLsizei width = GLsizei(filled) * kBrickSize;
    // A last row partly filled: the block's rows keep their full length.
    glPixelStorei(GL_UNPACK_ROW_LENGTH, slots_.x * kBrickSize);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
    glTextureSubImage3D(density_.id(), 0, 0, y, z, width, kBrickSize, kBrickSize, GL_RED, GL_HALF_FLOAT, density);
    if (colour) {
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glTextureSubImage3D(orientation_.id(), 0, 0, y, z, width, kBrickSize, kBrickSize, GL_RGBA, GL_UNSIGNED_BYTE,
                            colour);
    }
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
}

void BrickAtlas::uploadLevelZero(const VolumeSource& source, const VoxelBox& clip) {
    YV_CHECK(plan_.level == 0 && used_ == 0);
    const std::uint64_t n = plan_.bricks.size(), perRow = std::uint64_t(slots_.x);
    const std::uint64_t rows = (n + perRow - 1) / perRow;
    const std::size_t rowTexels = std::size_t(perRow) * kBrickSize, rowBlock = rowTexels * 64;
    // Every row's texels, as upload() lays one out, rows one after another;
    // pages left untouched until the threads that fill them fault them in.
    Staging<std::uint16_t> density;
    Staging<std::uint8_t> colour;
    {
        const TraceSpan span("convert the level's bricks");
        density.resize(std::size_t(rows) * rowBlock);
        if (withOrientation_) colour.resize(4 * std::size_t(rows) * rowBlock);
        tbb::combinable<float> maxima([] { return 0.0f; });
        std::uint8_t* colours = withOrientation_ ? colour.data() : nullptr;
        forEachLevelZeroBrick(source, clip, plan_, [&](std::size_t s, const SourceBrick& b) {
            slotOf_[indirectionIndex(plan_.bricks[s])] = std::uint32_t(s + 1);
            const std::size_t base = std::size_t(s / perRow) * rowBlock + std::size_t(s % perRow) * kBrickSize;
            float& most = maxima.local();
            for (int z = 0; z < kBrickSize; ++z)
                for (int y = 0; y < kBrickSize; ++y)
                    for (int x = 0; x < kBrickSize; ++x) {
                        const int from = brickOffset(x, y, z);
                        const std::size_t t = base + std::size_t(x) + rowTexels * std::size_t(y + kBrickSize * z);
                        // |axis| where there is density, as the level sums make it.
                        const glm::vec3 axis = b.orientation && b.density[from] != 0.0f ? glm::abs(b.orientation[from])
                                                                                        : glm::vec3(0.0f);
                        writeTexel(density.data(), colours, t, b.density[from], axis);
                        most = std::max(most, b.density[from]);
                    }
        });
        densityMax_ = maxima.combine([](float a, float b) { return std::max(a, b); });
    }
    used_ = rowStart_ = n;
    for (std::uint64_t r = 0; r < rows; ++r)
        uploadRowTexels(r, std::min(perRow, n - r * perRow), density.data() + r * rowBlock,
                        withOrientation_ ? colour.data() + 4 * r * rowBlock : nullptr);
    uploadIndirection();
}

void BrickAtlas::finish() {
    uploadRow();
    std::vector<std::uint16_t>().swap(rowDensity_);
    std::vector<std::uint8_t>().swap(rowOrientation_);
    uploadIndirection();
}

void BrickAtlas::uploadIndirection() {
    const glm::ivec3 d = plan_.brickDims;
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage3D(indirection_.id(), 0, 0, 0, 0, d.x, d.y, d.z, GL_RED_INTEGER, GL_UNSIGNED_INT, slotOf_.data());
    checkGlError("uploading the brick atlas");
}

void BrickAtlas::setAddressingUniforms(const GlProgram& p) const {
    glUniform3i(p.uniform("atlasSlots"), slots_.x, slots_.y, slots_.z);
    glUniform3f(p.uniform("originVoxel"), float(plan_.originVoxel.x), float(plan_.originVoxel.y),
                float(plan_.originVoxel.z));
    glUniform1f(p.uniform("levelScale"), float(plan_.scale));
    glUniform3i(p.uniform("brickDims"), plan_.brickDims.x, plan_.brickDims.y, plan_.brickDims.z);
}

} // namespace yv
