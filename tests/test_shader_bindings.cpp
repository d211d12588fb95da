// The binding points are named once (shaders/bindings.glsl): every shader
// binds its blocks, counters, textures and images by those names, never by a
// bare number, and the names mean on the GPU what C++ binds there.

// GCC 12 sees an uninitialised std::function in <regex>'s automaton at -O1
// with the sanitizers (tools/test-sanitize): a false positive in libstdc++.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include "gpu/egl_context.h"
#include "gpu/gl_bindings.h"
#include "gpu/gl_program.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>

#include <epoxy/gl.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const fs::path kShaderDir = fs::path(YV_SOURCE_DIR) / "shaders";

std::string fileText(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

/// bindings.glsl's names and their numbers; fails on any line that is not a
/// comment, blank, or `const int kName = N;` (the file must stay valid C++ and GLSL).
std::map<std::string, int> bindingNames() {
    const std::regex line(R"(const int (k[A-Za-z0-9]+) = ([0-9]+);\s*(//.*)?)");
    std::map<std::string, int> names;
    std::istringstream in(fileText(kShaderDir / "bindings.glsl"));
    for (std::string text; std::getline(in, text);) {
        if (text.empty() || text.rfind("//", 0) == 0) continue;
        std::smatch m;
        INFO("bindings.glsl: " << text);
        REQUIRE(std::regex_match(text, m, line));
        CHECK(names.emplace(m[1], std::stoi(m[2])).second); // each name once
    }
    return names;
}

/// The shaders a run or `yarnvox inspect` compiles (the benchmarks' own
/// shaders belong to bench/).
std::vector<fs::path> shaderFiles() {
    std::vector<fs::path> files;
    for (const fs::directory_entry& e : fs::directory_iterator(kShaderDir)) {
        const std::string name = e.path().filename().string();
        if (name != "bindings.glsl" && name.rfind("bench_", 0) != 0) files.push_back(e.path());
    }
    return files;
}

} // namespace

TEST_CASE("Every binding in the shaders is a name from shaders/bindings.glsl, and every name is used", "[bindings]") {
    const std::map<std::string, int> names = bindingNames();
    REQUIRE(names.size() > 20);
    const std::vector<fs::path> files = shaderFiles();
    REQUIRE(files.size() > 20);
    const std::regex binding(R"(binding\s*=\s*([A-Za-z0-9_]+))");
    std::set<std::string> used;
    for (const fs::path& file : files) {
        const std::string text = fileText(file);
        for (auto it = std::sregex_iterator(text.begin(), text.end(), binding); it != std::sregex_iterator(); ++it) {
            const std::string name = (*it)[1];
            INFO(file.filename().string() << ": binding = " << name);
            CHECK(names.count(name) == 1);
            used.insert(name);
        }
    }
    for (const auto& [name, number] : names) {
        INFO(name << " = " << number << " is bound by no shader");
        CHECK(used.count(name) == 1);
    }
    // C++ sees the same list (gl_bindings.h includes it).
    CHECK(yv::kFragmentsBinding == names.at("kFragmentsBinding"));
    CHECK(yv::kTransferFunctionUnit == names.at("kTransferFunctionUnit"));
}

TEST_CASE("A storage block declared with a binding name is bound at that name's number", "[gl][bindings]") {
    YV_REQUIRE_GL();
    const yv::GlContext context;
    const std::map<std::string, int> names = bindingNames();
    const std::vector<std::string> xsDefines = {"CROSS_SECTION_DISK 0", "CROSS_SECTION_GATHER 0", "CROSS_SECTION_QUAD 1"};
    std::vector<std::string> sampleDefines = xsDefines;
    sampleDefines.push_back("ALBEDO 1");
    const std::vector<std::pair<std::string, std::vector<std::string>>> programs = {
        {"sample.comp", sampleDefines}, {"brick_scan.comp", {}}, {"brick_resolve.comp", {"ALBEDO 1"}},
        {"brick_resolve_scan.comp", {}}, {"slice_setup.comp", {}}};
    const std::regex block(R"(binding = (k[A-Za-z0-9]+)\)\s*(?:readonly |writeonly )?buffer (\w+))");
    for (const auto& [file, defines] : programs) {
        const yv::GlProgram program = yv::GlProgram::compute(file, defines);
        const std::string text = fileText(kShaderDir / file);
        int checked = 0;
        for (auto it = std::sregex_iterator(text.begin(), text.end(), block); it != std::sregex_iterator(); ++it) {
            const std::string name = (*it)[1], blockName = (*it)[2];
            const GLuint index = glGetProgramResourceIndex(program.id(), GL_SHADER_STORAGE_BLOCK, blockName.c_str());
            if (index == GL_INVALID_INDEX) continue; // compiled out of this variant
            const GLenum property = GL_BUFFER_BINDING;
            GLint bound = -1;
            glGetProgramResourceiv(program.id(), GL_SHADER_STORAGE_BLOCK, index, 1, &property, 1, nullptr, &bound);
            INFO(file << ": block " << blockName << " at " << name);
            CHECK(bound == names.at(name));
            ++checked;
        }
        INFO(file);
        CHECK(checked >= 3);
    }
}
