// Checks on where a run will write, made before the work starts: a run of
// minutes must not end by replacing something that is not its output.
#pragma once

#include <string>
#include <vector>

namespace yv {

/// What `path` itself is (never what a link points to) when it exists and is
/// not a regular file: "a symbolic link", "a directory", "a device", "a FIFO",
/// "a socket" or "not a regular file"; "" for a regular file or nothing.
/// Renaming a finished file over any of these would destroy it (a device
/// node, a FIFO another program reads, a link the user made), so no yarnvox
/// file is published over one (checkOutputPath, PendingFile).
std::string nonRegularKind(const std::string& path);

/// Throws yv::Error, naming `path` and `what` ("-o", "--stats"), when `path`
/// is not a place for a new or replaced regular file: a directory, a device,
/// a FIFO, a socket or a symbolic link; a directory that does not exist; or
/// the same file as any of `inputs`. When it is good, removes what killed
/// runs left beside it (removeStaleTemporaries, core/stale_temporaries.h).
void checkOutputPath(const std::string& path, const std::string& what, const std::vector<std::string>& inputs);

} // namespace yv
