// The GL backend's programs compiled ahead on a thread of their own, through
// a context sharing the run's (gpu/gl_program_compiler.h): each program is
// the one asked for, usable on the run's context, its compile errors thrown
// where it is used, and a run's bricks the same bits as with programs
// compiled in place.
#include "core/error.h"
#include "core/packed_bricks.h"
#include "garment/cross_section.h"
#include "garment/generate.h"
#include "gpu/egl_context.h"
#include "gpu/gl_bindings.h"
#include "gpu/gl_program.h"
#include "gpu/gl_program_compiler.h"
#include "gpu/gl_voxelizer.h"
#include "test_helpers.h"

#include <catch2/catch.hpp>

#include <epoxy/gl.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

using namespace yv;

namespace {

/// buffer_clear.comp run over a buffer of `n` words, all 7 at first, its
/// first `cleared` words cleared; returns the buffer's words.
std::vector<GLuint> clearWords(const GlProgram& clear, GLuint n, GLuint cleared) {
    std::vector<GLuint> words(n, 7u);
    GLuint buffer = 0;
    glCreateBuffers(1, &buffer);
    glNamedBufferStorage(buffer, GLsizeiptr(n * sizeof(GLuint)), words.data(), 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kClearedWordsBinding, buffer);
    clear.use();
    glUniform1ui(clear.uniform("uWords"), cleared);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(buffer, 0, GLsizeiptr(n * sizeof(GLuint)), words.data());
    glDeleteBuffers(1, &buffer);
    return words;
}

/// Keeps a run's regions, resolved on the GPU or not.
class KeepRegions : public RegionSink {
  public:
    void consume(const ZoomRegion&, PackedBricks&& bricks) override { packed.push_back(std::move(bricks)); }
    void consumeAccumulators(const ZoomRegion&, std::vector<BrickAccumulator>&& bricks) override {
        std::move(bricks.begin(), bricks.end(), std::back_inserter(accumulators));
    }
    std::vector<PackedBricks> packed;
    std::vector<BrickAccumulator> accumulators;
};

bool sameBricks(const BrickVolume& a, const BrickVolume& b) {
    if (a.bricks.size() != b.bricks.size()) return false;
    for (std::size_t i = 0; i < a.bricks.size(); ++i)
        if (a.bricks[i].key != b.bricks[i].key || a.bricks[i].activeMask != b.bricks[i].activeMask ||
            std::memcmp(a.bricks[i].density.data(), b.bricks[i].density.data(), 4 * kBrickVoxels) != 0 ||
            std::memcmp(a.bricks[i].orientation.data(), b.bricks[i].orientation.data(), 12 * kBrickVoxels) != 0)
            return false;
    return true;
}

} // namespace

TEST_CASE("a program compiled on the compile thread runs on the run's context", "[gl][programs]") {
    YV_REQUIRE_GL();
    const GlContext context;
    GlProgramCompiler compiler(context, {{"buffer_clear.comp", {}}});
    const GlProgram clear = compiler.take("buffer_clear.comp");
    CHECK(compiler.waiting() == 0);
    const std::vector<GLuint> words = clearWords(clear, 1000, 600);
    CHECK(std::count(words.begin(), words.begin() + 600, 0u) == 600);
    CHECK(std::count(words.begin() + 600, words.end(), 7u) == 400);
    CHECK(clear.linkedYet());
    CHECK_NOTHROW(checkGlError("a program from the compile thread"));
}

TEST_CASE("a program not asked of the compiler, or asked twice, is compiled where it is taken", "[gl][programs]") {
    YV_REQUIRE_GL();
    const GlContext context;
    GlProgramCompiler compiler(context, {{"buffer_clear.comp", {}}, {"brick_flag.comp", {}}});
    const GlProgram first = compiler.take("buffer_clear.comp");
    const GlProgram second = compiler.take("buffer_clear.comp"); // the request is spent: compiled here
    CHECK(second.linkedYet());
    CHECK(compiler.waiting() == 1); // brick_flag.comp is never taken
    CHECK(clearWords(first, 64, 64) == std::vector<GLuint>(64, 0u));
    CHECK(clearWords(second, 64, 32)[40] == 7u);
    // Other #defines are another program.
    const GlProgram variant = compiler.take("brick_flag.comp", {"REDUCE_MAX 1"});
    CHECK(variant.id() != 0);
    CHECK(compiler.waiting() == 1);
    // A compiler with nothing ahead compiles everything here.
    GlProgramCompiler here;
    CHECK(clearWords(here.take("buffer_clear.comp"), 16, 16) == std::vector<GLuint>(16, 0u));
}

