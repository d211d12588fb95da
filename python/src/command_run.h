// The module's `gen` and `voxelize`: the command line's own subcommands run
// in this process (cli/embedded_command.h), with a Python progress callback
// that can stop the run, and each garment's report returned as a dict.
#pragma once

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

namespace yv::python {

/// Runs `words` ("gen ..." or "voxelize ...") without the GIL. `progress`
/// (None, or progress(stage, unit, done, total)) is called with the GIL held;
/// when it returns False or raises, the run stops at the next region boundary
/// as after a SIGINT. Returns one report dict a voxelized garment. Throws
/// OptionError (bad options), Cancelled (stopped by the callback), the
/// callback's own exception, KeyboardInterrupt (SIGINT) or Error.
pybind11::list runCommand(const std::vector<std::string>& words, const pybind11::object& progress);

/// Registers Error, OptionError and Cancelled in `module`.
void registerExceptions(pybind11::module_& module);

} // namespace yv::python
