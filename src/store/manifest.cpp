// The manifest's JSON (formats/brick-store.md, "Manifest"); file I/O is in brick_store.cpp.
#include "store/manifest.h"

#include "core/error.h"
#include "core/json_fields.h"
#include "core/text.h"

#include <climits>
#include <cmath>
#include <cstdio>

namespace yv {
namespace {

// 3: JSON (1 and 2 were text, "yarnvox brick store" on the first line).
constexpr std::int64_t kVersion = 3;
constexpr const char* kFormatName = "yarnvox work dir";
constexpr const char* kTextManifestTitle = "yarnvox brick store";

std::string num(double v) {
    char s[40];
    std::snprintf(s, sizeof s, "%.17g", v);
    return s;
}

VoxelGrid gridFromJson(const JsonFields& in, const std::string& where) {
    const JsonFields g(in.at("grid"), where + ": grid");
    g.onlyKeys({"origin", "voxel_size", "dims"});
    VoxelGrid grid;
    const std::vector<double> origin = g.numbers("origin", 3);
    grid.origin = {origin[0], origin[1], origin[2]};
    grid.voxelSize = g.number("voxel_size");
    const std::vector<std::int64_t> dims = g.integers("dims", 3, 0, INT32_MAX);
    grid.dims = {int(dims[0]), int(dims[1]), int(dims[2])};
    return grid;
}

} // namespace

StoreManifest parseManifest(const std::string& path, const std::string& text) {
    if (text.starts_with(kTextManifestTitle))
        throw Error(path + ": work dir written by an older yarnvox (manifest format): run without --resume, which "
                           "starts it over, or remove it");
    const Json json = parseJson(text, path);
    const JsonFields in(json, path);
    if (in.string("format") != kFormatName)
        in.fail("format", std::string("expected \"") + kFormatName + "\": not a yarnvox work dir manifest");
    if (const std::int64_t version = in.integer("version", 0, INT64_MAX); version != kVersion)
        in.fail("version", "unsupported work dir version " + std::to_string(version) + ": expected " +
                               std::to_string(kVersion) + " (written by another yarnvox version?)");
    in.onlyKeys({"format", "version", "yarnvox_version", "sampling_code", "fingerprint", "grid", "reduce", "run",
                 "complete_regions", "stage_seconds"});
    StoreManifest m;
    m.yarnvoxVersion = in.string("yarnvox_version");
    m.samplingCode = in.hex("sampling_code");
    m.fingerprint = in.hex("fingerprint");
    m.grid = gridFromJson(in, path);
    const std::string reduce = in.string("reduce");
    if (reduce != "mean" && reduce != "max") in.fail("reduce", "unknown reduce mode \"" + reduce + "\": expected mean or max");
    m.reduce = reduce == "max" ? Reduce::Max : Reduce::Mean;
    m.run = runMetadataFromJson(in.at("run"), path + ": run");
    if (in.has("complete_regions")) m.completeRegions = in.unsignedInteger("complete_regions");
    if (in.has("stage_seconds")) {
        if (!m.completeRegions) in.fail("stage_seconds", "recorded for a run that has not finished");
        m.stageSeconds = stageSecondsFromJson(in.at("stage_seconds"), path);
    }
    checkGrid(m.grid, path);
    return m;
}

void checkGrid(const VoxelGrid& g, const std::string& where) {
    const bool ok = std::isfinite(g.origin.x) && std::isfinite(g.origin.y) && std::isfinite(g.origin.z) &&
                    std::isfinite(g.voxelSize) && g.voxelSize > 0 && g.dims.x >= 0 && g.dims.y >= 0 && g.dims.z >= 0 &&
                    g.dims.x % 8 == 0 && g.dims.y % 8 == 0 && g.dims.z % 8 == 0;
    if (!ok)
        throw Error(where + ": invalid grid (origin " + num(g.origin.x) + " " + num(g.origin.y) + " " +
                    num(g.origin.z) + ", voxel size " + num(g.voxelSize) + ", dims " + coordText(g.dims) +
                    "): expected finite values, a positive voxel size and dims that are multiples of 8");
}

std::string formatManifest(const StoreManifest& m) {
    Json json = {{"format", kFormatName},
                 {"version", kVersion},
                 {"yarnvox_version", m.yarnvoxVersion},
                 {"sampling_code", hex64(m.samplingCode)},
                 {"fingerprint", hex64(m.fingerprint)},
                 {"grid",
                  {{"origin", {m.grid.origin.x, m.grid.origin.y, m.grid.origin.z}},
                   {"voxel_size", m.grid.voxelSize},
                   {"dims", {m.grid.dims.x, m.grid.dims.y, m.grid.dims.z}}}},
                 {"reduce", toString(m.reduce)},
                 {"run", runMetadataJson(m.run)}};
    if (m.completeRegions) {
        json["complete_regions"] = *m.completeRegions;
        json["stage_seconds"] = stageSecondsJson(m.stageSeconds);
    }
    return jsonText(json) + "\n";
}

bool sameGrid(const VoxelGrid& a, const VoxelGrid& b) {
    return a.origin == b.origin && a.voxelSize == b.voxelSize && a.dims == b.dims;
}

std::string runDifference(const StoreManifest& disk, const StoreManifest& now) {
    std::string d;
    const auto add = [&](const std::string& s) { d += (d.empty() ? "" : "; ") + s; };
    if (disk.yarnvoxVersion != now.yarnvoxVersion)
        add("made by yarnvox " + disk.yarnvoxVersion + ", this is " + now.yarnvoxVersion);
    else if (disk.samplingCode != now.samplingCode)
        add("the sampling code differs (" + hex64(disk.samplingCode) + " on disk, " + hex64(now.samplingCode) +
            " in this yarnvox): its regions may hold other values");
    else if (disk.fingerprint != now.fingerprint) {
        // A --bbox run resumed with another box (or none) is the likely reason.
        if (disk.run.bbox != now.run.bbox) {
            const auto box = [](const std::string& b) { return b.empty() ? std::string("the whole garment") : "box " + b; };
            add("made for " + box(disk.run.bbox) + ", this run asks for " + box(now.run.bbox) + " (voxels, max exclusive)");
        }
        // Where the runs name their backends, a change of backend is the likely reason.
        const std::string& before = disk.run.backend;
        const std::string& after = now.run.backend;
        if (!before.empty() && !after.empty() && before != after)
            add("made with --backend " + before + ", this run uses --backend " + after);
        add("fingerprint " + hex64(disk.fingerprint) + " on disk, " + hex64(now.fingerprint) + " for this run");
    }
    if (!sameGrid(disk.grid, now.grid))
        add("grid on disk has origin (" + num(disk.grid.origin.x) + ", " + num(disk.grid.origin.y) + ", " +
            num(disk.grid.origin.z) + "), voxel size " + num(disk.grid.voxelSize) + ", dims " + coordText(disk.grid.dims) +
            "; this run has origin (" + num(now.grid.origin.x) + ", " + num(now.grid.origin.y) + ", " +
            num(now.grid.origin.z) + "), voxel size " + num(now.grid.voxelSize) + ", dims " + coordText(now.grid.dims));
    if (disk.reduce != now.reduce)
        add(std::string("reduce ") + toString(disk.reduce) + " on disk, " + toString(now.reduce) + " for this run");
    return d;
}

} // namespace yv
