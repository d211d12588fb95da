// A first run's slowest compiles, side by side. NVIDIA's driver compiles one
// program at a time in a process, whatever its threads or contexts, and a
// machine's first run waited about half a second on it; other processes
// compile beside it. So where yarnvox's program cache lacks the GL backend's
// slowest programs, a run starts helper processes (this executable's hidden
// `compile-programs` command) that compile them into the cache while it
// reads and slices the garment, and the backend loads them from there
// (bench/results/README.md, 2026-12-06: a first run's compiles). Where the
// cache holds them, as on every run after a machine's first, none starts.
#pragma once

#include "core/sampling.h"
#include "gpu/egl_context.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace yv {

/// A compute program: its shader file and #defines.
struct ComputeProgram {
    std::string name;
    std::vector<std::string> defines;
};

/// The GL backend's programs that take its driver longest to compile, as a
/// run with these options builds them, longest first: both passes of
/// brick_resolve.comp, sample.comp, and slice_items.comp where sample items
/// are found in compute.
std::vector<ComputeProgram> slowestBackendPrograms(bool analyticDisk, bool albedo, Reduce reduce, Overlap overlap,
                                                   bool computeItems);

/// Starts helper processes for those of `programs` that the program cache
/// lacks for the current context's driver (none where it holds them all or
/// has no folder). YV_COMPILE_PROCESSES=N: at most N helpers (default 2; 0
/// for none). Returns how many started; a helper that cannot start, or
/// fails, only leaves its programs to be compiled here.
int startProgramHelpers(const std::vector<ComputeProgram>& programs, const GlContextOptions& options);

/// Waits for the helpers started (their programs are then in the cache, or
/// compiled here as before).
void waitForProgramHelpers();

/// A helper's work: each line of `in` ("NAME", then a tab before each
/// define) compiled on a context of its own and stored in the program cache.
void compileProgramsIntoCache(std::istream& in, const GlContextOptions& options);

} // namespace yv
