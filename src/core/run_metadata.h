// What a voxelize run records about itself for later readers (merge,
// inspect, export): its description (VolumeMetadata) and the zoom regions a
// .vdb lists. One writer and one reader of each, here: a work dir's manifest
// keeps the description as JSON (runMetadataJson); a .vdb keeps the same
// fields as OpenVDB metadata items (metadataFields, vdb/file_metadata.h) and
// its regions as one string item (encodeRegions), both byte for byte as
// yarnvox has always written them (formats/vdb-subset.md).
#pragma once

#include <glm/vec3.hpp>
#include <nlohmann/json_fwd.hpp>

#include <cstdint>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace yv {

/// One zoom region as a .vdb records it: its voxel box (min inclusive, max
/// exclusive) and its heat.
struct RecordedRegion {
    std::uint64_t id = 0;
    glm::ivec3 min{0}, max{0};
    std::uint64_t activeVoxels = 0;
    bool operator==(const RecordedRegion&) const = default;
};

/// The description of a voxelize run.
struct VolumeMetadata {
    std::string input;        ///< garment file or generator description
    std::string backend;      ///< "cpu" or "gl"
    std::string crossSection; ///< "fibers", "disk" or a PNG path
    int resolution = 0;       ///< voxels on the longest axis asked for (0: from voxel size)
    std::uint64_t sliceCount = 0;
    double yarnRadius = 0.0;
    std::string yarnRadiusSource;  ///< "option", "cross-section", "file" or "estimated"
    double twist = 0.0;
    int supersample = 1;
    std::string overlap = "clamp"; ///< how interpenetrating yarns add up (mean reduction)
    double sliceSpacing = 0.0;     ///< largest distance between slices along a yarn, world units
    int slicesPerSegment = 0;      ///< --slices-per-segment as asked (0: not asked)
    double sliceSpacingOption = 0.0; ///< --slice-spacing as asked (0: one slice per supersampled voxel)
    bool albedo = false;           ///< --albedo: the bricks carry the fibres' colour (an "albedo" grid)
    /// --bbox: "i0,j0,k0,i1,j1,k1", the voxels the run voxelized (max
    /// exclusive); empty for the whole garment, and then not recorded at all.
    std::string bbox;
    /// The run's zoom regions, sorted by id, written as the density grid's
    /// "yarnvox_regions" metadata (none: no item). Not part of the run's
    /// description: the writer of the .vdb fills it in.
    std::vector<RecordedRegion> regions;
};

/// A field's value, of the type the .vdb stores it as (OpenVDB's string,
/// int32, int64, double metadata; albedo, a bool, only in the manifest).
using MetadataValue = std::variant<std::string, std::int32_t, std::int64_t, double, bool>;

struct MetadataField {
    const char* name;
    MetadataValue value;
    bool operator==(const MetadataField& o) const { return std::string(name) == o.name && value == o.value; }
};

/// The run's description, field by field (regions apart), in the order the
/// manifest keeps them: input, backend, cross_section, resolution,
/// slice_count, yarn_radius, yarn_radius_source, twist, supersample, overlap,
/// slice_spacing, slices_per_segment, slice_spacing_option, albedo, and bbox
/// where the run had a box (a whole run's fields are what they always were).
std::vector<MetadataField> metadataFields(const VolumeMetadata& m);

/// Whether `name` is a field of the run's description (metadataFields).
bool isRunMetadataField(const std::string& name);

/// The description as a JSON object of metadataFields.
nlohmann::ordered_json runMetadataJson(const VolumeMetadata& m);
/// The description runMetadataJson wrote; throws yv::Error naming `where`
/// and the field when a field is missing (bbox may be), unknown or of another type.
VolumeMetadata runMetadataFromJson(const nlohmann::ordered_json& json, const std::string& where);

/// The fields as text, for people (inspect): numbers as C's "%.17g" (every
/// digit of a double), albedo as 1 or 0.
std::vector<std::pair<std::string, std::string>> runMetadataText(const VolumeMetadata& m);

/// The density grid's metadata item that holds the regions.
inline constexpr const char* kRegionsMetadataName = "yarnvox_regions";

/// "ID MINX MINY MINZ MAXX MAXY MAXZ ACTIVE" per region, in the order given,
/// joined by ';': the same regions give the same string.
std::string encodeRegions(const std::vector<RecordedRegion>& regions);
/// The regions of an encodeRegions string; throws yv::Error naming `where`
/// and the bad entry when it is malformed.
std::vector<RecordedRegion> decodeRegions(const std::string& text, const std::string& where);

} // namespace yv
