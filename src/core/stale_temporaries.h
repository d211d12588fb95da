// What a killed yarnvox leaves beside an output: a signal lets a command
// remove its temporaries, but SIGKILL (or a second SIGINT) ends it at once,
// leaving OUT.partial-PID-N (core/atomic_file.h), OUT.partial-PID.vdb (the
// .vdb a --format vol|nvdb run converts) or, for a report directory,
// DIR.tmp-PID and DIR.old-PID. The next run writing OUT removes them.
#pragma once

#include <string>
#include <vector>

namespace yv {

/// Whether process `pid` exists on this machine (a temporary of a live
/// process is never touched: it may be another run writing the same output).
bool processAlive(long pid);

/// The PID in `name` when it is `base` + ".partial-", ".tmp-" or ".old-",
/// then the digits of a PID, then nothing, "-..." or "." (yarnvox's
/// temporaries of the output `base`); -1 otherwise.
long temporaryOwner(const std::string& name, const std::string& base);

/// Removes the temporaries of `path` (files, or report directories) beside
/// it whose process is gone, and returns their paths. Never throws: what
/// cannot be removed stays.
std::vector<std::string> removeStaleTemporaries(const std::string& path);

} // namespace yv
