// yarnvox's `gen` and `voxelize` commands run from another program in its own
// process (the Python module): the words a command line would hold, parsed
// by the CLI's own subcommands, so options, defaults, checks and messages are
// the command line's.
#pragma once

#include "cli/voxelize_command.h"

#include <string>
#include <vector>

namespace yv {

/// Runs `words` ("gen ..." or "voxelize ...", without the program's name),
/// each voxelize job through `voxelizeOne`. Throws CLI::ParseError (its
/// what() the line the command line prints after "yarnvox: error: ") for an
/// option the command line would refuse, and yv::Error for a failed run.
void runEmbeddedCommand(const std::vector<std::string>& words, const VoxelizeOne& voxelizeOne);

/// The long option names of `command` ("gen" or "voxelize", without their
/// dashes), each with whether it is a flag (takes no value).
std::vector<std::pair<std::string, bool>> embeddedCommandOptions(const std::string& command);

} // namespace yv
