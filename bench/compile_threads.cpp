// Does the driver compile shader programs side by side when they are given
// to threads of their own, each with a GL context sharing the first one's
// objects? A first run on a machine with no shader cache waits on the
// driver's compiler (issue: at most 0.3 s over the next run). Compiles
// yarnvox's shaders (every one that builds without a variant's #defines),
// each time with a salt #define no cache has seen, on 1 thread (the first
// context, as a run does now) and on K threads with sharing contexts, and
// prints one JSON line a try: seconds to make the sharing contexts and to
// have every program linked.
//
// Two more ways to spread the compile, each handing the linked programs back
// to the first context as program binaries (glGetProgramBinary, then
// glProgramBinary): --separate K, K threads each with a context of its own
// that shares nothing (a driver may lock per share group), and --processes K,
// K copies of this program each compiling its share in its own process
// (a driver may lock per process).
//
//   yv_bench_compile_threads [--threads 1,2,4,8] [--separate 2,4] [--processes 2,4]
//                            [--rounds 3] [--device -1] [--cold K]
//                            [--dump-sources DIR] [--cold-spirv DIR]
//                            [--cold-warm-child W K [--dispatch]]
// Run with __GL_SHADER_DISK_CACHE_PATH pointing at an empty folder.
//
// --cold K: what a first run's process sees. No probe: the context is made,
// then the programs a default GL voxelize compiles (with their #defines, in
// the order the run needs them) are compiled on K threads with unshared
// contexts taking the next program as they finish (K = 0: on the first
// context, every compile started and then every link waited for, as the run
// does), their binaries loaded into the first context. One JSON line; run
// each K in a fresh process with a fresh cache folder.
//
// --cold-processes K: the same programs over this process and K copies of
// itself started first thing (a driver that compiles one program at a time
// in a process may compile side by side in several), each copy's binaries
// loaded here; seconds from the process's start (bound, never dispatched:
// on a cold NVIDIA driver such a binary is finalised again at its first
// dispatch, 0.19 to 0.24 s for a run's programs; bench/results/README.md). --cold-warmers K: the
// copies only compile (into the driver's disk cache, which all processes
// share); once they are done this process compiles their programs too.
//
// --dump-sources DIR writes the text each of those programs is compiled
// from (DIR/<index>.comp, the order of --cold); bench/spirv_compile.sh turns
// them into SPIR-V, and --cold-spirv DIR is --cold 0 with DIR/<index>.spv
// handed to the driver instead (GL_ARB_gl_spirv: glShaderBinary, then
// glSpecializeShader): does a driver given SPIR-V link faster than one given
// GLSL, the compiler's front end already done?
#include "core/atomic_file.h"
#include "core/error.h"
#include "gpu/egl_context.h"
#include "gpu/gl_program.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

using namespace yv;

