// yarnvox's own cache of linked GL programs: the driver's binary of each
// program (glGetProgramBinary), one file a program, named by a hash of the
// driver's names and the program's whole source. A changed shader, define
// or driver names another file, so a stale binary is never looked up; a
// file that is damaged, or that the driver refuses (glProgramBinary), is
// compiled again and replaced. A run loads what an earlier run compiled
// instead of asking the driver's compiler, and helper processes can compile
// a run's programs into it side by side (NVIDIA's compiler takes one program
// at a time in a process).
#pragma once

#include <epoxy/gl.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace yv {

/// A linked program as the driver gives it back.
struct ProgramBinary {
    GLenum format = 0;
    std::vector<std::uint8_t> bytes;
};

/// The cache's folder: YV_PROGRAM_CACHE (a folder, or "off" for none), else
/// $XDG_CACHE_HOME/yarnvox/programs, else $HOME/.cache/yarnvox/programs.
/// nullopt where there is none (off, or no home); the folder is made when
/// the first program is stored.
std::optional<std::filesystem::path> programCacheDir();

/// The driver's names on the current context (vendor, renderer, version,
/// shading language version): part of every key.
std::string driverIdentity();

/// The key of a program: a hash of `driver` and each stage's type and full
/// source text, in order (32 hex digits).
std::string programKey(const std::string& driver, const std::vector<std::pair<GLenum, std::string>>& stages);

/// The binary stored under `key`; nullopt where there is none or the file is
/// damaged (its length or checksum do not match).
std::optional<ProgramBinary> loadCachedProgram(const std::filesystem::path& dir, const std::string& key);

/// Stores `binary` under `key` (written beside and renamed into place, so a
/// reader never sees half a file). A cache that cannot be written is no
/// error: false, and the run goes on.
bool storeCachedProgram(const std::filesystem::path& dir, const std::string& key, const ProgramBinary& binary);

/// What the cache did in this process (for --stats and tests).
struct ProgramCacheCounts {
    std::uint64_t loaded = 0;  ///< programs taken from the cache
    std::uint64_t stored = 0;  ///< programs compiled and stored
    std::uint64_t refused = 0; ///< files damaged or refused by the driver, compiled again
};
ProgramCacheCounts programCacheCounts();
void countProgramCache(std::uint64_t loaded, std::uint64_t stored, std::uint64_t refused);

} // namespace yv
