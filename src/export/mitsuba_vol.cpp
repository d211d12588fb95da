#include "export/mitsuba_vol.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/text.h"

#include <openvdb/tools/Dense.h>
#include <tbb/parallel_for.h>

#include <glm/vector_relational.hpp>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>

namespace yv {
namespace {

static_assert(std::endian::native == std::endian::little, "the .vol writer stores values as they lie in memory");

/// Voxels converted per piece: bounds the memory of an export of any size.
constexpr std::size_t kPieceVoxels = std::size_t(1) << 22;

std::string bytesText(double bytes) {
    char s[32];
    if (bytes >= 1e12) std::snprintf(s, sizeof s, "%.2f TB", bytes / 1e12);
    else if (bytes >= 1e9) std::snprintf(s, sizeof s, "%.2f GB", bytes / 1e9);
    else if (bytes >= 1e6) std::snprintf(s, sizeof s, "%.2f MB", bytes / 1e6);
    else std::snprintf(s, sizeof s, "%.0f bytes", bytes);
    return s;
}

std::string dimsText(glm::ivec3 d) {
    return std::to_string(d.x) + " x " + std::to_string(d.y) + " x " + std::to_string(d.z);
}

/// The index-to-world map as a per-axis scale and offset: world = offset + scale * index.
struct AxisMap {
    glm::dvec3 scale{1.0}, offset{0.0};
};

AxisMap axisMap(const openvdb::math::Transform& transform) {
    const openvdb::math::MapBase::ConstPtr map = transform.baseMap();
    if (!map->isLinear())
        throw Error("the grid's transform (" + map->type() + ") is not linear: a .vol box cannot hold it");
    const openvdb::Mat4d m = map->getAffineMap()->getMat4();
    AxisMap a;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            if (r != c && m(r, c) != 0.0)
                throw Error("the grid's transform rotates or shears the voxels: a .vol box is axis-aligned");
    for (int i = 0; i < 3; ++i) {
        a.scale[i] = m(i, i);
        a.offset[i] = m(3, i);
        if (!(a.scale[i] > 0.0)) throw Error("the grid's transform mirrors or flattens an axis: a .vol box cannot hold it");
    }
    return a;
}

void appendHeader(PendingFile& out, VolEncoding e, glm::ivec3 dims, int channels, glm::dvec3 lo, glm::dvec3 hi) {
    std::uint8_t h[48];
    h[0] = 'V', h[1] = 'O', h[2] = 'L', h[3] = 3;
    const std::int32_t ints[5] = {std::int32_t(e), dims.x, dims.y, dims.z, channels};
    std::memcpy(h + 4, ints, sizeof ints);
    const float box[6] = {float(lo.x), float(lo.y), float(lo.z), float(hi.x), float(hi.y), float(hi.z)};
    std::memcpy(h + 24, box, sizeof box);
    out.append(h, sizeof h);
}

std::uint8_t densityByte(float d) { return std::uint8_t(std::lround(std::clamp(d, 0.0f, 1.0f) * 255.0f)); }
/// [-1, 1] to 1..255 with 0 at 128, so the zero vector of empty voxels stays exact.
std::uint8_t componentByte(float c) { return std::uint8_t(128 + std::lround(std::clamp(c, -1.0f, 1.0f) * 127.0f)); }

void putValue(std::uint8_t* at, VolEncoding e, float v, bool isComponent) {
    switch (e) {
    case VolEncoding::Float32: std::memcpy(at, &v, 4); break;
    case VolEncoding::Float16: {
        const openvdb::math::half h(v);
        const std::uint16_t bits = h.bits();
        std::memcpy(at, &bits, 2);
        break;
    }
    case VolEncoding::UInt8: *at = isComponent ? componentByte(v) : densityByte(v); break;
    }
}

/// The pieces of a box in file order: whole z slices when one fits a piece,
/// else bands of y rows inside one slice.
template <typename Fn> void forEachPiece(const VoxelBox& box, Fn&& fn) {
    const glm::ivec3 d = box.dims();
    const std::size_t slice = std::size_t(d.x) * std::size_t(d.y);
    if (slice <= kPieceVoxels) {
        const int step = int(std::max<std::size_t>(1, kPieceVoxels / slice));
        for (int z = box.min.z; z < box.max.z; z += step)
            fn(openvdb::CoordBBox(openvdb::Coord(box.min.x, box.min.y, z),
                                  openvdb::Coord(box.max.x - 1, box.max.y - 1, std::min(z + step, box.max.z) - 1)));
        return;
    }
    const int rows = int(std::max<std::size_t>(1, kPieceVoxels / std::size_t(d.x)));
    for (int z = box.min.z; z < box.max.z; ++z)
        for (int y = box.min.y; y < box.max.y; y += rows)
            fn(openvdb::CoordBBox(openvdb::Coord(box.min.x, y, z),
                                  openvdb::Coord(box.max.x - 1, std::min(y + rows, box.max.y) - 1, z)));
}

/// Streams one grid's values over `box` into `out`: `channels` values per
/// voxel, made from the grid's value by `values(value, float* out)`.
template <typename GridT, typename ValuesFn>
void appendValues(PendingFile& out, const GridT& grid, const VoxelBox& box, int channels, VolEncoding e,
                  bool isComponent, ValuesFn&& values) {
    using ValueT = typename GridT::ValueType;
    const int bytes = encodingBytes(e);
    std::vector<std::uint8_t> buffer;
    forEachPiece(box, [&](const openvdb::CoordBBox& piece) {
        // Under an InterruptScope, SIGINT or SIGTERM stops between pieces; the temporaries go with the exception.
        throwIfInterrupted("while writing " + out.path() + ": nothing was written; run the command again");
        signalAtTestPoint("vol-piece");
        openvdb::tools::Dense<ValueT, openvdb::tools::LayoutXYZ> dense(piece);
        openvdb::tools::copyToDense(grid, dense);
        const std::size_t n = dense.valueCount();
        buffer.resize(n * std::size_t(channels) * std::size_t(bytes));
        const ValueT* src = dense.data();
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const tbb::blocked_range<std::size_t>& r) {
            float v[6] = {};
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                values(src[i], v);
                std::uint8_t* at = buffer.data() + i * std::size_t(channels) * std::size_t(bytes);
                for (int c = 0; c < channels; ++c) putValue(at + c * bytes, e, v[c], isComponent);
            }
        });
        out.append(buffer.data(), buffer.size());
    });
}

} // namespace