namespace {

struct Shader {
    std::vector<std::string> files; ///< compute: one; graphics: vertex, fragment
    std::vector<std::string> defines = {};
};

/// A default voxelize's programs (the draped garment's options: the texture
/// cross-section read in quads, mean reduction, no albedo), longest link first.
std::vector<Shader> defaultRunPrograms() {
    const std::vector<std::string> xs = {"CROSS_SECTION_DISK 0", "CROSS_SECTION_GATHER 0", "CROSS_SECTION_QUAD 1"};
    return {{{"brick_resolve.comp"}},         {{"sample.comp"}, xs},          {{"slice_items.comp"}, xs},
            {{"slice_setup.comp"}},           {{"brick_scan.comp"}},          {{"brick_resolve_scan.comp"}},
            {{"buffer_clear.comp"}},          {{"brick_resolve.comp"}, {"COUNT_ONLY 1"}},
            {{"brick_scatter.comp"}},         {{"sample_dispatch.comp"}},     {{"brick_flag.comp"}}};
}

double since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// `s`'s defines and a salt no cache has seen for another salt.
std::vector<std::string> salted(const Shader& s, int salt) {
    std::vector<std::string> defines = s.defines;
    defines.push_back("YV_SALT " + std::to_string(salt));
    return defines;
}

/// Starts `s`'s compile and link with `defines` on the current context.
GlProgram startProgram(const Shader& s, const std::vector<std::string>& defines) {
    return s.files.size() == 1 ? GlProgram::compute(s.files[0], defines)
                               : GlProgram::graphics(s.files[0], s.files[1], defines);
}

GlProgram build(const Shader& s, int salt) {
    GlProgram p = startProgram(s, salted(s, salt));
    p.waitLinked();
    return p;
}

/// A linked program as the driver's binary.
struct Binary {
    GLenum format = 0;
    std::vector<char> bytes;
};

/// Compiles and links `s` (salted) on the current context, returned as a binary.
Binary compileToBinary(const Shader& s, int salt) {
    const std::vector<std::string> defines = salted(s, salt);
    std::vector<GlShader> stages;
    if (s.files.size() == 1) {
        stages.push_back(startShaderStage(GL_COMPUTE_SHADER, s.files[0], defines));
    } else {
        stages.push_back(startShaderStage(GL_VERTEX_SHADER, s.files[0], defines));
        stages.push_back(startShaderStage(GL_FRAGMENT_SHADER, s.files[1], defines));
    }
    const GLuint program = glCreateProgram();
    glProgramParameteri(program, GL_PROGRAM_BINARY_RETRIEVABLE_HINT, GL_TRUE);
    for (const GlShader& st : stages) glAttachShader(program, st.id());
    glLinkProgram(program);
    GLint ok = GL_FALSE, length = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    glGetProgramiv(program, GL_PROGRAM_BINARY_LENGTH, &length);
    if (!ok || length <= 0) throw Error("link or binary of " + s.files[0] + " failed");
    Binary b;
    b.bytes.resize(std::size_t(length));
    glGetProgramBinary(program, length, nullptr, &b.format, b.bytes.data());
    glDeleteProgram(program);
    return b;
}

GLuint loadBinary(const Binary& b) {
    const GLuint program = glCreateProgram();
    glProgramBinary(program, b.format, b.bytes.data(), GLsizei(b.bytes.size()));
    GLint ok = GL_FALSE;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) throw Error("glProgramBinary refused a binary");
    return program;
}

void writeAll(int fd, const void* data, std::size_t n) {
    const char* p = static_cast<const char*>(data);
    while (n > 0) {
        const ssize_t w = ::write(fd, p, n);
        if (w <= 0) throw Error("write to the parent failed");
        p += w;
        n -= std::size_t(w);
    }
}

void readAll(int fd, void* data, std::size_t n) {
    char* p = static_cast<char*>(data);
    while (n > 0) {
        const ssize_t r = ::read(fd, p, n);
        if (r <= 0) throw Error("read from a child failed");
        p += r;
        n -= std::size_t(r);
    }
}

/// A copy of this program with `args` (after argv[0]), its standard output a
/// pipe: the pid and the pipe's read end.
std::pair<pid_t, int> spawnSelf(const char* self, const std::vector<std::string>& args) {
    int fds[2];
    if (::pipe(fds) != 0) throw Error("pipe failed");
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fds[1], 1);
    posix_spawn_file_actions_addclose(&actions, fds[0]);
    std::vector<char*> argv = {const_cast<char*>(self)};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    pid_t pid = 0;
    if (posix_spawn(&pid, "/proc/self/exe", &actions, nullptr, argv.data(), environ) != 0)
        throw Error("posix_spawn failed");
    posix_spawn_file_actions_destroy(&actions);
    ::close(fds[1]);
    return {pid, fds[0]};
}

/// Writes binary `index` for the parent: a header (index, format, length), then the bytes.
void writeBinary(int fd, std::uint32_t index, const Binary& b) {
    const std::uint32_t header[3] = {index, b.format, std::uint32_t(b.bytes.size())};
    writeAll(fd, header, sizeof header);
    writeAll(fd, b.bytes.data(), b.bytes.size());
}

