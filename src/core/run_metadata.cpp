#include "core/run_metadata.h"

#include "core/error.h"
#include "core/json_fields.h"

#include <climits>
#include <cstdio>
#include <sstream>

namespace yv {
namespace {

/// A field of VolumeMetadata: its name and its member. The one list of the
/// fields: the JSON writer, its reader and the .vdb's items all follow it.
struct FieldSpec {
    const char* name;
    std::variant<std::string VolumeMetadata::*, int VolumeMetadata::*, std::uint64_t VolumeMetadata::*,
                 double VolumeMetadata::*, bool VolumeMetadata::*>
        member;
    /// Written only when not empty, and read as empty where missing: a field
    /// added for runs that have it, so the others keep their bytes.
    bool optional = false;
};

constexpr FieldSpec kFields[] = {
    {"input", &VolumeMetadata::input},
    {"backend", &VolumeMetadata::backend},
    {"cross_section", &VolumeMetadata::crossSection},
    {"resolution", &VolumeMetadata::resolution},
    {"slice_count", &VolumeMetadata::sliceCount},
    {"yarn_radius", &VolumeMetadata::yarnRadius},
    {"yarn_radius_source", &VolumeMetadata::yarnRadiusSource},
    {"twist", &VolumeMetadata::twist},
    {"supersample", &VolumeMetadata::supersample},
    {"overlap", &VolumeMetadata::overlap},
    {"slice_spacing", &VolumeMetadata::sliceSpacing},
    {"slices_per_segment", &VolumeMetadata::slicesPerSegment},
    {"slice_spacing_option", &VolumeMetadata::sliceSpacingOption},
    {"albedo", &VolumeMetadata::albedo},
    {"bbox", &VolumeMetadata::bbox, true},
};

template <class... F> struct Overloaded : F... {
    using F::operator()...;
};
template <class... F> Overloaded(F...) -> Overloaded<F...>; // clang 14 deduces no aggregates

} // namespace

std::vector<MetadataField> metadataFields(const VolumeMetadata& m) {
    std::vector<MetadataField> out;
    for (const FieldSpec& f : kFields)
        std::visit(Overloaded{[&](std::string VolumeMetadata::*p) {
                                  if (!f.optional || !(m.*p).empty()) out.push_back({f.name, m.*p});
                              },
                              // The .vdb's types: int32 for ints, int64 for the slice count.
                              [&](int VolumeMetadata::*p) { out.push_back({f.name, std::int32_t(m.*p)}); },
                              [&](std::uint64_t VolumeMetadata::*p) { out.push_back({f.name, std::int64_t(m.*p)}); },
                              [&](double VolumeMetadata::*p) { out.push_back({f.name, m.*p}); },
                              [&](bool VolumeMetadata::*p) { out.push_back({f.name, m.*p}); }},
                   f.member);
    return out;
}

Json runMetadataJson(const VolumeMetadata& m) {
    Json out = Json::object();
    for (const MetadataField& f : metadataFields(m)) std::visit([&](const auto& v) { out[f.name] = v; }, f.value);
    return out;
}

VolumeMetadata runMetadataFromJson(const Json& json, const std::string& where) {
    const JsonFields in(json, where);
    VolumeMetadata m;
    for (const FieldSpec& f : kFields) {
        if (f.optional && !json.contains(f.name)) continue;
        std::visit(Overloaded{[&](std::string VolumeMetadata::*p) { m.*p = in.string(f.name); },
                              [&](int VolumeMetadata::*p) { m.*p = int(in.integer(f.name, INT32_MIN, INT32_MAX)); },
                              [&](std::uint64_t VolumeMetadata::*p) {
                                  m.*p = std::uint64_t(in.integer(f.name, 0, INT64_MAX));
                              },
                              [&](double VolumeMetadata::*p) { m.*p = in.number(f.name); },
                              [&](bool VolumeMetadata::*p) { m.*p = in.boolean(f.name); }},
                   f.member);
    }
    for (const auto& [key, value] : json.items())
        if (!isRunMetadataField(key)) in.fail(key, "no such field of a run's description");
    return m;
}

bool isRunMetadataField(const std::string& name) {
    for (const FieldSpec& f : kFields)
        if (name == f.name) return true;
    return false;
}

std::vector<std::pair<std::string, std::string>> runMetadataText(const VolumeMetadata& m) {
    std::vector<std::pair<std::string, std::string>> out;
    for (const MetadataField& f : metadataFields(m))
        out.emplace_back(f.name, std::visit(Overloaded{[](const std::string& s) { return s; },
                                                       [](std::int32_t v) { return std::to_string(v); },
                                                       [](std::int64_t v) { return std::to_string(v); },
                                                       [](bool v) { return std::string(v ? "1" : "0"); },
                                                       [](double v) {
                                                           char text[40];
                                                           std::snprintf(text, sizeof text, "%.17g", v);
                                                           return std::string(text);
                                                       }},
                                            f.value));
    return out;
}

std::string encodeRegions(const std::vector<RecordedRegion>& regions) {
    std::string out;
    for (const RecordedRegion& r : regions) {
        if (!out.empty()) out += ';';
        out += std::to_string(r.id);
        for (const int v : {r.min.x, r.min.y, r.min.z, r.max.x, r.max.y, r.max.z}) out += ' ' + std::to_string(v);
        out += ' ' + std::to_string(r.activeVoxels);
    }
    return out;
}

std::vector<RecordedRegion> decodeRegions(const std::string& text, const std::string& where) {
    std::vector<RecordedRegion> out;
    std::istringstream entries(text);
    for (std::string entry; std::getline(entries, entry, ';');) {
        std::istringstream in(entry);
        RecordedRegion r;
        std::string rest;
        in >> r.id >> r.min.x >> r.min.y >> r.min.z >> r.max.x >> r.max.y >> r.max.z >> r.activeVoxels;
        const bool bad = in.fail() || (in >> rest, !rest.empty());
        if (bad || r.max.x <= r.min.x || r.max.y <= r.min.y || r.max.z <= r.min.z)
            throw Error(where + ": region entry " + std::to_string(out.size() + 1) + " '" + entry +
                        "' is not 'ID MINX MINY MINZ MAXX MAXY MAXZ ACTIVE' with min below max");
        out.push_back(r);
    }
    return out;
}

} // namespace yv
