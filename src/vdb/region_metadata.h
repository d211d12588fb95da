// The zoom regions of a run as a .vdb records them: one string item,
// "yarnvox_regions", in the density grid's metadata, so `yarnvox inspect`
// can frame and outline regions without the work directory
// (formats/vdb-subset.md).
#pragma once

#include <glm/vec3.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace yv {

/// The density grid's metadata item that holds the regions.
inline constexpr const char* kRegionsMetadataName = "yarnvox_regions";

/// One zoom region: its voxel box (min inclusive, max exclusive) and its heat.
struct RecordedRegion {
    std::uint64_t id = 0;
    glm::ivec3 min{0}, max{0};
    std::uint64_t activeVoxels = 0;
};

/// "ID MINX MINY MINZ MAXX MAXY MAXZ ACTIVE" per region, in the order given,
/// joined by ';': the same regions give the same string.
std::string encodeRegions(const std::vector<RecordedRegion>& regions);
/// The regions of an encodeRegions string; throws yv::Error naming `where`
/// and the bad entry when it is malformed.
std::vector<RecordedRegion> decodeRegions(const std::string& text, const std::string& where);

} // namespace yv
