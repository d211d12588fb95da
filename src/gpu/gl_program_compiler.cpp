#include "gpu/gl_program_compiler.h"

#include "core/environment_count.h"
#include "core/error.h"
#include "core/trace.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <memory>
#include <utility>

namespace yv {

GlProgramCompiler::GlProgramCompiler(const GlContext& context, std::vector<ProgramRequest> requests, int threads)
    : requests_(std::move(requests)), promises_(requests_.size()), taken_(requests_.size(), false) {
    futures_.reserve(promises_.size());
    for (std::promise<GlProgram>& p : promises_) futures_.push_back(p.get_future());
    threadCount_ = std::clamp(threads, 1, 16);
    for (int t = 0; t < threadCount_; ++t) threads_.emplace_back([this, &context] { compileOn(context); });
}

GlProgramCompiler::~GlProgramCompiler() {
    stop_ = true;
    for (std::thread& t : threads_) t.join();
}

int GlProgramCompiler::threadsForRuns() {
    return int(countFromEnvironment("YV_COMPILE_THREADS", 1, 16, "compile threads").value_or(kDefaultThreads));
}

void GlProgramCompiler::compileOn(const GlContext& context) {
    std::unique_ptr<GlContext> sharing;
    try {
        const TraceSpan span("make the compile thread's GL context");
        sharing = context.makeSharing();
    } catch (const Error&) {
        // The last thread without a context leaves each program to be
        // compiled where it is taken, as without a compiler (an empty
        // program says so); the others' threads take the requests.
        if (++withoutContext_ == threadCount_)
            for (std::size_t i = next_.exchange(requests_.size()); i < requests_.size(); ++i)
                promises_[i].set_value(GlProgram{});
        return;
    }
    for (std::size_t i = next_++; i < requests_.size(); i = next_++) {
        if (stop_) {
            promises_[i].set_value(GlProgram{});
            continue;
        }
        try {
            GlProgram program = GlProgram::compute(requests_[i].name, requests_[i].defines);
            program.waitLinked();
            // Another context sees the linked program once the link has
            // completed here (GL 4.5 core, 5.3: changes to shared objects).
            glFinish();
            promises_[i].set_value(std::move(program));
        } catch (...) {
            promises_[i].set_exception(std::current_exception()); // thrown at the program's first use
        }
    }
    sharing->releaseCurrent();
}

GlProgram GlProgramCompiler::take(const std::string& name, const std::vector<std::string>& defines) {
    const ProgramRequest request{name, defines};
    for (std::size_t i = 0; i < requests_.size(); ++i) {
        if (taken_[i] || !(requests_[i] == request)) continue;
        taken_[i] = true;
        return GlProgram::linkedElsewhere(
            std::move(futures_[i]), [request] { return GlProgram::compute(request.name, request.defines); }, name);
    }
    return GlProgram::compute(name, defines);
}

std::size_t GlProgramCompiler::waiting() const {
    return static_cast<std::size_t>(std::count(taken_.begin(), taken_.end(), false));
}

} // namespace yv
