#include "gpu/slice_placer.h"

#include "core/error.h"
#include "gpu/gpu_layout.h"

#include <algorithm>

namespace yv {

namespace {
constexpr std::uint64_t kGroupSize = 256; // slice_setup.comp's local_size_x
}

SlicePlacer::SlicePlacer(const std::optional<std::vector<std::string>>& spriteDefines)
    : program_(GlProgram::compute("slice_setup.comp")) {
    if (spriteDefines) {
        std::vector<std::string> defines = *spriteDefines;
        defines.push_back("SLICE_SPRITES 1");
        spriteProgram_.emplace(GlProgram::compute("slice_setup.comp", defines));
    }
    GLint groups = 0;
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &groups);
    maxGroups_ = static_cast<GLuint>(std::clamp(groups, 1, 65535));
}

void SlicePlacer::place(const SliceDraw& draw, GlBuffer& records, std::uint64_t* gpuBytes,
                        const SpriteRegion* sprites) const {
    YV_CHECK(!sprites || spriteProgram_);
    records.reserve(std::max<std::uint64_t>(draw.instances, 1) * sizeof(GpuSliceRecord), gpuBytes);
    if (sprites) sprites->sprites->reserve(std::max<std::uint64_t>(draw.instances, 1) * sizeof(GpuSpriteRecord), gpuBytes);
    if (draw.instances == 0) return;
    const GlProgram& program = sprites ? *spriteProgram_ : program_;
    program.use();
    if (sprites) {
        glUniform1f(program.uniform("uRadius"), sprites->radius);
        glUniform1f(program.uniform("uSupport"), sprites->support);
        glUniform1i(program.uniform("uSupersample"), sprites->supersample);
        glUniform3i(program.uniform("uRegionMin"), sprites->regionMin.x, sprites->regionMin.y, sprites->regionMin.z);
        glUniform3i(program.uniform("uRegionBricks"), sprites->regionBricks.x, sprites->regionBricks.y, sprites->regionBricks.z);
        glUniform2f(program.uniform("uViewport"), float(sprites->viewport), float(sprites->viewport));
        glUniform1i(program.uniform("uMargin"), sprites->margin);
        sprites->sprites->bindStorage(6);
    }
    glUniform1i(program.uniform("uDrawCount"), draw.drawCount);
    glUniform1ui(program.uniform("uUniformSlices"), draw.uniformSlices);
    glUniform1ui(program.uniform("uInstances"), static_cast<GLuint>(draw.instances));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, draw.segments);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, draw.drawList);
    records.bindStorage(5);
    const std::uint64_t groups = (draw.instances + kGroupSize - 1) / kGroupSize;
    glDispatchCompute(static_cast<GLuint>(std::min<std::uint64_t>(groups, maxGroups_)), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

} // namespace yv