/// One binary a child wrote (writeBinary).
std::pair<std::uint32_t, Binary> readBinary(int fd) {
    std::uint32_t header[3];
    readAll(fd, header, sizeof header);
    Binary b;
    b.format = header[1];
    b.bytes.resize(header[2]);
    readAll(fd, b.bytes.data(), b.bytes.size());
    return {header[0], std::move(b)};
}

/// The end of a --cold or --cold-spirv line: each program's link in ms (a
/// program built with a variant's defines marked *), then the renderer.
void printLinkTimes(const std::vector<Shader>& shaders, const std::vector<double>& linkMs, const GlContext& gl) {
    for (std::size_t i = 0; i < shaders.size(); ++i)
        std::printf("%s\"%s%s\": %.1f", i ? ", " : "", shaders[i].files[0].c_str(),
                    shaders[i].defines.empty() ? "" : "*", linkMs[i]);
    std::printf("}, \"renderer\": \"%s\"}\n", gl.info().renderer.c_str());
}

/// --cold K (see the top of the file).
int coldCompile(GlContext& gl, int contexts, int device, double contextSeconds) {
    const std::vector<Shader> shaders = defaultRunPrograms();
    const auto start = std::chrono::steady_clock::now();
    std::vector<double> linkMs(shaders.size(), 0.0);
    double loadSeconds = 0.0; // the binaries into the first context
    if (contexts == 0) {
        std::vector<GlProgram> programs;
        // Timed at the start of each: NVIDIA's driver compiles inside glLinkProgram.
        for (std::size_t i = 0; i < shaders.size(); ++i) {
            const Shader& s = shaders[i];
            const auto linkStart = std::chrono::steady_clock::now();
            programs.push_back(startProgram(s, s.defines));
            linkMs[i] = 1e3 * since(linkStart);
        }
        for (const GlProgram& p : programs) p.waitLinked();
        for (const GlProgram& p : programs) p.use();
        glFinish();
    } else {
        std::vector<Binary> binaries(shaders.size());
        std::atomic<std::size_t> next{0};
        std::vector<std::thread> workers;
        for (int t = 0; t < contexts; ++t)
            workers.emplace_back([&] {
                GlContext own(GlContextOptions{device, false});
                for (std::size_t i; (i = next.fetch_add(1)) < shaders.size();) {
                    const auto linkStart = std::chrono::steady_clock::now();
                    binaries[i] = compileToBinary(shaders[i], 0);
                    linkMs[i] = 1e3 * since(linkStart);
                }
            });
        for (std::thread& w : workers) w.join();
        const auto loadStart = std::chrono::steady_clock::now();
        gl.makeCurrent();
        for (const Binary& b : binaries) glUseProgram(loadBinary(b));
        glFinish();
        loadSeconds = since(loadStart);
    }
    std::printf("{\"cold_contexts\": %d, \"first_context_s\": %.3f, \"linked_s\": %.3f, \"load_s\": %.3f, "
                "\"link_ms\": {",
                contexts, contextSeconds, since(start), loadSeconds);
    printLinkTimes(shaders, linkMs, gl);
    return 0;
}