TEST_CASE("a compile error on the compile thread is thrown where the program is used, naming the shader", "[gl][programs]") {
    YV_REQUIRE_GL();
    const GlContext context;
    test::ScratchDir dir("yv_program_compiler");
    std::ofstream(dir.path / "buffer_clear.comp") << "layout(local_size_x = 1) in;\nvoid main() { not glsl; }\n";
    ::setenv("YV_SHADER_DIR", dir.path.c_str(), 1);
    GlProgramCompiler compiler(context, {{"buffer_clear.comp", {}}});
    const GlProgram broken = compiler.take("buffer_clear.comp");
    try {
        broken.use();
        FAIL("a shader that does not compile was used");
    } catch (const Error& e) {
        CHECK_THAT(e.what(), Catch::Matches("shader buffer_clear.comp: compile failed[\\s\\S]*"));
    }
    ::unsetenv("YV_SHADER_DIR"); // after the compile thread has read it
    // The same request from the built-in shader compiles.
    GlProgramCompiler good(context, {{"buffer_clear.comp", {}}});
    CHECK_NOTHROW(good.take("buffer_clear.comp").use());
}

TEST_CASE("a compiler dropped with programs not taken, or taken and never used, leaves the context clean", "[gl][programs]") {
    YV_REQUIRE_GL();
    const GlContext context;
    const std::vector<ProgramRequest> requests = runPrograms(GlProgramChoice{});
    {
        GlProgramCompiler compiler(context, requests);
        const GlProgram taken = compiler.take(requests.front().name, requests.front().defines);
        CHECK(compiler.waiting() == requests.size() - 1);
    } // waits for the program being compiled, deletes the rest
    CHECK_NOTHROW(checkGlError("after the compiler"));
    // The context still compiles and runs programs.
    GlProgramCompiler here;
    CHECK(clearWords(here.take("buffer_clear.comp"), 8, 8) == std::vector<GLuint>(8, 0u));
}

TEST_CASE("every program a GL run asks for compiles, for every choice of variants", "[gl][programs]") {
    YV_REQUIRE_GL();
    const GlContext context;
    std::vector<GlProgramChoice> choices(6);
    choices[1].diskCrossSection = true;
    choices[2].albedo = true;
    choices[3].reduce = Reduce::Max;
    choices[4].overlap = Overlap::Sum;
    choices[5].slicePrimitive = SlicePrimitive::Point;
    for (const GlProgramChoice& choice : choices) {
        const std::vector<ProgramRequest> requests = runPrograms(choice);
        // The passes' first programs first: the slices placed, then their items.
        REQUIRE(requests.size() >= 9);
        CHECK(requests.front().name == "slice_setup.comp");
        CHECK(requests[1].name == (choice.slicePrimitive == SlicePrimitive::Point ? "sample_dispatch.comp"
                                                                                   : "slice_items.comp"));
        CHECK(requests.back().name == "brick_resolve.comp");
        GlProgramCompiler compiler(context, requests, 4);
        for (const ProgramRequest& r : requests) {
            INFO(r.name);
            CHECK_NOTHROW(compiler.take(r.name, r.defines).waitLinked());
        }
    }
}

TEST_CASE("GL: a run whose programs come from the compile thread gives the bricks of one that compiles its own, bit for bit", "[gl][programs][agreement]") {
    YV_REQUIRE_GL();
    GenerateOptions g;
    g.pattern = WeavePattern::Twill;
    g.crossings = 24;
    SliceOptions opt;
    opt.radius = 0.12;
    const SlicePlan plan = planSlices(generateGarment(g), opt);
    const VoxelGrid grid = makeGrid(plan, 96, 0);
    const CrossSection xs = makeFiberCrossSection();
    GlVoxelizeSettings settings;
    settings.brickResolve = BrickResolve::Gpu;
    settings.fragmentCapacity = 6000; // several regions
    const BrickVolume inPlace = [&] {
        const GlContext context;
        return voxelizeGl(plan, xs, grid, settings, context);
    }();

    for (int threads : {1, 3}) {
        INFO(threads << " compile threads");
        auto context = std::make_unique<GlContext>();
        auto compiler = std::make_unique<GlProgramCompiler>(*context, runPrograms(GlProgramChoice{}), threads);
        GlBackend backend(plan, xs, grid, settings, std::move(context), std::move(compiler));
        const ZoomPlan zoom = planZoomRegions(plan, grid, xs, {backend.fragmentBudget(), backend.maxRegionSize(), 1});
        REQUIRE(zoom.regions.size() > 1);
        KeepRegions sink;
        backend.run(zoom.regions, sink);
        CHECK(sink.accumulators.empty());
        const BrickVolume ahead = unpackVolume(grid, Reduce::Mean, sink.packed);
        REQUIRE(!ahead.bricks.empty());
        CHECK(sameBricks(ahead, inPlace));
    }
}
