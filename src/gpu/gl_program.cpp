#include "gpu/gl_program.h"

#include "core/error.h"
#include "core/trace.h"
#include "gpu/shader_sources.h"

#include <epoxy/egl.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <optional>
#include <sstream>
#include <utility>

#include <unistd.h>

namespace yv {
namespace {

/// YV_SHADER_DIR=DIR: a shader file found in DIR is compiled instead of the
/// copy built into the binary (for trying a shader change on a machine
/// without rebuilding it). One that is there but cannot be read is an error.
std::optional<std::string> shaderOverride(const std::string& name) {
    const char* dir = std::getenv("YV_SHADER_DIR");
    if (!dir || !*dir) return std::nullopt;
    const std::string path = std::string(dir) + "/" + name;
    if (access(path.c_str(), F_OK) != 0) return std::nullopt;
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    if (!std::filesystem::is_regular_file(path) || !(text << in.rdbuf()) || text.str().empty())
        throw Error("YV_SHADER_DIR: " + path + ": cannot be read, or is empty");
    return text.str();
}

std::string trimmed(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ' || s.back() == '\r' || s.back() == '\0'))
        s.pop_back();
    return s;
}

std::string shaderLog(GLuint shader) {
    GLint len = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<size_t>(len > 0 ? len : 0), '\0');
    if (len > 0) glGetShaderInfoLog(shader, len, nullptr, log.data());
    return trimmed(std::move(log));
}

std::string programLog(GLuint program) {
    GLint len = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<size_t>(len > 0 ? len : 0), '\0');
    if (len > 0) glGetProgramInfoLog(program, len, nullptr, log.data());
    return trimmed(std::move(log));
}

const char* glErrorName(GLenum e) {
    switch (e) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    default: return "unknown GL error";
    }
}

} // namespace

std::optional<std::string> shaderText(const std::string& name) {
    if (std::optional<std::string> text = shaderOverride(name)) return text;
    if (const char* text = shaderSource(name.c_str())) return std::string(text);
    return std::nullopt;
}

namespace {

/// A shader's source as given to the driver, and the files its source-string
/// numbers stand for (files[i] is number i + 1).
struct ComposedShader {
    std::string text;
    std::vector<std::string> files;
};

/// FILE of an `#include "FILE"` line, else nullopt.
std::optional<std::string> includedFile(const std::string& line) {
    const std::size_t hash = line.find_first_not_of(" \t");
    if (hash == std::string::npos || line.compare(hash, 8, "#include") != 0) return std::nullopt;
    const std::size_t open = line.find('"', hash + 8), close = line.find('"', open + 1);
    if (open == std::string::npos || close == std::string::npos || close == open + 1)
        throw Error("a malformed #include line: " + line);
    return line.substr(open + 1, close - open - 1);
}

/// Appends `text`, shader file `name`'s, under source-string number
/// `number`, each `#include "FILE"` line replaced by FILE's text under a
/// number of its own the first time FILE is included (the next times by
/// nothing but the #line that follows).
void appendWithIncludes(const std::string& name, const std::string& text, int number, ComposedShader& out, int depth) {
    out.text += "#line 1 " + std::to_string(number) + "\n";
    std::istringstream lines(text);
    int lineNumber = 0;
    for (std::string line; std::getline(lines, line);) {
        ++lineNumber;
        std::optional<std::string> file;
        try {
            file = includedFile(line);
        } catch (const Error& e) {
            throw Error("shader " + name + " line " + std::to_string(lineNumber) + ": " + e.what());
        }
        if (!file) {
            out.text += line + "\n";
            continue;
        }
        if (std::find(out.files.begin(), out.files.end(), *file) == out.files.end()) {
            const std::optional<std::string> included = shaderText(*file);
            if (!included)
                throw Error("shader " + name + " line " + std::to_string(lineNumber) + " includes " + *file +
                            ", which is not among the embedded shaders (add shaders/" + *file +
                            " to YV_SHADERS in CMakeLists.txt)");
            if (depth >= 8) throw Error("shader " + name + ": #include nested more than 8 deep");
            out.files.push_back(*file);
            appendWithIncludes(*file, *included, static_cast<int>(out.files.size()), out, depth + 1);
        }
        out.text += "#line " + std::to_string(lineNumber + 1) + " " + std::to_string(number) + "\n";
    }
}

/// "#version 450 core", the #define lines, bindings.glsl (the binding points'
/// names, always the built-in list: the C++ that binds the buffers was built
/// with it), then the shader with its includes. A shader includes only what
/// it uses: NVIDIA's compiler takes 5 to 9 ms a program to read the rest
/// (bench/results/README.md, 2026-12-06: a first run's compiles).
ComposedShader composeShader(const std::string& name, const std::vector<std::string>& defines) {
    const std::optional<std::string> text = shaderText(name);
    if (!text)
        throw Error("shader " + name + ": not among the embedded shaders (add shaders/" + name +
                    " to YV_SHADERS in CMakeLists.txt)");
    ComposedShader out{"#version 450 core\n", {name, "bindings.glsl"}};
    for (const std::string& d : defines) out.text += "#define " + d + "\n";
    out.text += "#line 1 2\n";
    if (const char* bindings = shaderSource("bindings.glsl")) out.text += bindings;
    out.text += "\n";
    appendWithIncludes(name, *text, 1, out, 0);
    return out;
}

/// "source-string 1 is NAME, 2 is bindings.glsl, 3 is ...": how to read a driver's log.
std::string sourceStringNames(const std::string& name) {
    std::string names;
    try {
        const ComposedShader composed = composeShader(name, {});
        for (std::size_t i = 0; i < composed.files.size(); ++i)
            names += (i ? ", " : "source-string ") + std::to_string(i + 1) + " is " + composed.files[i];
    } catch (const Error&) {
        names = "source-string 1 is " + name + ", 2 is bindings.glsl";
    }
    return names;
}

} // namespace

