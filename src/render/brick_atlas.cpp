#include "render/brick_atlas.h"

#include "core/error.h"
#include "gpu/gl_program.h"

#include <glm/common.hpp>
#include <glm/vector_relational.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace yv {

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
    rowDensity_.assign(std::size_t(slots_.x) * 512u, 0.0f);
    if (withOrientation) rowOrientation_.assign(std::size_t(slots_.x) * 512u * 4u, 0u);
}

void BrickAtlas::uploadRow() {
    if (!rowStaged_) return;
    const int width = slots_.x * kBrickSize;
    const int y = int(row_ % std::uint64_t(slots_.y)) * kBrickSize, z = int(row_ / std::uint64_t(slots_.y)) * kBrickSize;
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage3D(density_.id(), 0, 0, y, z, width, 8, 8, GL_RED, GL_FLOAT, rowDensity_.data());
    if (withOrientation_)
        glTextureSubImage3D(orientation_.id(), 0, 0, y, z, width, 8, 8, GL_RGBA, GL_UNSIGNED_BYTE, rowOrientation_.data());
    rowStaged_ = false;
}

void BrickAtlas::upload(const LevelBrick& brick) {
    const glm::ivec3 c = brick.coord, d = plan_.brickDims;
    if (glm::any(glm::lessThan(c, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(c, d)))
        throw Error("brick atlas: a brick outside the level's grid");
    std::uint32_t& slot = slotOf_[std::size_t(c.x) + std::size_t(d.x) * (std::size_t(c.y) + std::size_t(d.y) * std::size_t(c.z))];
    if (slot != 0u) throw Error("brick atlas: a brick given twice");
    if (used_ >= std::uint64_t(slots_.x) * std::uint64_t(slots_.y) * std::uint64_t(slots_.z))
        throw Error("brick atlas: more bricks than the level plan counted");
    const std::uint64_t s = used_++;
    slot = std::uint32_t(s + 1);
    // Slots fill in order, so a row is whole once the next one begins.
    if (s / std::uint64_t(slots_.x) != row_) {
        uploadRow();
        row_ = s / std::uint64_t(slots_.x);
    }
    rowStaged_ = true;
    // Voxel (x, y, z) of the brick lies at texel (8 i + x, y, z) of the row, x fastest.
    const std::size_t i = std::size_t(s % std::uint64_t(slots_.x)), width = std::size_t(slots_.x) * 8u;
    for (std::size_t z = 0; z < 8; ++z)
        for (std::size_t y = 0; y < 8; ++y) {
            const std::size_t from = 8 * (y + 8 * z), to = 8 * i + width * (y + 8 * z);
            std::copy_n(brick.density.data() + from, 8, rowDensity_.data() + to);
            if (!withOrientation_) continue;
            for (std::size_t x = 0; x < 8; ++x) {
                const glm::vec3 a = glm::clamp(brick.axisColour[from + x], 0.0f, 1.0f);
                std::uint8_t* rgba = rowOrientation_.data() + 4 * (to + x);
                rgba[0] = std::uint8_t(std::lround(255.0f * a.x));
                rgba[1] = std::uint8_t(std::lround(255.0f * a.y));
                rgba[2] = std::uint8_t(std::lround(255.0f * a.z));
                rgba[3] = 255;
            }
        }
    for (const float d : brick.density) densityMax_ = std::max(densityMax_, d);
}

void BrickAtlas::finish() {
    uploadRow();
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
