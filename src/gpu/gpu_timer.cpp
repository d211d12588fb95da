#include "gpu/gpu_timer.h"

namespace yv {

void GpuTimer::begin() {
    if (useQueries_) {
        GLuint query = 0;
        glGenQueries(1, &query);
        queries_.emplace_back(query);
        glBeginQuery(GL_TIME_ELAPSED, query);
        return;
    }
    glFinish();
    start_ = std::chrono::steady_clock::now();
}

void GpuTimer::end() {
    if (useQueries_) {
        glEndQuery(GL_TIME_ELAPSED);
        return;
    }
    glFinish();
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

double GpuTimer::seconds() {
    for (const GlQuery& query : queries_) {
        GLuint64 ns = 0;
        glGetQueryObjectui64v(query.id(), GL_QUERY_RESULT, &ns);
        seconds_ += double(ns) * 1e-9;
    }
    queries_.clear();
    return seconds_;
}

} // namespace yv
