// yarnvox's program cache: a linked program is stored under a key of the
// driver's names and its whole source, and a later build of the same
// program loads it; a changed shader, define or driver is another key, and a
// damaged or refused file is compiled again and replaced.
#include "core/error.h"
#include "gpu/egl_context.h"
#include "gpu/gl_program.h"
#include "gpu/program_cache.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>

#include <epoxy/gl.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

/// Sets an environment variable while the object lives ("" is unset), then
/// puts back what was there.
struct ScopedEnv {
    std::string name;
    std::optional<std::string> before;
    ScopedEnv(std::string n, const std::string& value) : name(std::move(n)) {
        if (const char* v = std::getenv(name.c_str())) before = v;
        if (value.empty()) ::unsetenv(name.c_str());
        else ::setenv(name.c_str(), value.c_str(), 1);
    }
    ~ScopedEnv() {
        if (before) ::setenv(name.c_str(), before->c_str(), 1);
        else ::unsetenv(name.c_str());
    }
    ScopedEnv(const ScopedEnv&) = delete;
    ScopedEnv& operator=(const ScopedEnv&) = delete;
};

/// A program cache folder and a shader folder of this test's own.
struct CacheAndShaders {
    yv::test::ScratchDir root{"yv_program_cache"};
    fs::path cache = root.path / "cache", shaders = root.path / "shaders";
    ScopedEnv cacheEnv{"YV_PROGRAM_CACHE", cache.string()}, shaderEnv{"YV_SHADER_DIR", shaders.string()};
    CacheAndShaders() { fs::create_directories(shaders); }
    /// A compute shader that writes `value` (or VALUE where defined) to word 0 of binding 0.
    void writeShader(const std::string& value) const {
        std::ofstream(shaders / "cache_test.comp", std::ios::binary)
            << "layout(local_size_x = 1) in;\nlayout(std430, binding = 0) buffer Out { uint values[]; };\n"
               "#ifndef VALUE\n#define VALUE " << value << "u\n#endif\nvoid main() { values[0] = VALUE; }\n";
    }
    std::vector<fs::path> files() const {
        std::vector<fs::path> out;
        if (fs::exists(cache))
            for (const fs::directory_entry& e : fs::directory_iterator(cache)) out.push_back(e.path());
        return out;
    }
};

GLuint runOnce(const yv::GlProgram& program) {
    GLuint buffer = 0, value = 0;
    glCreateBuffers(1, &buffer);
    glNamedBufferStorage(buffer, sizeof value, &value, GL_DYNAMIC_STORAGE_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffer);
    program.use();
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(buffer, 0, sizeof value, &value);
    glDeleteBuffers(1, &buffer);
    return value;
}

/// Builds cache_test.comp with `defines` and runs it; `loaded`: whether it came from the cache.
GLuint buildAndRun(const std::vector<std::string>& defines, bool& loaded) {
    const yv::ProgramCacheCounts before = yv::programCacheCounts();
    const yv::GlProgram program = yv::GlProgram::compute("cache_test.comp", defines);
    const GLuint value = runOnce(program);
    loaded = yv::programCacheCounts().loaded == before.loaded + 1;
    return value;
}

} // namespace

TEST_CASE("A linked program is stored in the program cache and loaded from it the next time, and runs the same", "[gl]") {
    YV_REQUIRE_GL();
    yv::GlContext ctx;
    GLint formats = 0;
    glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &formats);
    REQUIRE(formats > 0); // Mesa's llvmpipe gives one; without it the cache would be idle
    const CacheAndShaders dirs;
    dirs.writeShader("42");
    bool loaded = true;
    CHECK(buildAndRun({}, loaded) == 42u);
    CHECK_FALSE(loaded);
    REQUIRE(dirs.files().size() == 1);
    CHECK(buildAndRun({}, loaded) == 42u);
    CHECK(loaded);
    CHECK(dirs.files().size() == 1);
}

