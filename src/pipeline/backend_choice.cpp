#include "pipeline/backend_choice.h"

#include "core/trace.h"
#include "gpu/gl_voxelizer.h"

#include <chrono>
#include <cstdlib>

namespace yv {

const char* backendName(Backend b) { return b == Backend::Cpu ? "cpu" : "gl"; }

GlStart startGl(const VoxelizeJob& job, int spreadIndex) {
    GlStart gl;
    if (job.backend == BackendRequest::Cpu) return gl;
    if (job.glContext) {
        gl.kept = job.glContext.get();
        gl.kept->makeCurrent();
        return gl; // its programs were compiled by the runs before
    }
    const auto start = std::chrono::steady_clock::now();
    try {
        const TraceSpan span("make the GL context");
        gl.context = std::make_unique<GlContext>(
            GlContextOptions{job.device, std::getenv("YV_GL_DEBUG") != nullptr, spreadIndex});
    } catch (...) {
        gl.error = std::current_exception();
    }
    gl.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (gl.context && gl.context->info().hardware()) compileInvariantPrograms();
    return gl;
}

Backend chooseBackend(const VoxelizeJob& job, GlStart& gl) {
    const bool needsGl = job.method == VoxelizeMethod::Dense || job.backend == BackendRequest::Gl;
    if (needsGl && gl.error) std::rethrow_exception(gl.error); // no GL 4.5 context: its one-line error
    if (job.method == VoxelizeMethod::Dense) return Backend::GlDense;
    if (job.backend == BackendRequest::Gl) return Backend::Gl;
    if (job.backend == BackendRequest::Auto && gl.current() && gl.current()->info().hardware()) return Backend::Gl;
    gl.context.reset();
    gl.kept = nullptr;
    return Backend::Cpu;
}

} // namespace yv
