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
    /// Starts compiling `requests` in their order on a thread of its own,
    /// through a context sharing `context`'s objects (made there; where it
    /// cannot be made, take() compiles on the calling thread, as without a
    /// compiler). `context` must outlive the compiler.
    GlProgramCompiler(const GlContext& context, std::vector<ProgramRequest> requests);
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

  private:
    void compileAll(const GlContext& context);

    std::vector<ProgramRequest> requests_;
    std::vector<std::promise<GlProgram>> promises_; ///< set on the thread, one a request
    std::vector<std::future<GlProgram>> futures_;   ///< handed out by take()
    std::vector<bool> taken_;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

} // namespace yv
