#include "vdb/file_metadata.h"

#include "core/json_fields.h"

#include <cstring>

namespace yv {

openvdb::MetaMap vdbFileMetadata(const VolumeMetadata& metadata, const VoxelGrid& grid, Reduce reduce, int lodLevels,
                                 int lodFirstLevel, bool albedo) {
    openvdb::MetaMap meta;
    meta.insertMeta("yarnvox_version", openvdb::StringMetadata(YV_VERSION));
    for (const MetadataField& field : metadataFields(metadata)) {
        // The albedo grids say whether the run had albedo: the flag itself is the manifest's.
        if (std::strcmp(field.name, "albedo") == 0) continue;
        if (const auto* s = std::get_if<std::string>(&field.value)) meta.insertMeta(field.name, openvdb::StringMetadata(*s));
        if (const auto* i = std::get_if<std::int32_t>(&field.value)) meta.insertMeta(field.name, openvdb::Int32Metadata(*i));
        if (const auto* l = std::get_if<std::int64_t>(&field.value)) meta.insertMeta(field.name, openvdb::Int64Metadata(*l));
        if (const auto* d = std::get_if<double>(&field.value)) meta.insertMeta(field.name, openvdb::DoubleMetadata(*d));
    }
    meta.insertMeta("voxel_size", openvdb::DoubleMetadata(grid.voxelSize));
    meta.insertMeta("reduce", openvdb::StringMetadata(toString(reduce)));
    meta.insertMeta("grid_dims", openvdb::Vec3IMetadata(openvdb::Vec3i(grid.dims.x, grid.dims.y, grid.dims.z)));
    if (lodLevels > 0) meta.insertMeta("lod_levels", openvdb::Int32Metadata(lodLevels));
    if (lodLevels > 0 && lodFirstLevel != 1) meta.insertMeta("lod_first_level", openvdb::Int32Metadata(lodFirstLevel));
    if (albedo) meta.insertMeta("albedo", openvdb::StringMetadata("linear RGB, density-weighted mean"));
    return meta;
}

VolumeMetadata vdbRunMetadata(const openvdb::MetaMap& meta, const std::string& where) {
    Json fields = runMetadataJson(VolumeMetadata{});
    for (auto it = meta.beginMeta(); it != meta.endMeta(); ++it) {
        const std::string& name = it->first;
        if (!isRunMetadataField(name) || name == "albedo") continue;
        const openvdb::Metadata& item = *it->second;
        if (const auto* s = dynamic_cast<const openvdb::StringMetadata*>(&item)) fields[name] = s->value();
        else if (const auto* i = dynamic_cast<const openvdb::Int32Metadata*>(&item)) fields[name] = i->value();
        else if (const auto* l = dynamic_cast<const openvdb::Int64Metadata*>(&item)) fields[name] = l->value();
        else if (const auto* d = dynamic_cast<const openvdb::DoubleMetadata*>(&item)) fields[name] = d->value();
        else fields[name] = nullptr; // a type yarnvox never writes: refused below, by name
    }
    fields["albedo"] = meta["albedo"] != nullptr;
    return runMetadataFromJson(fields, where);
}

} // namespace yv
