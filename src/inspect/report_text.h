// What the inspect reports share: printf-style text built up before it is
// printed, sizes in bytes, and the density statistics and the time per stage
// as text and as JSON.
#pragma once

#include "core/stage_seconds.h"
#include "core/stats.h"
#include "core/voxel_statistics.h"

#include <string>

namespace yv {

/// Appends printf-formatted text to `out`.
[[gnu::format(printf, 2, 3)]] void appendf(std::string& out, const char* format, ...);

/// A byte count as "512 B", "340.27 KB", "1.20 GB" (powers of 1000).
std::string bytesText(double bytes);

/// The statistics as --json has them; `voxelVolume` turns the density sum into fibre volume.
JsonObject statisticsJson(const VoxelStatistics& v, double voxelVolume);

/// The density histogram as bars, the voxels above 1 and, where the volume
/// has an orientation grid, the share of unit axes and their mean |axis|.
std::string statisticsText(const VoxelStatistics& v, double voxelVolume, bool hasOrientation);

/// Seconds per stage, or "recorded": false where the run did not record them.
JsonObject stageReportObject(const StageSeconds& stages);

/// The time per stage in a line (and the parts timed on their own threads in
/// another), or why none was recorded.
std::string stageSecondsText(const StageSeconds& stages, const char* notRecordedWhy);

} // namespace yv
