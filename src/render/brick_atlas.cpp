#include "render/brick_atlas.h"

#include "core/error.h"
#include "core/trace.h"
#include "gpu/gl_program.h"

#include <Imath/half.h>
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
}

void BrickAtlas::upload(const LevelBrick& brick) {
    const TraceSpan span("upload a brick");
    const glm::ivec3 c = brick.coord, d = plan_.brickDims;
    if (glm::any(glm::lessThan(c, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(c, d)))
        throw Error("brick atlas: a brick outside the level's grid");
    std::uint32_t& slot = slotOf_[std::size_t(c.x) + std::size_t(d.x) * (std::size_t(c.y) + std::size_t(d.y) * std::size_t(c.z))];
    if (slot != 0u) throw Error("brick atlas: a brick given twice");
    if (used_ >= std::uint64_t(slots_.x) * std::uint64_t(slots_.y) * std::uint64_t(slots_.z))
        throw Error("brick atlas: more bricks than the level plan counted");
    const std::uint64_t s = used_++;
    slot = std::uint32_t(s + 1);
    const glm::ivec3 at = glm::ivec3(int(s % std::uint64_t(slots_.x)), int((s / std::uint64_t(slots_.x)) % std::uint64_t(slots_.y)),
                                     int(s / (std::uint64_t(slots_.x) * std::uint64_t(slots_.y)))) * kBrickSize;
    // Halves made here (rounded to nearest even) and copied as they are: handed
    // floats for a 16-bit texture, NVIDIA's driver converts them on a slow
    // path (about 5 us a brick on the H200, half a second for 100 k bricks).
    std::array<std::uint16_t, 512> halves;
    for (std::size_t v = 0; v < 512; ++v) {
        halves[v] = imath_float_to_half(brick.density[v]);
        densityMax_ = std::max(densityMax_, brick.density[v]);
    }
    glTextureSubImage3D(density_.id(), 0, at.x, at.y, at.z, 8, 8, 8, GL_RED, GL_HALF_FLOAT, halves.data());
    if (withOrientation_) {
        std::array<std::uint8_t, 4 * 512> rgba;
        for (std::size_t v = 0; v < 512; ++v) {
            const glm::vec3 a = glm::clamp(brick.axisColour[v], 0.0f, 1.0f);
            rgba[4 * v + 0] = std::uint8_t(std::lround(255.0f * a.x));
            rgba[4 * v + 1] = std::uint8_t(std::lround(255.0f * a.y));
            rgba[4 * v + 2] = std::uint8_t(std::lround(255.0f * a.z));
            rgba[4 * v + 3] = 255;
        }
        glTextureSubImage3D(orientation_.id(), 0, at.x, at.y, at.z, 8, 8, 8, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    }
}

void BrickAtlas::finish() {
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
