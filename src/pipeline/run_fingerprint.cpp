#include "pipeline/run_fingerprint.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/sampling.h"
#include "gpu/gl_program.h"
#include "store/brick_store.h"

#include <algorithm>
#include <cstring>
#include <optional>
#include <sstream>
#include <string_view>
#include <vector>

namespace yv {
namespace {

/// Order-sensitive mixing of 64-bit hashes.
class Fingerprint {
  public:
    void add(const void* data, std::size_t n) { h_ = xxh64(data, n) ^ (h_ * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull); }
    template <class T> void add(const T& v) { add(&v, sizeof v); }
    std::uint64_t value() const { return h_; }

  private:
    std::uint64_t h_ = 0;
};

} // namespace

std::uint64_t samplingCodeHash() {
    Fingerprint f;
    f.add(kCpuSamplingRuleVersion);
    // "common.glsl,slice.vert,...": the names CMake embeds, in its order.
    std::string_view names = YV_SHADER_NAMES;
    while (!names.empty()) {
        const std::size_t comma = std::min(names.find(','), names.size());
        const std::string name(names.substr(0, comma));
        names.remove_prefix(std::min(comma + 1, names.size()));
        // What is compiled: a YV_SHADER_DIR copy makes another run.
        const std::optional<std::string> text = shaderText(name);
        if (!text) throw Error("shader " + name + " is not embedded in this yarnvox (a build error)");
        f.add(name.data(), name.size());
        f.add(text->data(), text->size());
    }
    return f.value();
}

std::uint64_t runFingerprint(const std::string& inputPath, const SliceOptions& slices, const CrossSection& xs,
                             const VoxelGrid& grid, Reduce reduce, Overlap overlap, int supersample,
                             const ZoomPlan& zoom, const std::string& backend) {
    Fingerprint f;
    f.add(YV_VERSION, std::strlen(YV_VERSION));
    f.add(samplingCodeHash());
    // The backends agree to float precision, not bit for bit: one volume is made by one.
    f.add(backend.data(), backend.size());
    const std::optional<std::vector<std::uint8_t>> bytes = readWholeFile(inputPath);
    if (!bytes) throw Error(inputPath + ": cannot read the garment to fingerprint the run: it is gone");
    f.add(bytes->data(), bytes->size());
    f.add(slices.slicesPerSegment), f.add(slices.spacing), f.add(slices.twist), f.add(slices.radius);
    f.add(xs.size);
    f.add(xs.density.data(), xs.density.size());
    // --albedo makes other bricks (and region files); without it the hash is what it always was.
    if (xs.hasAlbedo()) f.add(xs.albedo.data(), xs.albedo.size() * sizeof(xs.albedo[0]));
    f.add(grid.origin), f.add(grid.voxelSize), f.add(grid.dims);
    f.add(static_cast<int>(reduce)), f.add(static_cast<int>(overlap)), f.add(supersample);
    for (const ZoomRegion& r : zoom.regions) f.add(r.id), f.add(r.min), f.add(r.max);
    return f.value();
}

std::string encodeMetadata(const VolumeMetadata& m) {
    std::ostringstream out;
    out.precision(17);
    out << "input=" << m.input << "\nbackend=" << m.backend << "\ncross_section=" << m.crossSection
        << "\nresolution=" << m.resolution << "\nslice_count=" << m.sliceCount << "\nyarn_radius=" << m.yarnRadius
        << "\nyarn_radius_source=" << m.yarnRadiusSource        << "\ntwist=" << m.twist << "\nsupersample=" << m.supersample << "\noverlap=" << m.overlap
        << "\nslice_spacing=" << m.sliceSpacing << "\nslices_per_segment=" << m.slicesPerSegment
        << "\nslice_spacing_option=" << m.sliceSpacingOption << "\nalbedo=" << (m.albedo ? 1 : 0) << "\n";
    return out.str();
}

VolumeMetadata decodeMetadata(const std::string& text) {
    VolumeMetadata m;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        const std::size_t eq = line.find('=');
        if (eq == std::string::npos) continue;
        const std::string key = line.substr(0, eq), value = line.substr(eq + 1);
        if (key == "input") m.input = value;
        else if (key == "backend") m.backend = value;
        else if (key == "cross_section") m.crossSection = value;
        else if (key == "resolution") m.resolution = std::stoi(value);
        else if (key == "slice_count") m.sliceCount = std::stoull(value);
        else if (key == "yarn_radius") m.yarnRadius = std::stod(value);
        else if (key == "yarn_radius_source") m.yarnRadiusSource = value;
        else if (key == "twist") m.twist = std::stod(value);
        else if (key == "supersample") m.supersample = std::stoi(value);
        else if (key == "overlap") m.overlap = value;
        else if (key == "slice_spacing") m.sliceSpacing = std::stod(value);
        else if (key == "slices_per_segment") m.slicesPerSegment = std::stoi(value);
        else if (key == "slice_spacing_option") m.sliceSpacingOption = std::stod(value);
        else if (key == "albedo") m.albedo = value == "1";
    }
    return m;
}

} // namespace yv
