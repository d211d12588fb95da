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
//   yv_bench_compile_threads [--threads 1,2,4,8] [--rounds 3] [--device -1]
// Run with __GL_SHADER_DISK_CACHE_PATH pointing at an empty folder.
#include "core/error.h"
#include "gpu/egl_context.h"
#include "gpu/gl_program.h"

#include <epoxy/gl.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

using namespace yv;

namespace {

struct Shader {
    std::vector<std::string> files; ///< compute: one; graphics: vertex, fragment
};

double since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

GlProgram build(const Shader& s, int salt) {
    const std::vector<std::string> defines = {"YV_SALT " + std::to_string(salt)};
    GlProgram p = s.files.size() == 1 ? GlProgram::compute(s.files[0], defines)
                                      : GlProgram::graphics(s.files[0], s.files[1], defines);
    p.waitLinked();
    return p;
}

} // namespace

int main(int argc, char** argv) try {
    std::vector<int> threadCounts = {1, 2, 4, 8};
    int rounds = 3, device = -1;
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
        } else if (k == "--rounds") rounds = std::stoi(value());
        else if (k == "--device") device = std::stoi(value());
        else throw Error("unknown option " + k);
    }
    GlContext gl(GlContextOptions{device, false});
    const std::vector<Shader> candidates = {
        {{"brick_flag.comp"}}, {{"buffer_clear.comp"}}, {{"brick_scan.comp"}}, {{"brick_scatter.comp"}},
        {{"brick_max_orient.comp"}}, {{"slice_setup.comp"}}, {{"slice_runs.comp"}}, {{"sample.comp"}},
        {{"sample_dispatch.comp"}}, {{"radix_histogram.comp"}}, {{"radix_scan.comp"}}, {{"radix_scatter.comp"}},
        {{"brick_resolve.comp"}}, {{"brick_resolve_scan.comp"}}, {{"slice.vert", "append.frag"}},
        {{"inspect_fullscreen.vert", "inspect_raycast.frag"}}, {{"inspect_proxy.vert", "inspect_proxy.frag"}},
        {{"inspect_slices.vert", "inspect_slices.frag"}}, {{"inspect_slices_keys.comp"}}};
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
        for (int threads : threadCounts) {
            ++salt;
            const auto start = std::chrono::steady_clock::now();
            std::vector<GlProgram> programs(shaders.size());
            double contextSeconds = 0.0;
            if (threads <= 1) {
                // As a run does: every compile started, then every link waited for.
                const std::vector<std::string> defines = {"YV_SALT " + std::to_string(salt)};
                for (std::size_t i = 0; i < shaders.size(); ++i) {
                    const Shader& s = shaders[i];
                    programs[i] = s.files.size() == 1 ? GlProgram::compute(s.files[0], defines)
                                                      : GlProgram::graphics(s.files[0], s.files[1], defines);
                }
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
