#include "core/error.h"
#include "gpu/egl_context.h"
#include "gpu/gl_program.h"
#include "gpu/gl_voxelizer.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <future>
#include <thread>
#include <vector>

namespace {

/// Compiles and links an inline compute source (the real shaders belong to the
/// voxelizer and are tested there).
GLuint inlineComputeProgram(const char* src) {
    GLuint cs = glCreateShader(GL_COMPUTE_SHADER);
    glShaderSource(cs, 1, &src, nullptr);
    glCompileShader(cs);
    GLint ok = GL_FALSE;
    glGetShaderiv(cs, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[4096] = {};
        glGetShaderInfoLog(cs, sizeof log, nullptr, log);
        FAIL("inline compute shader did not compile: " << log);
    }
    GLuint prog = glCreateProgram();
    glAttachShader(prog, cs);
    glLinkProgram(prog);
    glDeleteShader(cs);
    glGetProgramiv(prog, GL_LINK_STATUS, &ok);
    REQUIRE(ok == GL_TRUE);
    return prog;
}

const char* kCountingShader = R"(#version 450 core
layout(local_size_x = 64) in;
layout(std430, binding = 0) writeonly buffer Values { uint values[]; };
layout(std430, binding = 1) buffer Sum { uint sum; };
layout(binding = 0, offset = 0) uniform atomic_uint counter;
uniform uint n;
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= n) return;
    values[i] = i * i + 7u;
    atomicAdd(sum, i);
    atomicCounterIncrement(counter);
}
)";

/// What kCountingShader's program left after `n` invocations on fresh
/// buffers of the current context.
struct CountingRun {
    std::vector<GLuint> values;
    GLuint sum = 0, counter = 0;
};

CountingRun runCounting(GLuint prog, GLuint n) {
    GLuint bufs[3] = {};
    glCreateBuffers(3, bufs);
    const GLuint zero = 0;
    glNamedBufferStorage(bufs[0], n * sizeof(GLuint), nullptr, 0);
    glNamedBufferStorage(bufs[1], sizeof(GLuint), &zero, 0);
    glNamedBufferStorage(bufs[2], sizeof(GLuint), &zero, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, bufs[0]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, bufs[1]);
    glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, bufs[2]);
    glUseProgram(prog);
    glUniform1ui(glGetUniformLocation(prog, "n"), n);
    glDispatchCompute((n + 63) / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    REQUIRE_NOTHROW(yv::checkGlError("counting dispatch"));
    CountingRun run;
    run.values.resize(n);
    glGetNamedBufferSubData(bufs[0], 0, n * sizeof(GLuint), run.values.data());
    glGetNamedBufferSubData(bufs[1], 0, sizeof run.sum, &run.sum);
    glGetNamedBufferSubData(bufs[2], 0, sizeof run.counter, &run.counter);
    REQUIRE_NOTHROW(yv::checkGlError("read back"));
    glDeleteBuffers(3, bufs);
    return run;
}

} // namespace

TEST_CASE("GlContext gives an OpenGL 4.5 core context with sane limits", "[gl]") {
    YV_REQUIRE_GL();
    yv::GlContext ctx;
    const yv::GlInfo& info = ctx.info();
    INFO("renderer: " << info.renderer << ", version: " << info.version << ", platform: " << platformName(info.platform));

    GLint major = 0, minor = 0, profile = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    CHECK(major * 10 + minor >= 45);
    CHECK((profile & GL_CONTEXT_CORE_PROFILE_BIT) != 0);

    CHECK_FALSE(info.renderer.empty());
    CHECK_FALSE(info.version.empty());
    // Mesa's software rasteriser comes through the surfaceless platform, a GPU through the device platform.
    CHECK((info.renderer.find("llvmpipe") != std::string::npos) == !info.hardware());
    CHECK(info.maxSsboBlockSize > 0);
    CHECK(info.maxComputeWorkGroupCountX >= 65535); // GL 4.3 minimum
    CHECK(info.maxTextureSize >= 1024);
    CHECK(info.max3dTextureSize >= 256);
    CHECK(info.maxViewportDims[0] > 0);
    CHECK(info.maxViewportDims[1] > 0);
    CHECK((info.freeMemoryBytes == -1 || info.freeMemoryBytes > 0));
    const long long freeNow = ctx.queryFreeMemoryBytes();
    CHECK((freeNow == -1 || freeNow > 0));
    CHECK(yv::GlContext::available());
}

