#include "inspect/report_text.h"

#include <algorithm>
#include <cstdarg>
#include <cstdio>

namespace yv {

void appendf(std::string& out, const char* format, ...) {
    va_list args;
    va_start(args, format);
    va_list again;
    va_copy(again, args);
    const int n = std::vsnprintf(nullptr, 0, format, args);
    va_end(args);
    if (n > 0) {
        const std::size_t at = out.size();
        out.resize(at + std::size_t(n) + 1);
        std::vsnprintf(out.data() + at, std::size_t(n) + 1, format, again);
        out.resize(at + std::size_t(n)); // without vsnprintf's terminating zero
    }
    va_end(again);
}

std::string bytesText(double b) {
    const char* units[] = {"B", "KB", "MB", "GB", "TB"};
    int u = 0;
    while (b >= 1000.0 && u < 4) b /= 1000.0, ++u;
    char buf[32];
    std::snprintf(buf, sizeof buf, u ? "%.2f %s" : "%.0f %s", b, units[u]);
    return buf;
}

JsonObject statisticsJson(const VoxelStatistics& v, double voxelVolume) {
    std::vector<JsonObject> bins;
    for (int i = 0; i < VoxelStatistics::kBins; ++i)
        bins.push_back(JsonObject().set("low", v.binLow(i)).set("high", v.binHigh(i)).set("voxels", v.histogram[std::size_t(i)]));
    JsonObject axes;
    const double n = v.unitAxes ? double(v.unitAxes) : 1.0;
    axes.set("x", v.axisComponentSum().x / n).set("y", v.axisComponentSum().y / n).set("z", v.axisComponentSum().z / n);
    return JsonObject()
        .set("active_voxels", v.activeVoxels)
        .set("density_histogram", bins)
        .set("voxels_above_one", v.aboveOne)
        .set("share_above_one", v.activeVoxels ? double(v.aboveOne) / double(v.activeVoxels) : 0.0)
        .set("density_max", double(v.densityMax))
        .set("fiber_volume", v.densitySum() * voxelVolume)
        .set("unit_axes", v.unitAxes)
        .set("mean_abs_axis", axes);
}

std::string statisticsText(const VoxelStatistics& v, double voxelVolume, bool hasOrientation) {
    std::string out;
    appendf(out, "density of %llu active voxels (fibre volume %.6g):\n", static_cast<unsigned long long>(v.activeVoxels),
            v.densitySum() * voxelVolume);
    const std::uint64_t most = *std::max_element(v.histogram.begin(), v.histogram.end());
    for (int i = 0; i < VoxelStatistics::kBins; ++i) {
        const std::uint64_t n = v.histogram[std::size_t(i)];
        const std::string bar(std::size_t(most ? int(40.0 * double(n) / double(most) + 0.5) : 0), '#');
        if (i == VoxelStatistics::kBins - 1)
            appendf(out, "  above 1    %12llu %s\n", static_cast<unsigned long long>(n), bar.c_str());
        else
            appendf(out, "  %.1f - %.1f  %12llu %s\n", v.binLow(i), v.binHigh(i), static_cast<unsigned long long>(n),
                    bar.c_str());
    }
    appendf(out, "  above 1 by more than 1/1024: %llu voxels (%.3g %%), largest %.6g\n",
            static_cast<unsigned long long>(v.aboveOne),
            v.activeVoxels ? 100.0 * double(v.aboveOne) / double(v.activeVoxels) : 0.0, v.densityMax);
    if (!hasOrientation) return out;
    const double n = v.unitAxes ? double(v.unitAxes) : 1.0;
    appendf(out, "orientation: %.4g %% of the active voxels have a unit axis; mean |axis| x %.3f, y %.3f, z %.3f\n",
            v.activeVoxels ? 100.0 * double(v.unitAxes) / double(v.activeVoxels) : 0.0, v.axisComponentSum().x / n,
            v.axisComponentSum().y / n, v.axisComponentSum().z / n);
    return out;
}

JsonObject stageReportObject(const StageSeconds& stages) {
    return JsonObject()
        .set("recorded", !stages.empty())
        .set("seconds", stageSecondsObject(stages))
        .set("total_seconds", wholeStageSum(stages));
}

std::string stageSecondsText(const StageSeconds& stages, const char* notRecordedWhy) {
    std::string out;
    if (stages.empty()) {
        appendf(out, "time per stage: not recorded (%s)\n", notRecordedWhy);
        return out;
    }
    std::string whole, parts;
    for (const auto& [name, value] : stages) {
        std::string& list = isWholeStage(name) ? whole : parts;
        appendf(list, "%s%s %.3f s", list.empty() ? "" : ", ", name.c_str(), value);
    }
    appendf(out, "time per stage: %s; %.3f s in all\n", whole.c_str(), wholeStageSum(stages));
    if (!parts.empty()) appendf(out, "  parts of them, on their own threads (they may overlap): %s\n", parts.c_str());
    return out;
}

} // namespace yv
