// GL shader programs built from the shaders embedded from shaders/.
#pragma once

#include "gpu/gl_objects.h"

#include <epoxy/gl.h>

#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace yv {

/// A linked GL program. Sources are composed as: "#version 450 core", the
/// given #define lines, shaders/bindings.glsl (the binding points' names,
/// gl_bindings.h), then the shader file itself, each of its `#include
/// "FILE"` lines replaced by FILE's text the first time (wherever the line
/// stands: the preprocessor's #if does not hide it). Every file is behind a
/// #line marker with a source-string number of its own (1 the shader, 2
/// bindings.glsl, then the includes in order; a compile error lists them),
/// so driver logs point at the right file and line.
///
/// Making one starts the driver's compile and link and returns: the outcome
/// is asked for at the program's first use (or waitLinked()), so a driver
/// that compiles on threads of its own may compile the programs a run makes
/// one after another side by side. (On the H200 a first run with no shader
/// cache spent about 1 s compiling; with this, 0.6 to 0.9 s. Asking for more
/// compiler threads with GL_KHR_parallel_shader_compile made no clear
/// difference there and cost warm renders 0.1 s: bench/first_run.sh.)
class GlProgram {
  public:
    GlProgram() = default;
    /// Compute program from one shader file (e.g. "brick_flag.comp").
    static GlProgram compute(const std::string& name, const std::vector<std::string>& defines = {});
    /// Graphics program from a vertex and a fragment shader file.
    static GlProgram graphics(const std::string& vertexName, const std::string& fragmentName,
                              const std::vector<std::string>& defines = {});
    /// Graphics program with a geometry shader between the two.
    static GlProgram graphicsWithGeometry(const std::string& vertexName, const std::string& geometryName,
                                          const std::string& fragmentName, const std::vector<std::string>& defines = {});
    ~GlProgram();
    GlProgram(GlProgram&& other) noexcept;
    GlProgram& operator=(GlProgram&& other) noexcept;
    GlProgram(const GlProgram&) = delete;
    GlProgram& operator=(const GlProgram&) = delete;

    /// The program's name, once linked (waits, and throws as waitLinked does).
    GLuint id() const;
    void use() const;
    /// Uniform location, or -1 (not an error: the driver may optimise it away).
    GLint uniform(const char* name) const;
    /// Waits for the compile and link; a failure throws yv::Error with the
    /// shader's name and the driver's log, as it would have when made.
    void waitLinked() const;

  private:
    struct Stage {
        GlShader shader;
        std::string name;
    };
    /// What a program still being compiled keeps for its check.
    struct Pending {
        std::vector<Stage> stages;
        std::string names;
    };
    explicit GlProgram(GLuint id) : id_(id) {}
    /// Attaches and starts the link; `names` is what a link error reports.
    static GlProgram link(std::vector<Stage> stages, const std::string& names);
    GLuint id_ = 0;
    mutable std::unique_ptr<Pending> pending_; ///< until waitLinked() has checked it
};

/// The text compiled for shader file `name`: the file of that name in
/// YV_SHADER_DIR where the variable is set and the file is there (for trying
/// a shader change without rebuilding), else the copy built into the binary;
/// nullopt when neither exists. (bindings.glsl is compiled from the built-in
/// copy always: the C++ that binds the buffers was built with it.)
std::optional<std::string> shaderText(const std::string& name);

/// The whole text given to the driver for shader file `name` with `defines`
/// (#version, the #defines, bindings.glsl, the file with its includes), as
/// startShaderStage composes it: for tools that compile it elsewhere.
std::string composedShaderText(const std::string& name, const std::vector<std::string>& defines);

/// Compiles one stage. A failure throws yv::Error with the shader's name and
/// the driver's log.
GlShader compileShaderStage(GLenum stage, const std::string& name, const std::vector<std::string>& defines);
/// Starts compiling one stage and returns (a shader that is not among the
/// embedded ones throws at once); checkShaderStage asks for the outcome.
GlShader startShaderStage(GLenum stage, const std::string& name, const std::vector<std::string>& defines);
/// Throws yv::Error with `name` and the driver's log when `shader` did not compile.
void checkShaderStage(const GlShader& shader, const std::string& name);

/// Throws yv::Error naming `where` when glGetError reports an error.
void checkGlError(const char* where);

} // namespace yv
