#include "plan/resource_estimate.h"

#include "core/bricks.h"
#include "core/world_units.h"

#include <glm/geometric.hpp>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

namespace yv {
namespace {

/// Bytes a voxel takes in the .vdb at least: its density and its axis.
constexpr double kVdbBytesPerVoxel = 16.0;
/// The fibre texture leaves gaps between fibres: count a quarter of the disk.
constexpr double kLeastFill = 0.25;

/// A leaf's mask, origin and header over the voxels it holds, per grid (the
/// .vdb files measured held 17.6 to 18.2 bytes per voxel for 16 of values).
constexpr double kLeafBytesPerVoxel = 1.0;
/// Room left beside the expected output: its error, and whatever else writes to the disk meanwhile.
constexpr double kDiskMargin = 0.05;
constexpr double kDiskMarginBytes = 1e6;

/// `dir`, or the nearest directory above it that exists: a work dir not
/// made yet will lie on its parent's file system.
std::string existingDir(const std::string& dir) {
    std::filesystem::path p = dir.empty() ? "." : dir;
    std::error_code ec;
    while (!std::filesystem::is_directory(p, ec) && p.has_parent_path() && p != p.parent_path()) p = p.parent_path();
    return std::filesystem::is_directory(p, ec) ? p.string() : ".";
}

double freeBytes(const std::string& dir) {
    // Tests stand a small disk in for the real one (resource_estimate.h).
    if (const char* test = std::getenv("YARNVOX_TEST_FREE_BYTES")) return std::strtod(test, nullptr);
    struct statvfs fs {};
    if (statvfs(existingDir(dir).c_str(), &fs) != 0) return INFINITY; // cannot tell: do not refuse
    return double(fs.f_bavail) * double(fs.f_frsize);
}

/// Whether the two directories' files take from one file system's free space.
bool sameFileSystem(const std::string& a, const std::string& b) {
    struct stat sa {}, sb {};
    return ::stat(existingDir(a).c_str(), &sa) == 0 && ::stat(existingDir(b).c_str(), &sb) == 0 && sa.st_dev == sb.st_dev;
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
        if (sameFileSystem(place.workDir, place.outputDir)) onOutput += needs.outputBytes;
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

double grownFibreArea(const CrossSection& xs, double radius, double h) {
    const int n = xs.size;
    const double texel = 2.0 * radius / n;
    const int grow = static_cast<int>(std::lround(h / texel)); // texels a voxel face spans
    if (n == 0 || xs.analyticDisk || grow > 4 * n) return M_PI * radius * radius + 4.0 * radius * h + h * h;
    // The fibre mask dilated by a square of `grow` texels: first along rows,
    // then along columns, on a grid padded by the growth.
    const int m = n + grow;
    const auto grown = [grow](const std::vector<char>& in, int width, int height, bool alongRows) {
        std::vector<char> out(in.size(), 0);
        for (int line = 0; line < (alongRows ? height : width); ++line)
            for (int i = 0, last = -1 - grow; i < (alongRows ? width : height); ++i) {
                const std::size_t at = alongRows ? std::size_t(line) * width + i : std::size_t(i) * width + line;
                if (in[at]) last = i;
                out[at] = i - last <= grow;
            }
        return out;
    };
    std::vector<char> mask(std::size_t(m) * m, 0);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) mask[std::size_t(y) * m + x] = xs.density[std::size_t(y) * n + x] != 0;
    const std::vector<char> both = grown(grown(mask, m, m, true), m, m, false);
    const double texels = double(std::count(both.begin(), both.end(), 1));
    return texels * texel * texel;
}

ExpectedOutput expectOutput(const OutputPlan& run) {
    const double h = run.voxelSize;
    const double area = run.xs ? grownFibreArea(*run.xs, run.radius, h)
                               : M_PI * run.radius * run.radius + 4.0 * run.radius * h + h * h;
    const VdbShape& shape = run.shape;
    const int grids = shape.albedo ? 3 : 2;
    const double values = shape.albedo ? 28.0 : 16.0; // density, axis (and colour) as floats
    double levels = 1.0; // each coarser level holds about a quarter of the voxels of the one before
    for (int l = std::max(1, shape.lodFirstLevel); l <= shape.lodLevels; ++l) levels += std::pow(0.25, l);
    ExpectedOutput e;
    e.activeVoxels = run.yarnLength * area / (h * h * h);
    e.vdbBytes = e.activeVoxels * levels * (values * (shape.halfPrecision ? 0.5 : 1.0) + kLeafBytesPerVoxel * grids);
    e.regionBytes = e.activeVoxels * (values + kLeafBytesPerVoxel * grids);
    return e;
}

OutputPlan outputPlan(const SlicePlan& plan, const VoxelGrid& grid, const CrossSection& xs, const VdbShape& shape) {
    OutputPlan run;
    run.yarnLength = plan.yarnLength;
    run.radius = plan.options.radius;
    run.voxelSize = grid.voxelSize;
    run.xs = &xs;
    run.shape = shape;
    return run;
}

namespace {

/// What the expected output takes of the output's file system, and of the
/// work dir's where that is another, against what they have free.
struct DiskUse {
    double onOutput = 0.0, outputFree = 0.0;
    double onWorkDir = 0.0, workDirFree = 0.0; ///< 0, 0: no work dir of its own