const char* toString(VolEncoding e) {
    switch (e) {
    case VolEncoding::Float32: return "float32";
    case VolEncoding::Float16: return "float16";
    case VolEncoding::UInt8: return "uint8";
    }
    return "?";
}

VolEncoding parseVolEncoding(const std::string& name) {
    if (name == "float32") return VolEncoding::Float32;
    if (name == "float16") return VolEncoding::Float16;
    if (name == "uint8") return VolEncoding::UInt8;
    throw Error("unknown .vol type '" + name + "' (float32, float16 or uint8)");
}

int encodingBytes(VolEncoding e) { return e == VolEncoding::Float32 ? 4 : e == VolEncoding::Float16 ? 2 : 1; }

VolBoxConvention parseVolBoxConvention(const std::string& name) {
    if (name == "corners") return VolBoxConvention::Corners;
    if (name == "centres") return VolBoxConvention::Centres;
    throw Error("unknown .vol bounding box convention '" + name + "' (corners or centres)");
}

VoxelBox voxelBoxFromWorld(const openvdb::math::Transform& transform, glm::dvec3 lo, glm::dvec3 hi) {
    const AxisMap a = axisMap(transform);
    VoxelBox box;
    for (int i = 0; i < 3; ++i) {
        if (!(lo[i] < hi[i])) throw Error("the world box is empty along axis " + std::string(1, "xyz"[i]));
        // Voxel n covers index coordinates [n - 0.5, n + 0.5).
        const double u0 = (lo[i] - a.offset[i]) / a.scale[i] + 0.5, u1 = (hi[i] - a.offset[i]) / a.scale[i] + 0.5;
        if (std::abs(u0) > 2e9 || std::abs(u1) > 2e9) throw Error("the world box reaches beyond the grid's index range");
        box.min[i] = int(std::floor(u0));
        box.max[i] = int(std::ceil(u1));
    }
    if (box.empty()) throw Error("the world box holds no voxel");
    return box;
}

