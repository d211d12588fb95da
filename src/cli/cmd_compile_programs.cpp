// `yarnvox compile-programs`: not a user's command. A GL run whose program
// cache lacks its slowest programs starts this executable with it, twice,
// to compile them beside the run (gpu/program_helpers.h); the programs are
// read from standard input, one a line.
#include "cli/commands.h"
#include "gpu/program_helpers.h"

#include <CLI/CLI.hpp>

#include <iostream>
#include <memory>

namespace yv {

void addCompileProgramsCommand(CLI::App& app) {
    CLI::App* cmd = app.add_subcommand("compile-programs", "a GL run's helper: compiles programs into the cache");
    cmd->group(""); // not listed in --help
    auto options = std::make_shared<GlContextOptions>();
    cmd->add_option("--device", options->device);
    cmd->add_option("--spread", options->spreadIndex);
    cmd->callback([options] { compileProgramsIntoCache(std::cin, *options); });
}

} // namespace yv
