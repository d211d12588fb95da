// The ceiling for yarnvox's raster + append pass: a bare append on this GPU.
// Instanced squares of side S pixels are rasterised with a fragment shader that
// only increments the atomic counter and stores one 16-byte fragment
// (shaders/bench_append.frag), into a list as large as yarnvox's. Prints one
// JSON object per square size: fragments appended per second (best of the
// repeats, glFinish at both ends).
//
//   yv_bench_append [--sides 2,4,8,16] [--fragments 67108864] [--repeat 5] [--device -1]
#include "core/error.h"
#include "gpu/egl_context.h"
#include "gpu/gl_program.h"
#include "gpu/gpu_layout.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

using namespace yv;

int main(int argc, char** argv) try {
    std::vector<int> sides = {2, 4, 8, 16};
    std::uint64_t target = std::uint64_t(1) << 26;
    int repeat = 5, device = -1;
    for (int i = 1; i < argc; ++i) {
        const std::string k = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw Error(k + ": missing value");
            return argv[++i];
        };
        if (k == "--sides") {
            sides.clear();
            std::stringstream ss(value());
            for (std::string item; std::getline(ss, item, ',');) sides.push_back(std::stoi(item));
        } else if (k == "--fragments") target = std::stoull(value());
        else if (k == "--repeat") repeat = std::stoi(value());
        else if (k == "--device") device = std::stoi(value());
        else throw Error("unknown option " + k + " (see the comment at the top of bench/append_micro.cpp)");
    }

    GlContext context(GlContextOptions{device, false});
    const GlProgram program = GlProgram::graphics("bench_append.vert", "bench_append.frag");
    GLuint buffers[2], vao = 0, fbo = 0;
    glCreateBuffers(2, buffers);
    glNamedBufferStorage(buffers[0], GLsizeiptr(target * sizeof(GpuFragment)), nullptr, 0);
    glNamedBufferStorage(buffers[1], 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
    glCreateVertexArrays(1, &vao);
    glCreateFramebuffers(1, &fbo);
    const int viewport = 4096;
    glNamedFramebufferParameteri(fbo, GL_FRAMEBUFFER_DEFAULT_WIDTH, viewport);
    glNamedFramebufferParameteri(fbo, GL_FRAMEBUFFER_DEFAULT_HEIGHT, viewport);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, viewport, viewport);
    glDisable(GL_DEPTH_TEST);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glBindVertexArray(vao);
    program.use();
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, buffers[0]);
    glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, buffers[1]);
    glUniform1ui(program.uniform("uCapacity"), GLuint(target));
    glUniform2f(program.uniform("uViewport"), float(viewport), float(viewport));
    glUniform1i(program.uniform("uPerRow"), 1024);
    checkGlError("setting up the append microbenchmark");

    for (int side : sides) {
        const GLsizei instances = GLsizei(std::max<std::uint64_t>(1, target / (std::uint64_t(side) * side)));
        glUniform1f(program.uniform("uSide"), float(side));
        double best = 1e300;
        GLuint appended = 0;
        for (int r = 0; r < repeat; ++r) {
            const GLuint zero = 0;
            glNamedBufferSubData(buffers[1], 0, 4, &zero);
            glFinish();
            const auto start = std::chrono::steady_clock::now();
            glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, instances);
            glFinish();
            best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
            glGetNamedBufferSubData(buffers[1], 0, 4, &appended);
        }
        checkGlError("append microbenchmark");
        std::printf("{ \"bench\": \"append\", \"renderer\": \"%s\", \"side_pixels\": %d, \"instances\": %d, "
                    "\"fragments\": %u, \"seconds\": %.6f, \"fragments_per_second\": %.4g, \"instances_per_second\": %.4g }\n",
                    context.info().renderer.c_str(), side, instances, appended, best, appended / best, instances / best);
        std::fflush(stdout);
    }
    glDeleteBuffers(2, buffers);
    glDeleteVertexArrays(1, &vao);
    glDeleteFramebuffers(1, &fbo);
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "yv_bench_append: error: %s\n", e.what());
    return 1;
}
