#include "inspect/run_slices.h"

#include "core/error.h"
#include "bcc.h"
#include "garment/curve_check.h"
#include "store/brick_store.h"

#include <openvdb/openvdb.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <sstream>

namespace yv {
namespace {

using Recorded = std::map<std::string, std::string>;

/// A work directory's run description (core/run_metadata.h).
Recorded storeRecord(const std::string& dir, VoxelGrid& grid) {
    const BrickStore store(dir);
    grid = store.manifest().grid;
    const auto fields = runMetadataText(store.manifest().run);
    return Recorded(fields.begin(), fields.end());
}

/// A .vdb's file metadata as text, and its grid from the density grid's transform.
Recorded vdbRecord(const std::string& path, VoxelGrid& grid) {
    openvdb::initialize();
    Recorded out;
    openvdb::io::File file(path);
    try {
        file.open(/*delayLoad=*/true);
        if (!file.hasGrid("density")) throw Error(path + ": has no float grid named 'density'");
        const openvdb::GridBase::Ptr density = file.readGridMetadata("density");
        const openvdb::math::Transform& t = density->transform();
        if (!t.isLinear()) throw Error(path + ": the density grid's transform is not linear: cannot place slices in it");
        grid.voxelSize = t.voxelSize().x();
        // yarnvox's transform maps voxel i to its centre, origin + (i + 0.5) h.
        const openvdb::Vec3d centre0 = t.indexToWorld(openvdb::Vec3d(0.0));
        grid.origin = glm::dvec3(centre0.x(), centre0.y(), centre0.z()) - 0.5 * grid.voxelSize;
        const openvdb::MetaMap::Ptr meta = file.getMetadata();
        for (auto it = meta->beginMeta(); it != meta->endMeta(); ++it) {
            // Metadata::str() keeps 6 digits; a radius or spacing wants all of them.
            if (const auto d = openvdb::DynamicPtrCast<openvdb::DoubleMetadata>(it->second)) {
                std::ostringstream text;
                text.precision(17);
                text << d->value();
                out[it->first] = text.str();
            } else {
                out[it->first] = it->second->str();
            }
        }
        // A .vdb says it has albedo by an item describing the grid's colour
        // (vdb/file_metadata.cpp); the manifest records the flag, as 1 or 0.
        if (out.count("albedo")) out["albedo"] = "1";
    } catch (const openvdb::Exception& e) {
        throw Error(path + ": not an OpenVDB file OpenVDB can read (" + e.what() + ")");
    }
    file.close();
    return out;
}

} // namespace

double recordedNumber(const std::map<std::string, std::string>& recorded, const std::string& key, double fallback,
                      const std::string& where) {
    const auto it = recorded.find(key);
    if (it == recorded.end()) return fallback;
    try {
        std::size_t used = 0;
        const double v = std::stod(it->second, &used);
        if (used == it->second.size()) return v;
    } catch (const std::exception&) {
    }
    throw Error(where + ": the recorded " + key + " '" + it->second + "' is not a number");
}

RunSlices loadRunSlices(const std::string& input, const RunSlicesOptions& options) {
    RunSlices out;
    const Recorded rec = std::filesystem::is_directory(input) ? storeRecord(input, out.grid) : vdbRecord(input, out.grid);
    if (!(out.grid.voxelSize > 0.0)) throw Error(input + ": no voxel size recorded: cannot place slices");
    out.garmentPath = options.garment;
    if (out.garmentPath.empty()) {
        const auto it = rec.find("input");
        if (it == rec.end() || it->second.empty())
            throw Error(input + ": names no garment (not made by yarnvox voxelize?): give --garment FILE.bcc");
        out.garmentPath = it->second;
        if (!std::filesystem::is_regular_file(out.garmentPath))
            throw Error(input + ": the run's garment " + out.garmentPath +
                        " is not there (generated, moved, or a relative path): give --garment FILE.bcc");
    }
    Garment garment = readBcc(out.garmentPath);
    // The run tidied the curves the same way before placing its slices.
    checkCurves(garment, out.garmentPath);

    SliceOptions opt;
    opt.radius = options.yarnRadius > 0.0 ? options.yarnRadius : recordedNumber(rec, "yarn_radius", garment.yarnRadius, input);
    if (!(opt.radius > 0.0))
        throw Error(input + ": no yarn radius recorded and " + out.garmentPath + " gives none: give --yarn-radius R");
    opt.twist = recordedNumber(rec, "twist", 0.0, input);
    const int supersample = int(recordedNumber(rec, "supersample", 1.0, input));
    opt.slicesPerSegment = int(recordedNumber(rec, "slices_per_segment", 0.0, input));
    opt.spacing = recordedNumber(rec, "slice_spacing_option", 0.0, input);
    if (!rec.count("slices_per_segment") && !rec.count("slice_spacing_option"))
        out.notes.push_back("slice placement not recorded (older run or foreign file): one slice per " +
                            std::string(supersample > 1 ? "supersampled " : "") + "voxel assumed");
    if (opt.slicesPerSegment <= 0 && opt.spacing <= 0.0) opt.spacing = defaultSliceSpacing(out.grid.voxelSize, std::max(1, supersample));
    out.recorded = rec;
    try {
        out.plan = planSlices(garment, opt);
    } catch (const Error& e) {
        throw Error(out.garmentPath + ": " + e.what());
    }
    return out;
}

} // namespace yv
