#include "cli/embedded_command.h"

#include "cli/commands.h"
#include "core/error.h"

#include <CLI/CLI.hpp>

namespace yv {
namespace {

/// The app with the embeddable subcommands, as main.cpp makes them.
void addEmbeddableCommands(CLI::App& app, const VoxelizeOne& voxelizeOne) {
    app.require_subcommand(1);
    addGenCommand(app);
    addVoxelizeCommand(app, voxelizeOne);
}

} // namespace

void runEmbeddedCommand(const std::vector<std::string>& words, const VoxelizeOne& voxelizeOne) {
    CLI::App app{"yarnvox"};
    addEmbeddableCommands(app, voxelizeOne);
    // CLI11 takes the words in reverse order (the last one first).
    std::vector<std::string> reversed(words.rbegin(), words.rend());
    app.parse(reversed);
}

std::vector<std::pair<std::string, bool>> embeddedCommandOptions(const std::string& command) {
    CLI::App app{"yarnvox"};
    addEmbeddableCommands(app, [](const VoxelizeJob&) {});
    const CLI::App* sub = app.get_subcommand(command);
    std::vector<std::pair<std::string, bool>> names;
    for (const CLI::Option* o : sub->get_options()) {
        for (const std::string& name : o->get_lnames())
            if (name != "help") names.emplace_back(name, o->get_type_size() == 0);
    }
    return names;
}

} // namespace yv