std::string volSiblingPath(const std::string& densityPath, const std::string& what) {
    const std::string ext = ".vol";
    const bool hasExt = densityPath.size() > ext.size() && densityPath.compare(densityPath.size() - ext.size(), ext.size(), ext) == 0;
    return (hasExt ? densityPath.substr(0, densityPath.size() - ext.size()) : densityPath) + "." + what + ".vol";
}

std::vector<std::string> volOutputPaths(const std::string& densityPath, bool withOrientation, const VolExportOptions& options,
                                        bool withAlbedo) {
    std::vector<std::string> paths{densityPath};
    if (withOrientation) paths.push_back(volSiblingPath(densityPath, "orientation"));
    if (withOrientation && options.sggxRoughness > 0.0) paths.push_back(volSiblingPath(densityPath, "sggx"));
    if (withAlbedo) paths.push_back(volSiblingPath(densityPath, "albedo"));
    return paths;
}

double volFileBytes(glm::ivec3 dims, int channels, VolEncoding e) {
    return 48.0 + double(dims.x) * double(dims.y) * double(dims.z) * channels * encodingBytes(e);
}

VolExportResult exportMitsubaVol(const FiberGrids& grids, const std::string& densityPath, const VolExportOptions& options) {
    YV_CHECK(grids.density);
    const openvdb::FloatGrid& density = *grids.density;
    const openvdb::Vec3SGrid* orientation = grids.orientation.get();
    if (options.sggxRoughness > 0.0 && !orientation)
        throw Error(densityPath + ": SGGX matrices need the fibre axes, and the .vdb has no 'orientation' grid");
    const AxisMap map = axisMap(density.transform());
    if (orientation && orientation->transform() != density.transform())
        throw Error(densityPath + ": the 'orientation' grid lies on another transform than 'density'");
    const openvdb::Vec3SGrid* albedo = grids.albedo.get();
    if (albedo && albedo->transform() != density.transform())
        throw Error(densityPath + ": the 'albedo' grid lies on another transform than 'density'");

    VolExportResult result;
    if (options.box) {
        result.box = *options.box;
        if (result.box.empty()) throw Error(densityPath + ": the box " + coordText(result.box.min) + " to " +
                                            coordText(result.box.max) + " holds no voxel (max is exclusive)");
    } else {
        const openvdb::CoordBBox active = density.evalActiveVoxelBoundingBox();
        if (active.empty()) throw Error(densityPath + ": the density grid has no active voxel: nothing to export");
        // One empty voxel of margin: the outermost fibre voxels are then inside
        // the box under either convention (Mitsuba 0.6 reads nothing beyond
        // the first and last voxel centres).
        result.box.min = glm::ivec3(active.min().x(), active.min().y(), active.min().z()) - 1;
        result.box.max = glm::ivec3(active.max().x(), active.max().y(), active.max().z()) + 2;
    }
    if (options.boxConvention == VolBoxConvention::Centres && glm::any(glm::lessThan(result.box.dims(), glm::ivec3(2))))
        throw Error(densityPath + ": a box of centres needs at least 2 voxels along each axis, not " + dimsText(result.box.dims()));
    const VoxelBox& box = result.box;
    const glm::ivec3 dims = box.dims();
    const std::vector<std::string> paths = volOutputPaths(densityPath, orientation != nullptr, options, albedo != nullptr);
    const bool sggx = orientation && options.sggxRoughness > 0.0;

    // The whole size is known before a byte is written: refuse here, not at a full disk.
    double need = volFileBytes(dims, 1, options.densityEncoding);
    if (orientation) need += volFileBytes(dims, 3, options.orientationEncoding);
    if (sggx) need += volFileBytes(dims, 6, VolEncoding::Float32);
    if (albedo) need += volFileBytes(dims, 3, options.albedoEncoding);
    const std::filesystem::path parent = std::filesystem::path(densityPath).parent_path();
    const std::string dir = parent.empty() ? "." : parent.string();
    std::error_code ec;
    const std::filesystem::space_info space = std::filesystem::space(dir, ec);
    if (ec) throw Error(densityPath + ": cannot tell the free space in " + dir + ": " + ec.message());
    if (need > double(space.available))
        throw Error(densityPath + ": a dense export of " + dimsText(dims) + " voxels needs " + bytesText(need) +
                    " (" + std::to_string(paths.size()) + " file" + (paths.size() > 1 ? "s" : "") + "), and " + dir +
                    " has " + bytesText(double(space.available)) +
                    " free: nothing was written (export a region with --bbox or --region, or use --vol-type uint8)");

    // Header bounding box: the voxels' outer faces, or their centres.
    const double inset = options.boxConvention == VolBoxConvention::Centres ? 0.5 : 0.0;
    for (int i = 0; i < 3; ++i) {
        result.worldMin[i] = map.offset[i] + map.scale[i] * (box.min[i] - 0.5 + inset);
        result.worldMax[i] = map.offset[i] + map.scale[i] * (box.max[i] - 0.5 - inset);
    }

    std::vector<std::unique_ptr<PendingFile>> files;
    for (const std::string& p : paths) files.push_back(std::make_unique<PendingFile>(p));
    std::atomic<std::uint64_t> clamped{0};

    appendHeader(*files[0], options.densityEncoding, dims, 1, result.worldMin, result.worldMax);
    const bool countClamped = options.densityEncoding == VolEncoding::UInt8;
    appendValues(*files[0], density, box, 1, options.densityEncoding, false, [&](float d, float* v) {
        v[0] = d;
        if (countClamped && d > 1.0f) clamped.fetch_add(1, std::memory_order_relaxed);
    });
    if (orientation) {
        appendHeader(*files[1], options.orientationEncoding, dims, 3, result.worldMin, result.worldMax);
        appendValues(*files[1], *orientation, box, 3, options.orientationEncoding, true,
                     [](const openvdb::Vec3s& a, float* v) { v[0] = a.x(), v[1] = a.y(), v[2] = a.z(); });
    }
    if (sggx) {
        // Fibre-like SGGX microflakes (Heitz et al. 2015): S = I - (1 - sigma^2) t t^T
        // for the unit fibre axis t; empty voxels keep S = 0 (no flakes).
        const float keep = float(1.0 - options.sggxRoughness * options.sggxRoughness);
        appendHeader(*files[2], VolEncoding::Float32, dims, 6, result.worldMin, result.worldMax);
        appendValues(*files[2], *orientation, box, 6, VolEncoding::Float32, false, [keep](const openvdb::Vec3s& a, float* v) {
            const float len2 = a.lengthSqr();
            if (!(len2 > 0.0f)) {
                std::fill(v, v + 6, 0.0f);
                return;
            }
            const float x = a.x(), y = a.y(), z = a.z(), k = keep / len2;
            v[0] = 1.0f - k * x * x, v[1] = 1.0f - k * y * y, v[2] = 1.0f - k * z * z;
            v[3] = -k * x * y, v[4] = -k * x * z, v[5] = -k * y * z;
        });
    }
    if (albedo) {
        // Linear RGB in [0, 1] (no sign to fold); empty voxels read 0.
        PendingFile& file = *files.back();
        appendHeader(file, options.albedoEncoding, dims, 3, result.worldMin, result.worldMax);
        appendValues(file, *albedo, box, 3, options.albedoEncoding, false,
                     [](const openvdb::Vec3s& c, float* v) { v[0] = c.x(), v[1] = c.y(), v[2] = c.z(); });
    }
    // Every file complete and on disk before any takes its name.
    for (auto& f : files) f->sync();
    for (auto& f : files) {
        f->publish();
        result.paths.push_back(f->path());
        result.bytes += f->size();
    }
    result.densityClamped = clamped;
    return result;
}

} // namespace yv