    DiskUse(const OutputPlan& run, const RunPlace& place) {
        const ExpectedOutput e = expectOutput(run);
        outputFree = freeBytes(place.outputDir);
        onOutput = 2.0 * e.vdbBytes; // the .vdb and its scratch file, both whole at the end
        if (place.workDir.empty()) return;
        const double workFree = freeBytes(place.workDir);
        if (sameFileSystem(place.workDir, place.outputDir)) {
            onOutput += e.regionBytes;
        } else {
            onWorkDir = e.regionBytes;
            workDirFree = workFree;
        }
    }
    static bool fits(double need, double free) { return need * (1.0 + kDiskMargin) + kDiskMarginBytes <= free; }
    bool fits() const { return fits(onOutput, outputFree) && (onWorkDir == 0.0 || fits(onWorkDir, workDirFree)); }
};

/// What to change: half precision where that alone fits, and the grid that
/// fits (voxels the given factor coarser, found by bisection: the expected
/// bytes fall as the voxels grow).
std::string whatToChange(const OutputPlan& run, const RunPlace& place, const std::string& scaleOption) {
    std::string advice;
    if (!run.shape.halfPrecision) {
        OutputPlan half = run;
        half.shape.halfPrecision = true;
        if (DiskUse(half, place).fits()) advice = "--precision half (16-bit values) fits; or ";
    }
    const auto fitsAt = [&](double factor) {
        OutputPlan coarser = run;
        coarser.voxelSize = run.voxelSize * factor;
        return DiskUse(coarser, place).fits();
    };
    const std::string freeSome = "free some space: no grid of this garment fits";
    double lo = 1.0, hi = 1e3; // factors on the voxel size: lo does not fit, hi does
    if (!fitsAt(hi)) return advice + freeSome;
    for (int i = 0; i < 80 && hi / lo > 1.0001; ++i) {
        const double mid = std::sqrt(lo * hi);
        (fitsAt(mid) ? hi : lo) = mid;
    }
    const std::string option = scaleOption.substr(0, scaleOption.find(' '));
    if (option == "--resolution") {
        const long long fitting = static_cast<long long>(std::floor(std::atoll(scaleOption.c_str() + option.size()) / hi));
        return advice + (fitting < 8 ? freeSome : "--resolution " + std::to_string(fitting) + " or lower");
    }
    return advice + "--voxel-size " + numberText(run.voxelSize * hi) + " or coarser";
}

} // namespace

std::string checkExpectedDisk(const OutputPlan& run, const RunPlace& place, const std::string& scaleOption) {
    const DiskUse use(run, place);
    if (use.fits()) return "";
    const ExpectedOutput e = expectOutput(run);
    char voxels[32];
    std::snprintf(voxels, sizeof voxels, "%.3g", e.activeVoxels);
    const bool onOutput = !DiskUse::fits(use.onOutput, use.outputFree);
    const std::string where = onOutput ? (place.outputDir.empty() ? std::string(".") : place.outputDir) : place.workDir;
    const std::string what = onOutput ? "the .vdb (" + gigabytes(e.vdbBytes) + ") and its scratch file" +
                                            (use.onOutput > 2.0 * e.vdbBytes ? std::string(" and the work dir's regions") : "")
                                      : "the work dir's region files";
    return "with " + scaleOption + " the run is expected to write " + gigabytes(onOutput ? use.onOutput : use.onWorkDir) +
           " (" + what + ", " + voxels + " active voxels) in " + where + ", whose file system has " +
           gigabytes(onOutput ? use.outputFree : use.workDirFree) + " free, less a 5 % margin: nothing was voxelized; " +
           whatToChange(run, place, scaleOption);
}

} // namespace yv
