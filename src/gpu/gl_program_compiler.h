// Where the GL backend's passes get their programs. NVIDIA's driver compiles
// a program inside the thread's link call, one program at a time: a first
// run with no shader cache spent half a second there before its first pass,
// with the GL thread waiting (bench/results/README.md). A compiler started
// with the run's context compiles the programs the run will use on a thread
// of its own, through a context that shares the run's objects, in the order
// the passes first use them, while the GL thread uploads the slices, plans
// and runs the passes whose programs are in: each pass waits only for its
// own programs, at their first use.
#pragma once

#include "gpu/egl_context.h"
#include "gpu/gl_program.h"

#include <atomic>
#include <cstddef>
#include <future>
#include <string>
#include <thread>
#include <vector>

namespace yv {

/// A compute program by its shader file and #defines (GlProgram::compute's arguments).
struct ProgramRequest {
    std::string name;
    std::vector<std::string> defines;
    bool operator==(const ProgramRequest&) const = default;
};

class GlProgramCompiler {
  public:
    /// Compiles nothing ahead: take() compiles on the calling thread.
    GlProgramCompiler() = default;
    /// Starts compiling `requests` in their order on `threads` threads of
    /// its own, each through a context sharing `context`'s objects (made
    /// there; where none can be made, take() compiles on the calling
    /// thread, as without a compiler), each taking the next request as it
    /// finishes one. `context` must outlive the compiler.
    GlProgramCompiler(const GlContext& context, std::vector<ProgramRequest> requests,
                      int threads = kDefaultThreads);
    /// Stops after the program being compiled and waits for the thread;
    /// programs not taken are deleted (a context of the share group must be
    /// current, as for any GlProgram).
    ~GlProgramCompiler();
    GlProgramCompiler(const GlProgramCompiler&) = delete;
    GlProgramCompiler& operator=(const GlProgramCompiler&) = delete;

    /// The program for `name` and `defines`: the one requested (linked on
    /// the thread; its first use waits for it, and a compile error is
    /// thrown there), else one compiled now on the calling thread, which
    /// must have the context current. Each request is taken once.
    GlProgram take(const std::string& name, const std::vector<std::string>& defines = {});

    /// Requests not taken yet.
    std::size_t waiting() const;

    /// Compile threads a run starts (YV_COMPILE_THREADS sets it, 1 to 16).
    static constexpr int kDefaultThreads = 2;
    static int threadsForRuns();

  private:
    void compileOn(const GlContext& context);

    std::vector<ProgramRequest> requests_;
    std::vector<std::promise<GlProgram>> promises_; ///< set on the thread, one a request
    std::vector<std::future<GlProgram>> futures_;   ///< handed out by take()
    std::vector<bool> taken_;
    int threadCount_ = 0;
    std::atomic<std::size_t> next_{0};   ///< the next request a thread takes
    std::atomic<int> withoutContext_{0}; ///< threads that could not make their context
    std::atomic<bool> stop_{false};
    std::vector<std::thread> threads_;
};

} // namespace yv
