#include "gpu/slice_placer.h"

#include "core/error.h"
#include "gpu/gl_bindings.h"
#include "gpu/gpu_layout.h"

#include <algorithm>

namespace yv {

namespace {
constexpr std::uint64_t kGroupSize = 256; // slice_setup.comp's and slice_runs.comp's local_size_x
}

SlicePlacer::SlicePlacer(int runSlices, const std::vector<std::string>& runDefines)
    : program_(GlProgram::compute("slice_setup.comp")), runSlices_(runSlices) {
    if (runSlices_ > 1) {
        runs_ = GlProgram::compute("slice_runs.comp", runDefines);
        const GLuint start[4] = {0, 1, 0, 0};
        commandStart_.upload(start, sizeof start, nullptr);
    }
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
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kSegmentsBinding, draw.segments);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kDrawListBinding, draw.drawList);
    records.bindStorage(kSlicesBinding);
    const std::uint64_t groups = (draw.instances + kGroupSize - 1) / kGroupSize;
    glDispatchCompute(static_cast<GLuint>(std::min<std::uint64_t>(groups, maxGroups_)), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

void SlicePlacer::joinRuns(std::uint64_t instances, int supersample, float spread, const GlBuffer& records,
                           GlBuffer& runs, GlBuffer& command, std::uint64_t* gpuBytes) const {
    YV_CHECK(runSlices_ > 1);
    runs.reserve(std::max<std::uint64_t>(instances, 1) * sizeof(GpuSliceRun), gpuBytes);
    command.reserve(16, gpuBytes);
    // No runs yet; one instance of each, from the first. Copied on the GPU:
    // writing the command from the host would wait for the pass before.
    glCopyNamedBufferSubData(commandStart_.id(), command.id(), 0, 0, 16);
    if (instances == 0) return;
    runs_.use();
    glUniform1ui(runs_.uniform("uInstances"), static_cast<GLuint>(instances));
    glUniform1i(runs_.uniform("uSupersample"), supersample);
    glUniform1f(runs_.uniform("uRunSpread"), spread);
    records.bindStorage(kSlicesBinding);
    runs.bindStorage(kRunsBinding);
    command.bindStorage(kRunDrawBinding);
    const std::uint64_t blocks = (instances + runSlices_ - 1) / runSlices_;
    const std::uint64_t groups = (blocks + kGroupSize - 1) / kGroupSize;
    glDispatchCompute(static_cast<GLuint>(std::min<std::uint64_t>(groups, maxGroups_)), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
}

} // namespace yv
