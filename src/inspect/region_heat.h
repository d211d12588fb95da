// `inspect --render ... --regions`: the zoom regions' boxes and heat, read
// from a work directory or from what a .vdb records, and the words for the
// scale their colours stand for.
#pragma once

#include "core/stats.h"
#include "inspect/region_outlines.h"

#include <string>
#include <vector>

namespace yv {

/// The zoom regions' boxes, hot by their active voxels (neither the store
/// nor the .vdb keeps fragment counts). Throws yv::Error for a .vdb that
/// records no regions.
std::vector<RegionHeat> loadRegionHeat(const std::string& input);

/// The heat scale as --json has it (`regions` must not be empty).
JsonObject regionHeatJson(const std::vector<RegionHeat>& regions);

/// The heat scale in a line (`regions` must not be empty).
std::string regionHeatText(const std::vector<RegionHeat>& regions);

} // namespace yv
