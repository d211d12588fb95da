// `yarnvox gen`: writes a procedural garment as BCC.
#include "bcc.h"
#include "cli/commands.h"
#include "cli/interruptible.h"
#include "cli/option_checks.h"
#include "core/interrupt.h"
#include "core/output_path.h"
#include "garment/generate.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <limits>
#include <memory>

namespace yv {

namespace {

struct GenArgs {
    std::string pattern = "plain", shape = "flat", output;
    std::uint64_t crossings = 1000, seed = 1;
    double spacing = 1.0, radius = 0.3;
    bool quiet = false;
};

/// Generates the garment and writes it; a signal before the write writes nothing.
void runGen(const GenArgs& a) {
    checkOutputPath(a.output, "-o", {}); // before the garment is generated, as every command does
    GenerateOptions opt;
    opt.pattern = parseWeavePattern(a.pattern);
    opt.shape = parseGarmentShape(a.shape);
    opt.crossings = a.crossings;
    opt.seed = a.seed;
    opt.yarnSpacing = a.spacing;
    opt.yarnRadius = a.radius;
    const Garment garment = generateGarment(opt);
    signalAtTestPoint("gen-write");
    throwIfInterrupted("before " + a.output + " was written: nothing was written; run the command again");
    writeBcc(a.output, garment);
    if (!a.quiet)
        std::printf("wrote %s: %s %s, %zu yarns, %zu control points, %zu segments\n", a.output.c_str(),
                    toString(opt.pattern), toString(opt.shape), garment.yarns.size(), garment.controlPointCount(),
                    garment.segmentCount());
}

} // namespace

void addGenCommand(CLI::App& app) {
    auto args = std::make_shared<GenArgs>();
    CLI::App* cmd = app.add_subcommand("gen", "Generate a yarn-level garment (BCC file) for tests, demos and benchmarks");
    cmd->add_option("--pattern", args->pattern, "Weave or knit: plain, twill, satin, knit")->capture_default_str();
    cmd->add_option("--crossings", args->crossings, "Number of yarn crossings (the paper's dense vest has 410000)")
        ->capture_default_str()
        ->check(wholeNumber<std::uint64_t>(1, 100'000'000));
    cmd->add_option("--shape", args->shape, "Garment shape: flat, cylinder, sphere")->capture_default_str();
    cmd->add_option("--seed", args->seed, "Seed of the control-point jitter")
        ->capture_default_str()
        ->check(wholeNumber<std::uint64_t>(0, std::numeric_limits<std::uint64_t>::max()));
    cmd->add_option("--spacing", args->spacing, "Distance between neighbouring yarns, world units")
        ->capture_default_str()
        ->check(worldLength());
    cmd->add_option("--yarn-radius", args->radius, "Yarn radius recorded in the file, world units")
        ->capture_default_str()
        ->check(worldLength());
    cmd->add_option("-o,--output", args->output, "Output .bcc file")->required();
    cmd->add_flag("-q,--quiet", args->quiet, "Print nothing on success");
    cmd->callback([args] { runInterruptible(args->output + " is whole", [&] { runGen(*args); }); });
}

} // namespace yv
