#include "pipeline/preview_slices.h"

#include "bcc.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "garment/cross_section.h"
#include "garment/curve_check.h"
#include "pipeline/run_fingerprint.h"
#include "pipeline/yarn_radius.h"
#include "store/manifest.h"

#include <openvdb/openvdb.h>

#include <filesystem>

namespace yv {
namespace {

namespace fs = std::filesystem;

/// The garment, its radius and its slices; `voxelSize` sets the default spacing.
SlicePlan planPreview(Garment& garment, const std::string& path, const PreviewSliceOptions& o, double radius, double voxelSize,
                      int supersample) {
    SliceOptions s;
    s.radius = radius;
    s.slicesPerSegment = o.slicesPerSegment;
    s.spacing = o.slicesPerSegment > 0 ? 0.0 : o.spacing > 0.0 ? o.spacing : defaultSliceSpacing(voxelSize, supersample);
    try {
        return planSlices(garment, s);
    } catch (const Error& e) {
        throw Error(path + ": " + e.what());
    }
}

Garment readGarment(const std::string& path) {
    Garment garment = readBcc(path);
    checkCurves(garment, path);
    return garment;
}

/// The recorded input, as given, or beside the volume when it was relative.
std::string findGarment(const std::string& recorded, const std::string& volumePath) {
    const std::string ask = " (give the garment: yarnvox inspect GARMENT.bcc --render volumetric-triangles)";
    if (recorded.empty()) throw Error(volumePath + ": records no garment it was made from" + ask);
    if (fs::is_regular_file(recorded)) return recorded;
    const fs::path beside = fs::path(volumePath).parent_path() / fs::path(recorded).filename();
    if (fs::is_regular_file(beside)) return beside.string();
    throw Error(volumePath + ": made from " + recorded + ", which is not there" + ask);
}

/// Mean density of `xs` over the unit disk (texel centres inside it).
double diskMean(const CrossSection& xs) {
    double sum = 0.0;
    int n = 0;
    for (int y = 0; y < xs.size; ++y)
        for (int x = 0; x < xs.size; ++x) {
            const double u = (x + 0.5) / xs.size * 2.0 - 1.0, v = (y + 0.5) / xs.size * 2.0 - 1.0;
            if (u * u + v * v > 1.0) continue;
            sum += xs.density[std::size_t(y) * std::size_t(xs.size) + std::size_t(x)] / 255.0;
            ++n;
        }
    return n ? sum / n : 1.0;
}

} // namespace

PreviewSlices garmentPreviewSlices(const std::string& path, const PreviewSliceOptions& o) {
    PreviewSlices p;
    p.garment = path;
    Garment garment = readGarment(path);
    const CrossSection xs = makeCrossSection(o.crossSection.empty() ? "fibers" : o.crossSection);
    p.yarnDensity = diskMean(xs);
    const YarnRadiusChoice radius = chooseYarnRadius(o.yarnRadius, xs, garment, path);
    const int resolution = o.resolution > 0 ? o.resolution : kPreviewResolution;
    const double voxelSize = voxelSizeFor(garment, radius.radius, resolution, 0.0);
    p.plan = planPreview(garment, path, o, radius.radius, voxelSize, 1);
    p.grid = makeGrid(p.plan, resolution, 0.0);
    return p;
}

PreviewSlices volumePreviewSlices(const std::string& volumePath, const PreviewSliceOptions& o) {
    VolumeMetadata meta;
    VoxelGrid grid;
    if (fs::is_directory(volumePath)) {
        const std::string manifestPath = (fs::path(volumePath) / "manifest").string();
        const auto bytes = readWholeFile(manifestPath);
        if (!bytes) throw Error(volumePath + ": not a work directory (no manifest)");
        const StoreManifest m = parseManifest(manifestPath, std::string(bytes->begin(), bytes->end()));
        meta = m.run;
        grid = m.grid;
    } else {
        openvdb::initialize();
        try {
            openvdb::io::File file(volumePath);
            file.open(false);
            const openvdb::MetaMap::Ptr fileMeta = file.getMetadata();
            const openvdb::GridBase::Ptr density = file.readGridMetadata("density");
            file.close();
            if (!fileMeta->metaValue<std::string>("yarnvox_version").size())
                throw Error(volumePath + ": not made by yarnvox");
            meta.input = fileMeta->metaValue<std::string>("input");
            meta.crossSection = fileMeta->metaValue<std::string>("cross_section");
            meta.yarnRadius = fileMeta->metaValue<double>("yarn_radius");
            meta.supersample = fileMeta->metaValue<int>("supersample");
            grid.voxelSize = fileMeta->metaValue<double>("voxel_size");
            const openvdb::Vec3i dims = fileMeta->metaValue<openvdb::Vec3i>("grid_dims");
            grid.dims = {dims.x(), dims.y(), dims.z()};
            // Voxel (0, 0, 0)'s centre is the transform's image of index 0.
            const openvdb::Vec3d centre = density->transform().indexToWorld(openvdb::Vec3d(0.0));
            grid.origin = glm::dvec3(centre.x(), centre.y(), centre.z()) - 0.5 * grid.voxelSize;
        } catch (const Error&) {
            throw;
        } catch (const std::exception& e) {
            throw Error(volumePath + ": no yarnvox metadata to find the garment by (" + e.what() +
                        "; give the garment: yarnvox inspect GARMENT.bcc --render volumetric-triangles)");
        }
    }
    PreviewSlices p;
    p.garment = findGarment(meta.input, volumePath);
    const std::string xsName = !o.crossSection.empty() ? o.crossSection : !meta.crossSection.empty() ? meta.crossSection : "fibers";
    try {
        p.yarnDensity = diskMean(makeCrossSection(xsName));
    } catch (const Error& e) {
        throw Error(volumePath + ": its cross-section " + xsName + ": " + e.what() + " (give --cross-section)");
    }
    Garment garment = readGarment(p.garment);
    const double radius = o.yarnRadius > 0.0 ? o.yarnRadius : meta.yarnRadius;
    if (!(radius > 0.0)) throw Error(volumePath + ": records no yarn radius (give --yarn-radius)");
    p.plan = planPreview(garment, p.garment, o, radius, grid.voxelSize, std::max(1, meta.supersample));
    p.grid = grid;
    return p;
}

} // namespace yv
