// A shader names the files it uses with `#include "FILE"` lines, which the
// program builder replaces by FILE's text (the embedded copy, or
// YV_SHADER_DIR's): each file once, and the driver's log still points at the
// right file and line.
#include "core/error.h"
#include "gpu/egl_context.h"
#include "gpu/gl_program.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>

#include <epoxy/gl.h>

#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

namespace {

/// YV_SHADER_DIR pointed at a fresh folder of this test's shader files while
/// the object lives.
struct ShaderDir {
    yv::test::ScratchDir dir{"yv_shader_includes"};
    ShaderDir() { ::setenv("YV_SHADER_DIR", dir.path.c_str(), 1); }
    ~ShaderDir() { ::unsetenv("YV_SHADER_DIR"); }
    void write(const std::string& name, const std::string& text) const {
        std::ofstream(dir.path / name, std::ios::binary) << text;
    }
};

/// Runs `program` once (one invocation) and reads back the first `n` words
/// of the buffer at binding 0.
std::vector<GLuint> runOnce(GLuint program, int n) {
    GLuint buffer = 0;
    glCreateBuffers(1, &buffer);
    std::vector<GLuint> values(static_cast<std::size_t>(n), 0u);
    glNamedBufferStorage(buffer, GLsizeiptr(values.size() * sizeof(GLuint)), values.data(), GL_DYNAMIC_STORAGE_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffer);
    glUseProgram(program);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(buffer, 0, GLsizeiptr(values.size() * sizeof(GLuint)), values.data());
    glDeleteBuffers(1, &buffer);
    return values;
}

} // namespace

TEST_CASE("An #include line is replaced by the file's text, once however often it is included", "[gl]") {
    YV_REQUIRE_GL();
    yv::GlContext ctx;
    const ShaderDir shaders;
    // A second copy of kBase or plusOne would not compile.
    shaders.write("base.glsl", "// Five lines, so that a line count that does not resume shows.\n"
                               "const uint kBase = 41u;\n\n"
                               "uint plusOne(uint v) { return v + 1u; }\n\n");
    shaders.write("doubled.glsl", "#include \"base.glsl\"\n\nuint doubled(uint v) { return 2u * v; }\n");
    shaders.write("include_test.comp", "layout(local_size_x = 1) in;\n"
                                       "#include \"base.glsl\"\n"
                                       "  #include \"doubled.glsl\"\n"
                                       "#include \"base.glsl\"\n"
                                       "layout(std430, binding = 0) buffer Out { uint values[]; };\n"
                                       "void main() {\n"
                                       "    values[0] = plusOne(kBase);\n"
                                       "    values[1] = doubled(kBase);\n"
                                       "    values[2] = uint(__LINE__);\n"
                                       "}\n");
    const yv::GlProgram program = yv::GlProgram::compute("include_test.comp");
    REQUIRE_NOTHROW(program.waitLinked());
    // __LINE__ is the file's own line 9: the line count resumes after each include.
    CHECK(runOnce(program.id(), 3) == std::vector<GLuint>{42u, 82u, 9u});
}

TEST_CASE("A compile error in an included file is reported with the file its source-string number stands for", "[gl]") {
    YV_REQUIRE_GL();
    yv::GlContext ctx;
    const ShaderDir shaders;
    shaders.write("fine.glsl", "const uint kFine = 1u;\n");
    shaders.write("broken.glsl", "const uint kBroken = 2u;\nuint broken() { return kBroken + undeclaredName; }\n");
    shaders.write("broken_include.comp", "layout(local_size_x = 1) in;\n#include \"fine.glsl\"\n"
                                         "#include \"broken.glsl\"\nvoid main() {}\n");
    const yv::GlProgram program = yv::GlProgram::compute("broken_include.comp");
    // Numbers: 1 the shader, 2 bindings.glsl, then the includes in order.
    REQUIRE_THROWS_WITH(program.waitLinked(), Catch::Contains("shader broken_include.comp: compile failed") &&
                                                  Catch::Contains("3 is fine.glsl, 4 is broken.glsl") &&
                                                  Catch::Contains("undeclaredName"));
}

TEST_CASE("An #include of a file that is nowhere is an Error naming the file and the line", "[gl]") {
    YV_REQUIRE_GL();
    yv::GlContext ctx;
    const ShaderDir shaders;
    shaders.write("missing_include.comp", "layout(local_size_x = 1) in;\n#include \"nowhere.glsl\"\nvoid main() {}\n");
    REQUIRE_THROWS_WITH(yv::GlProgram::compute("missing_include.comp"),
                        Catch::Contains("missing_include.comp line 2 includes nowhere.glsl") &&
                            Catch::Contains("not among the embedded shaders"));
    shaders.write("bad_include.comp", "layout(local_size_x = 1) in;\n#include nowhere.glsl\nvoid main() {}\n");
    REQUIRE_THROWS_WITH(yv::GlProgram::compute("bad_include.comp"),
                        Catch::Contains("bad_include.comp line 2: a malformed #include line"));
}

TEST_CASE("composedShaderText is the text the driver is given: compiled by hand it runs as the program does", "[gl]") {
    YV_REQUIRE_GL();
    yv::GlContext ctx;
    const ShaderDir shaders;
    shaders.write("base.glsl", "const uint kBase = 41u;\n");
    shaders.write("composed_test.comp", "layout(local_size_x = 1) in;\n"
                                        "#include \"base.glsl\"\n"
                                        "#include \"base.glsl\"\n"
                                        "layout(std430, binding = 0) buffer Out { uint values[]; };\n"
                                        "void main() { values[0] = kBase + EXTRA; values[1] = uint(__LINE__); }\n");
    const std::string text = yv::composedShaderText("composed_test.comp", {"EXTRA 7u"});
    CHECK(text.rfind("#version 450 core\n#define EXTRA 7u\n", 0) == 0);
    CHECK(text.find("#include") == std::string::npos);
    CHECK(text.find("kBase = 41u") == text.rfind("kBase = 41u")); // once

    const GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
    const char* source = text.c_str();
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    REQUIRE(ok == GL_TRUE);
    const GLuint byHand = glCreateProgram();
    glAttachShader(byHand, shader);
    glLinkProgram(byHand);
    glGetProgramiv(byHand, GL_LINK_STATUS, &ok);
    REQUIRE(ok == GL_TRUE);
    glDeleteShader(shader);

    const yv::GlProgram program = yv::GlProgram::compute("composed_test.comp", {"EXTRA 7u"});
    const std::vector<GLuint> expected = runOnce(program.id(), 2);
    CHECK(expected == std::vector<GLuint>{48u, 5u});
    const std::vector<GLuint> values = runOnce(byHand, 2);
    glDeleteProgram(byHand);
    CHECK(values == expected);

    REQUIRE_THROWS_WITH(yv::composedShaderText("nowhere.comp", {}), Catch::Contains("not among the embedded shaders"));
}