std::string composedShaderText(const std::string& name, const std::vector<std::string>& defines) {
    return composeShader(name, defines).text;
}

GlShader startShaderStage(GLenum stage, const std::string& name, const std::vector<std::string>& defines) {
    const ComposedShader composed = composeShader(name, defines);
    GlShader shader(glCreateShader(stage));
    if (!shader) throw Error("shader " + name + ": glCreateShader failed (no current GL context?)");
    const char* p = composed.text.c_str();
    glShaderSource(shader.id(), 1, &p, nullptr);
    // Traced by name: a first run with no shader cache waits on the driver's compiler.
    const auto start = std::chrono::steady_clock::now();
    glCompileShader(shader.id());
    if (traceEnabled()) traceSpanSince("compile " + name, start);
    return shader;
}

void checkShaderStage(const GlShader& shader, const std::string& name) {
    GLint ok = GL_FALSE;
    glGetShaderiv(shader.id(), GL_COMPILE_STATUS, &ok);
    if (!ok) {
        const std::string log = shaderLog(shader.id());
        throw Error("shader " + name + ": compile failed (" + sourceStringNames(name) + "):\n" + log);
    }
}

GlShader compileShaderStage(GLenum stage, const std::string& name, const std::vector<std::string>& defines) {
    GlShader shader = startShaderStage(stage, name, defines);
    checkShaderStage(shader, name);
    return shader;
}

GlProgram GlProgram::link(std::vector<Stage> stages, const std::string& names) {
    GlProgram program(glCreateProgram());
    for (const Stage& s : stages) glAttachShader(program.id_, s.shader.id());
    const auto start = std::chrono::steady_clock::now();
    glLinkProgram(program.id_);
    if (traceEnabled()) traceSpanSince("link " + names, start);
    // The stages stay until the check: a failed compile's log is theirs.
    program.pending_ = std::make_unique<Pending>(Pending{std::move(stages), names});
    return program;
}

void GlProgram::waitLinked() const {
    if (!pending_) return;
    const std::unique_ptr<Pending> pending = std::move(pending_);
    GLint ok = GL_FALSE;
    const auto start = std::chrono::steady_clock::now();
    glGetProgramiv(id_, GL_LINK_STATUS, &ok);
    if (traceEnabled()) traceSpanSince("wait for the link of " + pending->names, start);
    if (!ok) {
        for (const Stage& s : pending->stages) checkShaderStage(s.shader, s.name);
        throw Error("shader " + pending->names + ": link failed:\n" + programLog(id_));
    }
    for (const Stage& s : pending->stages) glDetachShader(id_, s.shader.id());
}

GlProgram GlProgram::compute(const std::string& name, const std::vector<std::string>& defines) {
    std::vector<Stage> stages;
    stages.push_back({startShaderStage(GL_COMPUTE_SHADER, name, defines), name});
    return link(std::move(stages), name);
}

GlProgram GlProgram::graphics(const std::string& vertexName, const std::string& fragmentName,
                              const std::vector<std::string>& defines) {
    std::vector<Stage> stages;
    stages.push_back({startShaderStage(GL_VERTEX_SHADER, vertexName, defines), vertexName});
    stages.push_back({startShaderStage(GL_FRAGMENT_SHADER, fragmentName, defines), fragmentName});
    return link(std::move(stages), vertexName + " + " + fragmentName);
}

GlProgram GlProgram::graphicsWithGeometry(const std::string& vertexName, const std::string& geometryName,
                                          const std::string& fragmentName, const std::vector<std::string>& defines) {
    std::vector<Stage> stages;
    stages.push_back({startShaderStage(GL_VERTEX_SHADER, vertexName, defines), vertexName});
    stages.push_back({startShaderStage(GL_GEOMETRY_SHADER, geometryName, defines), geometryName});
    stages.push_back({startShaderStage(GL_FRAGMENT_SHADER, fragmentName, defines), fragmentName});
    return link(std::move(stages), vertexName + " + " + geometryName + " + " + fragmentName);
}

GlProgram::~GlProgram() {
    // A program outliving its context has nothing left to free.
    if (eglGetCurrentContext() == EGL_NO_CONTEXT) {
        if (pending_)
            for (Stage& s : pending_->stages) s.shader.release();
        return;
    }
    if (id_ != 0) glDeleteProgram(id_);
}

GlProgram::GlProgram(GlProgram&& other) noexcept
    : id_(std::exchange(other.id_, 0)), pending_(std::move(other.pending_)) {}

GlProgram& GlProgram::operator=(GlProgram&& other) noexcept {
    if (this != &other) {
        GlProgram old(std::move(*this));
        id_ = std::exchange(other.id_, 0);
        pending_ = std::move(other.pending_);
    }
    return *this;
}

GLuint GlProgram::id() const {
    waitLinked();
    return id_;
}

void GlProgram::use() const { glUseProgram(id()); }

GLint GlProgram::uniform(const char* name) const { return glGetUniformLocation(id(), name); }

void checkGlError(const char* where) {
    GLenum first = glGetError();
    if (first == GL_NO_ERROR) return;
    // Drain the queue so the next check reports only its own errors; bounded
    // because a lost context may report forever.
    for (int i = 0; i < 32 && glGetError() != GL_NO_ERROR; ++i) {
    }
    throw Error(std::string("GL error ") + glErrorName(first) + " at " + where);
}

} // namespace yv