TEST_CASE("A changed shader or define is another program: the cache never serves a stale one", "[gl]") {
    YV_REQUIRE_GL();
    yv::GlContext ctx;
    const CacheAndShaders dirs;
    dirs.writeShader("42");
    bool loaded = true;
    REQUIRE(buildAndRun({}, loaded) == 42u);
    dirs.writeShader("43"); // the same file name, another text
    CHECK(buildAndRun({}, loaded) == 43u);
    CHECK_FALSE(loaded);
    CHECK(buildAndRun({"VALUE 44u"}, loaded) == 44u);
    CHECK_FALSE(loaded);
    CHECK(dirs.files().size() == 3);
    dirs.writeShader("42"); // back: the first program's binary serves it
    CHECK(buildAndRun({}, loaded) == 42u);
    CHECK(loaded);
}

TEST_CASE("A program's key changes with the driver's names and with each stage's type and text", "[gl]") {
    const std::vector<std::pair<GLenum, std::string>> stages = {{GL_COMPUTE_SHADER, "void main() {}"}};
    const std::string key = yv::programKey("NVIDIA\nH200\n4.6 580.159.04\n4.60", stages);
    CHECK(key.size() == 32);
    CHECK(key == yv::programKey("NVIDIA\nH200\n4.6 580.159.04\n4.60", stages));
    CHECK(key != yv::programKey("NVIDIA\nH200\n4.6 580.160.01\n4.60", stages)); // a driver update
    CHECK(key != yv::programKey("NVIDIA\nH100\n4.6 580.159.04\n4.60", stages));
    CHECK(key != yv::programKey("NVIDIA\nH200\n4.6 580.159.04\n4.60", {{GL_VERTEX_SHADER, "void main() {}"}}));
    CHECK(key != yv::programKey("NVIDIA\nH200\n4.6 580.159.04\n4.60", {{GL_COMPUTE_SHADER, "void main() { }"}}));
    // Where one part ends and the next begins is part of the key.
    CHECK(yv::programKey("ab", {{GL_COMPUTE_SHADER, "c"}}) != yv::programKey("a", {{GL_COMPUTE_SHADER, "bc"}}));
}

TEST_CASE("A damaged or refused program cache file is compiled again and replaced", "[gl]") {
    YV_REQUIRE_GL();
    yv::GlContext ctx;
    const CacheAndShaders dirs;
    dirs.writeShader("42");
    bool loaded = true;
    REQUIRE(buildAndRun({}, loaded) == 42u);
    REQUIRE(dirs.files().size() == 1);
    const fs::path file = dirs.files().front();
    const auto size = fs::file_size(file);
    SECTION("a byte changed: its checksum fails") {
        std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(std::streamoff(size - 1));
        f.put('\x5a' ^ char(size));
    }
    SECTION("cut short") { fs::resize_file(file, size - 3); }
    SECTION("a binary the driver refuses, under a right checksum") {
        const std::string key = file.stem().string();
        REQUIRE(yv::storeCachedProgram(dirs.cache, key, yv::ProgramBinary{0x1234, std::vector<std::uint8_t>(64, 7)}));
        const yv::ProgramCacheCounts before = yv::programCacheCounts();
        CHECK(buildAndRun({}, loaded) == 42u);
        CHECK_FALSE(loaded);
        CHECK(yv::programCacheCounts().refused == before.refused + 1);
    }
    CHECK(buildAndRun({}, loaded) == 42u);
    CHECK(buildAndRun({}, loaded) == 42u); // replaced by the compile before
    CHECK(loaded);
}

TEST_CASE("The program cache's folder: YV_PROGRAM_CACHE, then XDG_CACHE_HOME, then HOME, or none when off", "[gl]") {
    {
        const ScopedEnv env("YV_PROGRAM_CACHE", "off");
        CHECK_FALSE(yv::programCacheDir());
    }
    {
        const ScopedEnv env("YV_PROGRAM_CACHE", "/somewhere/programs");
        CHECK(yv::programCacheDir() == fs::path("/somewhere/programs"));
    }
    const ScopedEnv noSetting("YV_PROGRAM_CACHE", "");
    {
        const ScopedEnv xdg("XDG_CACHE_HOME", "/xdg");
        CHECK(yv::programCacheDir() == fs::path("/xdg/yarnvox/programs"));
    }
    const ScopedEnv noXdg("XDG_CACHE_HOME", "");
    {
        const ScopedEnv home("HOME", "/home/someone");
        CHECK(yv::programCacheDir() == fs::path("/home/someone/.cache/yarnvox/programs"));
    }
    const ScopedEnv noHome("HOME", "");
    CHECK_FALSE(yv::programCacheDir());
}
