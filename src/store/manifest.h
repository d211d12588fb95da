// The manifest of a brick store's work directory: which run the directory
// belongs to. JSON, so a person can see what a work dir holds; the format is
// in formats/brick-store.md.
#pragma once

#include "core/run_metadata.h"
#include "core/sampling.h"
#include "core/stage_seconds.h"
#include "core/voxel_grid.h"

#include <cstdint>
#include <optional>
#include <string>

namespace yv {

/// What a work directory belongs to. The fingerprint is the caller's hash of
/// everything that determines the bricks (garment, grid, options, and the
/// yarnvox version and sampling code below, so those are named when they differ).
struct StoreManifest {
    std::uint64_t fingerprint = 0;
    /// The yarnvox version that made the regions (YV_VERSION by default).
    std::string yarnvoxVersion = YV_VERSION;
    /// The caller's hash of the code that samples the yarns (shaders, CPU rule).
    std::uint64_t samplingCode = 0;
    VoxelGrid grid;
    Reduce reduce = Reduce::Mean;
    /// The description of the run, for a later `yarnvox merge` and `inspect`
    /// (its regions are not kept); not part of the run's identity.
    VolumeMetadata run;
    /// Set by BrickStore::markComplete: the number of regions of the finished
    /// run. Empty while the run is unfinished; ignored when comparing runs.
    std::optional<std::uint64_t> completeRegions;
    /// Set with completeRegions: the seconds the finishing run spent in each
    /// stage (core/stage_seconds.h); empty in work dirs of older yarnvox versions.
    StageSeconds stageSeconds;
};

/// The manifest as JSON text (doubles with every digit they need to read back bit-exactly).
std::string formatManifest(const StoreManifest& m);

/// Parses manifest text strictly; throws yv::Error "PATH: ..." naming the
/// field otherwise, and one line of its own for the text manifest of older
/// yarnvox versions.
StoreManifest parseManifest(const std::string& path, const std::string& text);

/// Why `disk` is not the run `now` describes (yarnvox version, sampling code,
/// fingerprint, grid, reduce mode); empty when it is. The fingerprint is only
/// named when version and sampling code agree: it covers them.
std::string runDifference(const StoreManifest& disk, const StoreManifest& now);

/// Whether two grids are bit-for-bit the same.
bool sameGrid(const VoxelGrid& a, const VoxelGrid& b);

/// Throws yv::Error unless `g` has finite values, a positive voxel size and
/// dims that are multiples of 8; `where` names it in the message.
void checkGrid(const VoxelGrid& g, const std::string& where);

} // namespace yv