TEST_CASE("a compute shader writes an SSBO and counts atomically", "[gl]") {
    YV_REQUIRE_GL();
    yv::GlContext ctx;
    GLuint prog = inlineComputeProgram(kCountingShader);
    constexpr GLuint n = 1000;
    const CountingRun run = runCounting(prog, n);
    int wrong = 0;
    for (GLuint i = 0; i < n; ++i) wrong += run.values[i] != i * i + 7u;
    CHECK(wrong == 0);
    CHECK(run.sum == n * (n - 1) / 2);
    CHECK(run.counter == n);
    glDeleteProgram(prog);
}

TEST_CASE("a shader name that is not embedded is an Error naming it", "[gl]") {
    YV_REQUIRE_GL();
    yv::GlContext ctx;
    const std::string name = "no_such_shader_for_test.comp";
    REQUIRE_THROWS_AS(yv::compileShaderStage(GL_COMPUTE_SHADER, name, {}), yv::Error);
    REQUIRE_THROWS_WITH(yv::compileShaderStage(GL_COMPUTE_SHADER, name, {"X 1"}), Catch::Contains(name));
    REQUIRE_THROWS_WITH(yv::GlProgram::compute(name), Catch::Contains(name));
}

TEST_CASE("A program's failed compile is an Error naming the shader at its first use, with the driver's log", "[gl]") {
    YV_REQUIRE_GL();
    yv::GlContext ctx;
    // A define that puts an #error line in the source: the stage cannot compile.
    const std::vector<std::string> broken = {"YV_TEST 1\n#error broken on purpose"};
    yv::GlProgram program = yv::GlProgram::compute("brick_scan.comp", broken); // compiles in the background
    REQUIRE_THROWS_WITH(program.waitLinked(),
                        Catch::Contains("shader brick_scan.comp: compile failed") && Catch::Contains("broken on purpose"));
    yv::GlProgram graphics = yv::GlProgram::graphics("inspect_proxy.vert", "inspect_proxy.frag", broken);
    REQUIRE_THROWS_WITH(graphics.use(), Catch::Contains("compile failed"));
    // Several made before any is used all link, and each checks once.
    std::vector<yv::GlProgram> programs;
    for (const char* name : {"brick_scan.comp", "buffer_clear.comp", "brick_flag.comp"}) programs.push_back(yv::GlProgram::compute(name));
    for (const yv::GlProgram& p : programs) {
        REQUIRE_NOTHROW(p.waitLinked());
        GLint linked = GL_FALSE;
        glGetProgramiv(p.id(), GL_LINK_STATUS, &linked);
        CHECK(linked == GL_TRUE);
    }
}

TEST_CASE("checkGlError reports and clears a GL error", "[gl]") {
    YV_REQUIRE_GL();
    yv::GlContext ctx;
    glGetError(); // start clean
    glBindBuffer(GL_ARRAY_BUFFER, 0xdead); // not a buffer name: GL_INVALID_OPERATION in core
    REQUIRE_THROWS_WITH(yv::checkGlError("test bind"), Catch::Contains("test bind"));
    REQUIRE_NOTHROW(yv::checkGlError("after"));
}

