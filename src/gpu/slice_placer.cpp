#include "gpu/slice_placer.h"

#include "gpu/gpu_layout.h"

#include <algorithm>

namespace yv {

namespace {
constexpr std::uint64_t kGroupSize = 256; // slice_setup.comp's local_size_x
}

SlicePlacer::SlicePlacer() : program_(GlProgram::compute("slice_setup.comp")) {
    GLint groups = 0;
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &groups);
    maxGroups_ = static_cast<GLuint>(std::clamp(groups, 1, 65535));
}

void SlicePlacer::place(const SliceDraw& draw, GlBuffer& records, std::uint64_t* gpuBytes) const {
    records.reserve(std::max<std::uint64_t>(draw.instances, 1) * sizeof(GpuSliceRecord), gpuBytes);
    if (draw.instances == 0) return;
    program_.use();
    glUniform1i(program_.uniform("uDrawCount"), draw.drawCount);
    glUniform1ui(program_.uniform("uUniformSlices"), draw.uniformSlices);
    glUniform1ui(program_.uniform("uInstances"), static_cast<GLuint>(draw.instances));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, draw.segments);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, draw.drawList);
    records.bindStorage(5);
    const std::uint64_t groups = (draw.instances + kGroupSize - 1) / kGroupSize;
    glDispatchCompute(static_cast<GLuint>(std::min<std::uint64_t>(groups, maxGroups_)), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

} // namespace yv
