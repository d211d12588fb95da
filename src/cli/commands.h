// Subcommands of the yarnvox CLI; each registers itself with its help text.
#pragma once

namespace CLI {
class App;
}

namespace yv {

void addGenCommand(CLI::App& app);
void addVoxelizeCommand(CLI::App& app);
void addMergeCommand(CLI::App& app);
void addInspectCommand(CLI::App& app);
void addExportCommand(CLI::App& app);
void addViewCommand(CLI::App& app);

} // namespace yv
