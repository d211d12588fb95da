#include "inspect/region_heat.h"

#include "core/error.h"
#include "inspect/inspect_store.h"
#include "inspect/inspect_vdb.h"
#include "inspect/report_text.h"

#include <algorithm>
#include <filesystem>
#include <utility>

namespace yv {
namespace {

/// The heat scale the outlines' colours stand for.
std::pair<double, double> heatRange(const std::vector<RegionHeat>& regions) {
    double low = regions.front().heat, high = low;
    for (const RegionHeat& h : regions) low = std::min(low, h.heat), high = std::max(high, h.heat);
    return {low, high};
}

} // namespace

std::vector<RegionHeat> loadRegionHeat(const std::string& input) {
    std::vector<RegionHeat> out;
    if (!std::filesystem::is_directory(input)) {
        for (const RecordedRegion& r : readVdbRegions(input))
            out.push_back(RegionHeat{r.id, VoxelBox{r.min, r.max}, double(r.activeVoxels)});
        if (out.empty()) throw Error(vdbHasNoRegions(input));
        return out;
    }
    for (const RegionRow& r : inspectStore(input, false).regions)
        out.push_back(RegionHeat{r.info.id, VoxelBox{r.info.min, r.info.max}, double(r.info.activeVoxels)});
    return out;
}

JsonObject regionHeatJson(const std::vector<RegionHeat>& regions) {
    const auto [low, high] = heatRange(regions);
    return JsonObject()
        .set("regions", std::uint64_t(regions.size()))
        .set("measure", "active_voxels")
        .set("low", low)
        .set("high", high)
        .set("colours", "blue (low), red, yellow (high)");
}

std::string regionHeatText(const std::vector<RegionHeat>& regions) {
    const auto [low, high] = heatRange(regions);
    std::string out;
    appendf(out,
            "region outlines: %zu regions coloured by active voxels, blue %.0f, red %.0f, yellow %.0f (the legend "
            "bar at the bottom left)\n",
            regions.size(), low, 0.5 * (low + high), high);
    return out;
}

} // namespace yv