/// --dump-sources DIR (see the top of the file).
int dumpSources(const std::string& dir) {
    const std::vector<Shader> shaders = defaultRunPrograms();
    for (std::size_t i = 0; i < shaders.size(); ++i) {
        const std::string path = dir + "/" + std::to_string(i) + ".comp";
        const std::string text = composedShaderText(shaders[i].files[0], shaders[i].defines);
        writeFileAtomically(path, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
    }
    return 0;
}

/// --cold-spirv DIR (see the top of the file): the programs of --cold 0 from
/// DIR/<index>.spv, each specialised and linked in turn.
int coldSpirv(GlContext& gl, const std::string& dir, double contextSeconds) {
    if (!epoxy_has_gl_extension("GL_ARB_gl_spirv")) throw Error("the driver lacks GL_ARB_gl_spirv");
    const std::vector<Shader> shaders = defaultRunPrograms();
    std::vector<std::vector<std::uint8_t>> modules;
    for (std::size_t i = 0; i < shaders.size(); ++i) {
        const std::string path = dir + "/" + std::to_string(i) + ".spv";
        std::optional<std::vector<std::uint8_t>> bytes = readWholeFile(path);
        if (!bytes) throw Error(path + ": cannot be read");
        modules.push_back(std::move(*bytes));
    }
    const auto start = std::chrono::steady_clock::now();
    std::vector<double> linkMs(shaders.size(), 0.0);
    std::vector<GLuint> programs;
    for (std::size_t i = 0; i < shaders.size(); ++i) {
        const auto linkStart = std::chrono::steady_clock::now();
        const GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
        glShaderBinary(1, &shader, GL_SHADER_BINARY_FORMAT_SPIR_V_ARB, modules[i].data(), GLsizei(modules[i].size()));
        glSpecializeShaderARB(shader, "main", 0, nullptr, nullptr);
        GLint ok = GL_FALSE;
        glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
        if (!ok) throw Error(std::to_string(i) + ".spv (" + shaders[i].files[0] + "): specialisation failed");
        const GLuint program = glCreateProgram();
        glAttachShader(program, shader);
        glLinkProgram(program);
        glGetProgramiv(program, GL_LINK_STATUS, &ok);
        if (!ok) throw Error(std::to_string(i) + ".spv (" + shaders[i].files[0] + "): link failed");
        glDeleteShader(shader);
        programs.push_back(program);
        linkMs[i] = 1e3 * since(linkStart);
    }
    for (GLuint p : programs) glUseProgram(p);
    glFinish();
    std::printf("{\"cold_spirv\": true, \"first_context_s\": %.3f, \"linked_s\": %.3f, \"link_ms\": {",
                contextSeconds, since(start));
    printLinkTimes(shaders, linkMs, gl);
    return 0;
}

/// --cold-processes K: which of defaultRunPrograms() worker W of K + 1
/// compiles (worker 0 is the first process): longest first, each to the
/// worker with the least so far, by each program's link time on an H100
/// with no shader cache (ms, defaultRunPrograms' order).
std::vector<std::size_t> coldShare(int worker, int workers) {
    const double linkMs[] = {136, 154, 56, 40, 27, 25, 3, 19, 12, 3, 4};
    std::vector<double> load(std::size_t(workers), 0.0);
    std::vector<std::size_t> order(std::size(linkMs)), share;
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return linkMs[a] > linkMs[b]; });
    for (std::size_t i : order) {
        const std::size_t w = std::size_t(std::min_element(load.begin(), load.end()) - load.begin());
        load[w] += linkMs[i];
        if (int(w) == worker) share.push_back(i);
    }
    return share;
}

