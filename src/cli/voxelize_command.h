// `yarnvox voxelize` for whoever runs it: the command line (main.cpp, which
// prints each garment's summary) and programs that run yarnvox in their own
// process (the Python module, which keeps the reports). Both parse the same
// options with the same checks and defaults, and write the same files.
#pragma once

#include "pipeline/voxelize_job.h"

#include <functional>

namespace CLI {
class App;
}

namespace yv {

/// Runs one garment's job once its options are parsed and its output named
/// (a .vol or .nvdb output: a temporary .vdb, converted afterwards).
using VoxelizeOne = std::function<void(const VoxelizeJob& job)>;

/// Adds the `voxelize` subcommand to `app`, running `voxelizeOne` for each
/// garment it is given.
void addVoxelizeCommand(CLI::App& app, VoxelizeOne voxelizeOne);

} // namespace yv
