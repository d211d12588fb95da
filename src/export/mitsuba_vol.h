// Mitsuba's gridvolume files (.vol, version 3; formats/mitsuba-vol.md): a
// dense box of the sparse grids, density (1 channel) at OUT.vol and the fibre
// axis (3 channels) beside it at OUT.orientation.vol, optionally the SGGX
// matrices of fibre-like microflakes (6 channels) at OUT.sggx.vol, and the
// fibres' linear RGB albedo (3 channels) at OUT.albedo.vol when the .vdb has one.
#pragma once

#include "core/voxel_box.h"
#include "export/fiber_grids.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace yv {

/// The file's value encoding, numbered as in the header.
enum class VolEncoding : std::int32_t { Float32 = 1, Float16 = 2, UInt8 = 3 };
const char* toString(VolEncoding e);
/// "float32", "float16" or "uint8"; throws yv::Error otherwise.
VolEncoding parseVolEncoding(const std::string& name);
/// Bytes one channel of one voxel takes.
int encodingBytes(VolEncoding e);

/// What the header's bounding box spans: the outer faces of the exported
/// voxels (a voxel is a cell; Mitsuba 3 with use_grid_bbox), or the centres of
/// the first and last voxels (Mitsuba 0.6, which puts value 0 and value
/// res - 1 on the box's faces).
enum class VolBoxConvention { Corners, Centres };
VolBoxConvention parseVolBoxConvention(const std::string& name);

/// Every voxel whose cell overlaps the world-space box [lo, hi] (a voxel
/// touched only on a face is left out). Throws yv::Error when the grid's
/// transform is not an axis-aligned scale and translation, or the box is empty.
VoxelBox voxelBoxFromWorld(const openvdb::math::Transform& transform, glm::dvec3 lo, glm::dvec3 hi);

struct VolExportOptions {
    VolEncoding densityEncoding = VolEncoding::Float32;
    VolEncoding orientationEncoding = VolEncoding::Float32;
    VolEncoding albedoEncoding = VolEncoding::Float32;
    VolBoxConvention boxConvention = VolBoxConvention::Corners;
    std::optional<VoxelBox> box; ///< none: the bounds of the active voxels and one voxel around them
    double sggxRoughness = 0.0;  ///< above 0: also write OUT.sggx.vol with this sigma
};

struct VolExportResult {
    std::vector<std::string> paths; ///< density, then orientation, SGGX and albedo, as written
    VoxelBox box;
    glm::dvec3 worldMin{0.0}, worldMax{0.0}; ///< the header's bounding box
    std::uint64_t bytes = 0;                 ///< all files together
    std::uint64_t densityClamped = 0;        ///< uint8: voxels above 1 written as 255
};

/// OUT.orientation.vol, OUT.sggx.vol and OUT.albedo.vol beside OUT.vol ("garment.vol" ->
/// "garment.orientation.vol"); a name without ".vol" gets the suffix appended.
std::string volSiblingPath(const std::string& densityPath, const std::string& what);

/// The files an export with these options writes, density first.
std::vector<std::string> volOutputPaths(const std::string& densityPath, bool withOrientation,
                                        const VolExportOptions& options, bool withAlbedo = false);

/// Bytes of one .vol file: the 48-byte header and the dense values.
double volFileBytes(glm::ivec3 dims, int channels, VolEncoding e);

/// Writes the dense files for `options.box` (or the active voxels' bounds
/// grown by one voxel),
/// a few slices at a time, each to a temporary name, renamed into place only
/// when all are complete. Refuses before writing anything, naming the bytes
/// needed and the free space, when they do not fit the file system; throws
/// yv::Error when the volume is empty or a write fails (nothing is left behind).
VolExportResult exportMitsubaVol(const FiberGrids& grids, const std::string& densityPath,
                                 const VolExportOptions& options);

} // namespace yv