TEST_CASE("contexts can be created and destroyed one after another", "[gl]") {
    YV_REQUIRE_GL();
    for (int round = 0; round < 3; ++round) {
        INFO("round " << round);
        yv::GlContext ctx;
        CHECK_FALSE(ctx.info().renderer.empty());
        GLuint prog = inlineComputeProgram(kCountingShader);
        GLuint buf = 0;
        glCreateBuffers(1, &buf);
        const GLuint value = 40u + static_cast<GLuint>(round);
        glNamedBufferStorage(buf, sizeof value, &value, 0);
        GLuint back = 0;
        glGetNamedBufferSubData(buf, 0, sizeof back, &back);
        CHECK(back == value);
        glDeleteBuffers(1, &buf);
        glDeleteProgram(prog);
        REQUIRE_NOTHROW(yv::checkGlError("round"));
    }
    CHECK(yv::GlContext::available());
}

TEST_CASE("destroying a nested context makes the outer one current again", "[gl]") {
    YV_REQUIRE_GL();
    yv::GlContext outer;
    { yv::GlContext inner; }
    GLuint buf = 0;
    glCreateBuffers(1, &buf);
    CHECK(buf != 0);
    glDeleteBuffers(1, &buf);
    REQUIRE_NOTHROW(yv::checkGlError("outer after inner"));
}

TEST_CASE("a context made and released on a thread of its own is made current on the thread that takes it", "[gl]") {
    YV_REQUIRE_GL();
    std::unique_ptr<yv::GlContext> ctx = std::async(std::launch::async, [] {
                                             auto made = std::make_unique<yv::GlContext>(yv::GlContextOptions{});
                                             made->releaseCurrent();
                                             return made;
                                         }).get();
    REQUIRE(ctx);
    CHECK_FALSE(ctx->info().renderer.empty());
    // Nothing is current here until it is taken; after that GL calls work here.
    CHECK(eglGetCurrentContext() == EGL_NO_CONTEXT);
    ctx->makeCurrent();
    CHECK(eglGetCurrentContext() != EGL_NO_CONTEXT);
    GLuint buf = 0;
    glCreateBuffers(1, &buf);
    const GLuint value = 1234u;
    glNamedBufferStorage(buf, sizeof value, &value, 0);
    GLuint back = 0;
    glGetNamedBufferSubData(buf, 0, sizeof back, &back);
    CHECK(back == value);
    glDeleteBuffers(1, &buf);
    REQUIRE_NOTHROW(yv::checkGlError("taken context"));
    // Released, another thread can make it current and use it.
    ctx->releaseCurrent();
    CHECK(eglGetCurrentContext() == EGL_NO_CONTEXT);
    GLuint onOther = 0;
    std::thread([&] {
        ctx->makeCurrent();
        glCreateBuffers(1, &onOther);
        glDeleteBuffers(1, &onOther);
        ctx->releaseCurrent();
    }).join();
    CHECK(onOther != 0);
    ctx->makeCurrent();
}

TEST_CASE("a sharing context's program runs on the first context, on that context's buffers", "[gl]") {
    YV_REQUIRE_GL();
    yv::GlContext ctx;
    // Compiled on a thread of its own, in a context sharing the first's objects.
    GLuint prog = 0;
    std::thread([&] {
        std::unique_ptr<yv::GlContext> sharing = ctx.makeSharing();
        CHECK(eglGetCurrentContext() != EGL_NO_CONTEXT);
        prog = inlineComputeProgram(kCountingShader);
        glFinish();
    }).join();
    REQUIRE(prog != 0);
    ctx.makeCurrent();
    REQUIRE(glIsProgram(prog) == GL_TRUE);
    constexpr GLuint n = 300;
    const CountingRun run = runCounting(prog, n);
    CHECK(run.counter == n);
    CHECK(run.sum == n * (n - 1) / 2);
    glDeleteProgram(prog);
}

TEST_CASE("the GL backend's programs compiled before a run are embedded shaders that compile", "[gl]") {
    YV_REQUIRE_GL();
    yv::GlContext ctx;
    REQUIRE_NOTHROW(yv::compileInvariantPrograms());
    REQUIRE_NOTHROW(yv::checkGlError("programs without variants"));
}

TEST_CASE("a context that cannot be made is an Error, not a crash", "[gl]") {
    CHECK_THROWS_AS(yv::GlContext(yv::GlContextOptions{1000}), yv::Error); // no machine has a thousand GL devices
}