/// One work group of `program` with a zeroed buffer on every storage and
/// atomic-counter binding a run's programs use, a 1x1 texture on the
/// cross-section's unit and every uniform 0 (so its loops end at once): what
/// a driver that finishes a program at its first dispatch needs to see.
void dispatchOnce(const GlProgram& program) {
    static GLuint zeros = 0, texel = 0;
    if (!zeros) {
        const std::vector<char> bytes(1 << 20, 0);
        glCreateBuffers(1, &zeros);
        glNamedBufferStorage(zeros, GLsizeiptr(bytes.size()), bytes.data(), 0);
        glCreateTextures(GL_TEXTURE_2D, 1, &texel);
        glTextureStorage2D(texel, 1, GL_R8UI, 1, 1);
        glTextureParameteri(texel, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(texel, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
    for (GLuint b = 0; b < 8; ++b) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, b, zeros);
    glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, zeros);
    glBindTextureUnit(0, texel);
    program.use();
    glDispatchCompute(1, 1, 1);
    glFinish();
}

/// --cold-child W K: compiles worker W's share of K + 1, binaries to stdout;
/// with `warmOnly` (--cold-warm-child) it only compiles them (the driver's
/// disk cache keeps them), and with --dispatch runs each once (dispatchOnce).
/// W = 0 is the first process's share, so K + 1 copies started from a shell
/// cover every program.
int coldChild(int worker, int workers, int device, bool warmOnly, bool dispatch) {
    GlContext own(GlContextOptions{device, false});
    const std::vector<Shader> shaders = defaultRunPrograms();
    for (std::size_t i : coldShare(worker, workers + 1)) {
        if (warmOnly) {
            const GlProgram program = startProgram(shaders[i], shaders[i].defines);
            program.waitLinked();
            if (dispatch) dispatchOnce(program);
            continue;
        }
        writeBinary(1, std::uint32_t(i), compileToBinary(shaders[i], 0));
    }
    return 0;
}

/// --cold-processes K: K copies of this program started first thing, each
/// compiling its share while this process makes its context and compiles
/// its own; their binaries loaded here. Seconds from the process's start.
int coldProcesses(int children, int device, const char* self, std::chrono::steady_clock::time_point processStart,
                  bool warmOnly) {
    std::vector<pid_t> pids;
    std::vector<int> pipes;
    for (int c = 1; c <= children; ++c) {
        const auto [pid, out] = spawnSelf(self, {warmOnly ? "--cold-warm-child" : "--cold-child", std::to_string(c),
                                                 std::to_string(children), "--device", std::to_string(device)});
        pids.push_back(pid);
        pipes.push_back(out);
    }
    GlContext gl(GlContextOptions{device, false});
    const double contextSeconds = since(processStart);
    const std::vector<Shader> shaders = defaultRunPrograms();
    std::vector<GlProgram> own;
    for (std::size_t i : coldShare(0, children + 1)) own.push_back(startProgram(shaders[i], shaders[i].defines));
    for (const GlProgram& p : own) p.use();
    const double ownSeconds = since(processStart);
    std::size_t loaded = 0;
    if (warmOnly) {
        // The copies compiled into the driver's disk cache: once they are
        // gone, this process's compiles of their programs are the cache's hits.
        for (int c = 0; c < children; ++c) {
            ::close(pipes[std::size_t(c)]);
            int status = 0;
            ::waitpid(pids[std::size_t(c)], &status, 0);
        }
        const double waited = since(processStart);
        for (int c = 0; c < children; ++c)
            for (std::size_t i : coldShare(c + 1, children + 1)) {
                startProgram(shaders[i], shaders[i].defines).use();
                ++loaded;
            }
        glFinish();
        std::printf("{\"cold_warmers\": %d, \"context_s\": %.3f, \"own_share_s\": %.3f, \"warmers_done_s\": %.3f, "
                    "\"compiled_after\": %zu, \"all_linked_s\": %.3f}\n",
                    children, contextSeconds, ownSeconds, waited, loaded, since(processStart));
        return 0;
    }
    for (int c = 0; c < children; ++c) {
        for (std::size_t n = coldShare(c + 1, children + 1).size(); n > 0; --n) {
            glUseProgram(loadBinary(readBinary(pipes[std::size_t(c)]).second));
            ++loaded;
        }
        ::close(pipes[std::size_t(c)]);
        int status = 0;
        ::waitpid(pids[std::size_t(c)], &status, 0);
    }
    glFinish();
    std::printf("{\"cold_processes\": %d, \"context_s\": %.3f, \"own_share_s\": %.3f, \"loaded\": %zu, "
                "\"all_linked_s\": %.3f}\n",
                children, contextSeconds, ownSeconds, loaded, since(processStart));
    return 0;
}

} // namespace

