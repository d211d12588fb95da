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
    // "bindings.glsl,layout.glsl,...": the names CMake embeds, in its order.
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
                             const ZoomPlan& zoom, const std::string& backend, const std::optional<VoxelBox>& box) {
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
    // Two boxes within the same bricks plan the same regions but keep other voxels.
    if (box) f.add(box->min), f.add(box->max);
    return f.value();
}

} // namespace yv
