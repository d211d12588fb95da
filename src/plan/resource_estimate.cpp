#include "plan/resource_estimate.h"

#include "core/bricks.h"

#include <glm/geometric.hpp>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>

namespace yv {
namespace {

/// Bytes a voxel takes in the .vdb at least: its density and its axis.
constexpr double kVdbBytesPerVoxel = 16.0;
/// The fibre texture leaves gaps between fibres: count a quarter of the disk.
constexpr double kLeastFill = 0.25;

double freeBytes(const std::string& dir) {
    struct statvfs fs {};
    if (statvfs(dir.empty() ? "." : dir.c_str(), &fs) != 0) return INFINITY; // cannot tell: do not refuse
    return double(fs.f_bavail) * double(fs.f_frsize);
}

std::string gigabytes(double bytes) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.3g GB", bytes / 1e9);
    return buf;
}

} // namespace

ResourceNeeds estimateNeeds(const Garment& garment, double radius, double h, bool halfPrecision) {
    double length = 0.0;
    for (const Yarn& y : garment.yarns) {
        for (std::size_t i = 1; i < y.points.size(); ++i) length += glm::distance(y.points[i - 1], y.points[i]);
        if (y.closed && y.points.size() > 2) length += glm::distance(y.points.back(), y.points.front());
    }
    ResourceNeeds n;
    n.activeVoxels = kLeastFill * M_PI * radius * radius * length / (h * h * h);
    n.outputBytes = n.activeVoxels * kVdbBytesPerVoxel * (halfPrecision ? 0.5 : 1.0);
    return n;
}

std::string checkNeeds(const ResourceNeeds& needs, const RunPlace& place, const std::string& scaleOption) {
    char count[32];
    std::snprintf(count, sizeof count, "%.3g", needs.activeVoxels);
    const std::string why = " (" + std::string(count) + " active voxels at least, from the yarns' length and radius); " +
                            "choose a coarser " + scaleOption.substr(0, scaleOption.find(' '));
    // The .vdb and its scratch file, plus the region files when they share the file system.
    const double outputFree = freeBytes(place.outputDir);
    double onOutput = 2.0 * needs.outputBytes;
    if (!place.workDir.empty()) {
        const double workFree = freeBytes(place.workDir);
        if (workFree == outputFree) onOutput += needs.outputBytes;
        else if (needs.outputBytes > workFree)
            return "the work dir " + place.workDir + " needs at least " + gigabytes(needs.outputBytes) + " with " +
                   scaleOption + ", its disk has " + gigabytes(workFree) + " free" + why;
    }
    if (onOutput > outputFree)
        return "the output needs at least " + gigabytes(onOutput) + " of disk in " +
               (place.outputDir.empty() ? std::string(".") : place.outputDir) + " with " + scaleOption +
               " (the .vdb and its scratch file), " + gigabytes(outputFree) + " are free" + why;
    return "";
}

} // namespace yv