int main(int argc, char** argv) try {
    std::vector<int> threadCounts = {1, 2, 4, 8}, separateCounts, processCounts;
    int rounds = 3, device = -1;
    int childIndex = -1, childCount = 0, childSalt = 0, cold = -1, coldChildren = -1, coldWorker = -1;
    bool warmOnly = false, dispatch = false;
    std::string dumpDir, spirvDir;
    for (int i = 1; i < argc; ++i) {
        const std::string k = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw Error(k + ": missing value");
            return argv[++i];
        };
        if (k == "--threads") {
            threadCounts.clear();
            std::stringstream ss(value());
            for (std::string item; std::getline(ss, item, ',');) threadCounts.push_back(std::stoi(item));
        } else if (k == "--separate" || k == "--processes") {
            std::vector<int>& counts = k == "--separate" ? separateCounts : processCounts;
            std::stringstream ss(value());
            for (std::string item; std::getline(ss, item, ',');) counts.push_back(std::stoi(item));
        } else if (k == "--child") { // INDEX COUNT SALT: this process compiles its share, binaries to stdout
            childIndex = std::stoi(value());
            childCount = std::stoi(value());
            childSalt = std::stoi(value());
        } else if (k == "--cold") cold = std::stoi(value());
        else if (k == "--cold-processes" || k == "--cold-warmers") {
            coldChildren = std::stoi(value());
            warmOnly = k == "--cold-warmers";
        } else if (k == "--cold-child" || k == "--cold-warm-child") { // W K
            warmOnly = k == "--cold-warm-child";
            coldWorker = std::stoi(value());
            coldChildren = std::stoi(value());
        }
        else if (k == "--dump-sources") dumpDir = value();
        else if (k == "--dispatch") dispatch = true;
        else if (k == "--cold-spirv") spirvDir = value();
        else if (k == "--rounds") rounds = std::stoi(value());
        else if (k == "--device") device = std::stoi(value());
        else throw Error("unknown option " + k);
    }
    const auto processStart = std::chrono::steady_clock::now();
    if (!dumpDir.empty()) return dumpSources(dumpDir);
    if (coldWorker >= 0) return coldChild(coldWorker, coldChildren, device, warmOnly, dispatch);
    if (coldChildren >= 0) return coldProcesses(coldChildren, device, argv[0], processStart, warmOnly);
    GlContext gl(GlContextOptions{device, false});
    if (cold >= 0) return coldCompile(gl, cold, device, since(processStart));
    if (!spirvDir.empty()) return coldSpirv(gl, spirvDir, since(processStart));
    const std::vector<Shader> candidates = {
        {{"brick_flag.comp"}}, {{"buffer_clear.comp"}}, {{"brick_scan.comp"}}, {{"brick_scatter.comp"}},
        {{"brick_max_orient.comp"}}, {{"slice_setup.comp"}}, {{"slice_runs.comp"}}, {{"sample.comp"}},
        {{"sample_dispatch.comp"}}, {{"radix_histogram.comp"}}, {{"radix_scan.comp"}}, {{"radix_scatter.comp"}},
        {{"brick_resolve.comp"}}, {{"brick_resolve_scan.comp"}}, {{"slice.vert", "append.frag"}},
        {{"inspect_fullscreen.vert", "inspect_raycast.frag"}}, {{"inspect_proxy.vert", "inspect_proxy.frag"}},
        {{"inspect_slices.vert", "inspect_slices.frag"}}, {{"inspect_slices_keys.comp"}}};
    if (childIndex >= 0) {
        // The probe's list is every candidate but those that need a variant's defines,
        // which the parent passes over; the child skips what does not build.
        for (std::size_t i = std::size_t(childIndex); i < candidates.size(); i += std::size_t(childCount)) {
            Binary b;
            try {
                b = compileToBinary(candidates[i], childSalt);
            } catch (const Error&) {
            }
            writeBinary(1, std::uint32_t(i), b);
        }
        return 0;
    }
    // Those that build without a variant's defines (salt 0: a compile of its own).
    std::vector<Shader> shaders;
    const auto probeStart = std::chrono::steady_clock::now();
    for (const Shader& s : candidates) {
        try {
            build(s, 0);
            shaders.push_back(s);
        } catch (const Error&) {
        }
    }
    std::printf("{\"probe_s\": %.3f, \"programs\": %zu, \"renderer\": \"%s\"}\n", since(probeStart), shaders.size(),
                gl.info().renderer.c_str());
    int salt = 1;
    for (int round = 0; round < rounds; ++round) {
        for (int threads : separateCounts) {
            ++salt;
            const auto start = std::chrono::steady_clock::now();
            std::vector<Binary> binaries(shaders.size());
            std::vector<std::thread> workers;
            for (int t = 0; t < threads; ++t) {
                workers.emplace_back([&, t] {
                    GlContext own(GlContextOptions{device, false});
                    for (std::size_t i = std::size_t(t); i < shaders.size(); i += std::size_t(threads))
                        binaries[i] = compileToBinary(shaders[i], salt);
                });
            }
            for (std::thread& w : workers) w.join();
            gl.makeCurrent();
            for (const Binary& b : binaries) glDeleteProgram(loadBinary(b));
            glFinish();
            std::printf("{\"round\": %d, \"separate_contexts\": %d, \"linked_s\": %.3f}\n", round, threads,
                        since(start));
            std::fflush(stdout);
        }
        for (int processes : processCounts) {
            ++salt;
            const auto start = std::chrono::steady_clock::now();
            std::vector<Binary> binaries(candidates.size());
            std::vector<pid_t> children;
            std::vector<int> pipes;
            for (int c = 0; c < processes; ++c) {
                const auto [pid, out] = spawnSelf(argv[0], {"--child", std::to_string(c), std::to_string(processes),
                                                            std::to_string(salt), "--device", std::to_string(device)});
                children.push_back(pid);
                pipes.push_back(out);
            }
            for (int c = 0; c < processes; ++c) {
                for (std::size_t i = std::size_t(c); i < candidates.size(); i += std::size_t(processes)) {
                    auto [index, binary] = readBinary(pipes[std::size_t(c)]);
                    binaries[index] = std::move(binary);
                }
                ::close(pipes[std::size_t(c)]);
                int status = 0;
                ::waitpid(children[std::size_t(c)], &status, 0);
            }
            const double received = since(start);
            gl.makeCurrent();
            std::size_t loaded = 0;
            for (const Binary& b : binaries)
                if (!b.bytes.empty()) {
                    glDeleteProgram(loadBinary(b));
                    ++loaded;
                }
            glFinish();
            std::printf("{\"round\": %d, \"processes\": %d, \"programs\": %zu, \"received_s\": %.3f, "
                        "\"linked_s\": %.3f}\n",
                        round, processes, loaded, received, since(start));
            std::fflush(stdout);
        }
        for (int threads : threadCounts) {
            ++salt;
            const auto start = std::chrono::steady_clock::now();
            std::vector<GlProgram> programs(shaders.size());
            double contextSeconds = 0.0;
            if (threads <= 1) {
                // As a run does: every compile started, then every link waited for.
                for (std::size_t i = 0; i < shaders.size(); ++i)
                    programs[i] = startProgram(shaders[i], salted(shaders[i], salt));
                for (const GlProgram& p : programs) p.waitLinked();
            } else {
                std::vector<std::thread> workers;
                std::vector<double> made(std::size_t(threads), 0.0);
                for (int t = 0; t < threads; ++t) {
                    workers.emplace_back([&, t] {
                        const auto c = std::chrono::steady_clock::now();
                        std::unique_ptr<GlContext> own = gl.makeSharing();
                        made[std::size_t(t)] = since(c);
                        for (std::size_t i = std::size_t(t); i < shaders.size(); i += std::size_t(threads))
                            programs[i] = build(shaders[i], salt);
                        glFinish();
                        // The programs outlive this context: their names belong to the shared group.
                        for (std::size_t i = std::size_t(t); i < shaders.size(); i += std::size_t(threads))
                            programs[i].waitLinked();
                        own->releaseCurrent();
                    });
                }
                for (std::thread& w : workers) w.join();
                for (double m : made) contextSeconds = std::max(contextSeconds, m);
            }
            gl.makeCurrent();
            // Each program used once on the first context, as a run would.
            for (const GlProgram& p : programs) p.use();
            glFinish();
            std::printf("{\"round\": %d, \"threads\": %d, \"contexts_s\": %.3f, \"linked_s\": %.3f}\n", round, threads,
                        contextSeconds, since(start));
            std::fflush(stdout);
        }
    }
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "yv_bench_compile_threads: %s\n", e.what());
    return 1;
}
