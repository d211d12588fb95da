#include "gpu/program_helpers.h"

#include "core/environment_count.h"
#include "core/trace.h"
#include "gpu/brick_resolver.h"
#include "gpu/cross_section_texture.h"
#include "gpu/gl_program.h"
#include "gpu/program_cache.h"
#include "gpu/sample_pass.h"

#include <istream>
#include <mutex>
#include <sstream>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace yv {
namespace {

constexpr long kDefaultHelpers = 2; // two helpers took the run's programs from 0.53-0.70 s to 0.34-0.35 s on an H100

std::mutex gMutex;
std::vector<pid_t> gHelpers; ///< started, not yet waited for

/// This process's environment without YV_TRACE (a helper writing the same
/// trace file would overwrite the run's).
std::vector<char*> helperEnvironment() {
    std::vector<char*> env;
    for (char** e = environ; *e; ++e)
        if (std::string_view(*e).rfind("YV_TRACE=", 0) != 0) env.push_back(*e);
    env.push_back(nullptr);
    return env;
}

/// Starts one helper with `requests` on its standard input; -1 where it cannot start.
pid_t startHelper(const std::string& requests, const GlContextOptions& options) {
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) return -1;
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fds[0], 0);
    // What a helper would say is not the run's to print: a failed helper only
    // leaves its programs to the run.
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
    const std::string device = std::to_string(options.device), spread = std::to_string(options.spreadIndex);
    const char* args[] = {"yarnvox", "compile-programs", "--device", device.c_str(), "--spread", spread.c_str(), nullptr};
    std::vector<char*> env = helperEnvironment();
    pid_t pid = -1;
    if (posix_spawn(&pid, "/proc/self/exe", &actions, nullptr, const_cast<char**>(args), env.data()) != 0) pid = -1;
    posix_spawn_file_actions_destroy(&actions);
    ::close(fds[0]);
    // A few hundred bytes: the pipe takes them without waiting on the helper.
    if (pid > 0 && ::write(fds[1], requests.data(), requests.size()) != ssize_t(requests.size())) {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, nullptr, 0);
        pid = -1;
    }
    ::close(fds[1]);
    return pid;
}

} // namespace

std::vector<ComputeProgram> slowestBackendPrograms(bool analyticDisk, bool albedo, Reduce reduce, Overlap overlap,
                                                   bool computeItems) {
    const TexelReads reads = texelReadsFor(TexelReads::Auto);
    std::vector<ComputeProgram> programs = {
        {"brick_resolve.comp", brickResolveDefines(reduce, overlap, albedo, false)},
        {"sample.comp", sampleDefines(analyticDisk, reads, albedo)},
    };
    if (computeItems) programs.push_back({"slice_items.comp", crossSectionDefines(analyticDisk, reads)});
    programs.push_back({"brick_resolve.comp", brickResolveDefines(reduce, overlap, albedo, true)});
    return programs;
}

int startProgramHelpers(const std::vector<ComputeProgram>& programs, const GlContextOptions& options) {
    const long helpers = countFromEnvironment("YV_COMPILE_PROCESSES", 0, 16, "helper processes").value_or(kDefaultHelpers);
    if (helpers == 0 || !programCacheDir()) return 0;
    // Longest first, dealt out in turn.
    std::vector<std::string> requests(static_cast<std::size_t>(helpers));
    std::size_t next = 0;
    for (const ComputeProgram& p : programs) {
        if (computeProgramCached(p.name, p.defines)) continue;
        std::string& line = requests[next++ % requests.size()];
        line += p.name;
        for (const std::string& d : p.defines) line += "\t" + d;
        line += "\n";
    }
    if (next == 0) return 0;
    const TraceSpan span("start the program helpers");
    int started = 0;
    const std::lock_guard lock(gMutex);
    for (const std::string& r : requests) {
        if (r.empty()) continue;
        const pid_t pid = startHelper(r, options);
        if (pid <= 0) continue;
        gHelpers.push_back(pid);
        ++started;
    }
    return started;
}

void waitForProgramHelpers() {
    const std::lock_guard lock(gMutex);
    if (gHelpers.empty()) return;
    const TraceSpan span("wait for the program helpers");
    for (pid_t pid : gHelpers) ::waitpid(pid, nullptr, 0);
    gHelpers.clear();
}

void compileProgramsIntoCache(std::istream& in, const GlContextOptions& options) {
    // A helper outlives no run: it ends with the process that started it.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() == 1) return;
    const GlContext context(options);
    for (std::string line; std::getline(in, line);) {
        std::istringstream fields(line);
        ComputeProgram p;
        std::getline(fields, p.name, '\t');
        for (std::string d; std::getline(fields, d, '\t');) p.defines.push_back(d);
        if (!p.name.empty()) GlProgram::compute(p.name, p.defines).waitLinked(); // stored once linked
    }
}

} // namespace yv
