#include "vdb/lod_pyramid.h"

#include "core/error.h"
#include "core/principal_axes.h"

#include <algorithm>
#include <bit>
#include <cstring>

namespace yv {
namespace {

/// Where the octant of `childKey` starts in its parent brick `skip` levels
/// up, in voxels: the child covers (8 >> skip)^3 of the parent's voxels.
glm::ivec3 octantOrigin(std::uint64_t childKey, int skip) {
    return (brickCoord(childKey) & ((1 << skip) - 1)) * (kBrickSize >> skip);
}

/// One block's sums: density, tensor (xx yy zz xy xz yz), density times colour.
struct BlockSums {
    double d, t[6], rgb[3];
};

/// Sums over each block of 2^Skip voxels a side of a brick: block (x, y, z)
/// of the (8 >> Skip)^3 covers voxels (2^Skip x .. 2^Skip (x + 1) - 1, ...).
/// One pass over the active voxels in OpenVDB's voxel order, so each block's
/// sum runs in that order, the same on every run. `density(v, r)` and
/// `tensor(v, r, t)` read voxel v, the r-th active one; `colour(v, r, c)`
/// gives its density times colour. Returns the mask of blocks with an active
/// voxel; `out` gets the sums of all (8 >> Skip)^3.
template <int Skip, bool WithAlbedo, typename DensityFn, typename TensorFn, typename ColourFn>
std::uint64_t blockSums(const std::array<std::uint64_t, kBrickVoxels / 64>& active, DensityFn density, TensorFn tensor,
                        ColourFn colour, BlockSums* out) {
    constexpr int kSide = kBrickSize >> Skip, kBlocks = kSide * kSide * kSide;
    // Local, so the preview's one block a brick stays in registers.
    BlockSums sums[kBlocks] = {};
    std::uint64_t mask = 0;
    int rank = 0;
    for (int w = 0; w < kBrickVoxels / 64; ++w)
        for (std::uint64_t bits = active[w]; bits; bits &= bits - 1, ++rank) {
            const int v = w * 64 + std::countr_zero(bits);
            const int block = (((v >> 6) >> Skip) * kSide + (((v >> 3) & 7) >> Skip)) * kSide + ((v & 7) >> Skip);
            mask |= std::uint64_t(1) << block;
            BlockSums& s = sums[block];
            s.d += density(v, rank);
            double tv[6];
            tensor(v, rank, tv);
            for (int i = 0; i < 6; ++i) s.t[i] += tv[i];
            if constexpr (WithAlbedo) {
                double cv[3];
                colour(v, rank, cv);
                for (int i = 0; i < 3; ++i) s.rgb[i] += cv[i];
            }
        }
    std::copy(sums, sums + kBlocks, out);
    return mask;
}

/// Appends the octant record of `sums` (format in lod_pyramid.h): the mask,
/// then the blocks' density sums, tensor sums and colour sums in block order.
void appendOctantRecord(std::uint64_t mask, const BlockSums* sums, bool withAlbedo, std::vector<std::uint8_t>& out) {
    const int n = std::popcount(mask);
    const std::size_t at = out.size();
    const int colourFloats = withAlbedo ? 3 : 0;
    out.resize(at + sizeof mask + n * (sizeof(double) + (6 + colourFloats) * sizeof(float)));
    std::uint8_t* p = out.data() + at;
    std::memcpy(p, &mask, sizeof mask);
    p += sizeof mask;
    std::uint8_t* tensors = p + n * sizeof(double);
    std::uint8_t* colours = tensors + n * 6 * sizeof(float);
    for (std::uint64_t bits = mask; bits; bits &= bits - 1) {
        const BlockSums& s = sums[std::countr_zero(bits)];
        std::memcpy(p, &s.d, sizeof(double));
        p += sizeof(double);
        float f[6];
        for (int i = 0; i < 6; ++i) f[i] = static_cast<float>(s.t[i]);
        std::memcpy(tensors, f, sizeof f);
        tensors += sizeof f;
        if (!withAlbedo) continue;
        for (int i = 0; i < 3; ++i) f[i] = static_cast<float>(s.rgb[i]);
        std::memcpy(colours, f, 3 * sizeof(float));
        colours += 3 * sizeof(float);
    }
}

/// The octant of a brick for its parent `skip` levels up (1 to 3), from
/// its active voxels (blockSums).
template <typename DensityFn, typename TensorFn, typename ColourFn>
void appendOctantSums(const std::array<std::uint64_t, kBrickVoxels / 64>& active, int skip, DensityFn density,
                      TensorFn tensor, bool withAlbedo, ColourFn colour, std::vector<std::uint8_t>& out) {
    BlockSums sums[64];
    std::uint64_t mask = 0;
    // The number of levels skipped and the albedo as constants: the block
    // index then costs nothing for the preview's one block.
    const auto sum = [&]<int Skip>() {
        mask = withAlbedo ? blockSums<Skip, true>(active, density, tensor, colour, sums)
                          : blockSums<Skip, false>(active, density, tensor, colour, sums);
    };
    switch (skip) {
    case 1: sum.template operator()<1>(); break;
    case 2: sum.template operator()<2>(); break;
    default: YV_CHECK(skip == 3); sum.template operator()<3>(); break;
    }
    appendOctantRecord(mask, sums, withAlbedo, out);
}

/// A voxel's structure tensor weighted by its density, d a a^T (xx, yy, zz,
/// xy, xz, yz), in double from the float axis.
void densityTensor(float density, glm::vec3 axis, double t[6]) {
    const double d = density;
    const glm::dvec3 a(axis);
    t[0] = d * a.x * a.x;
    t[1] = d * a.y * a.y;
    t[2] = d * a.z * a.z;
    t[3] = d * a.x * a.y;
    t[4] = d * a.x * a.z;
    t[5] = d * a.y * a.z;
}

} // namespace

int maxLodLevels(const VoxelGrid& grid) {
    const int longest = std::max({grid.dims.x, grid.dims.y, grid.dims.z});
    int levels = 0;
    while ((longest >> (levels + 1)) >= kBrickSize) ++levels;
    return levels;
}

int checkedLodLevels(int levels, const VoxelGrid& grid) {
    const int most = maxLodLevels(grid);
    if (levels < 0 || levels > most) {
        const int longest = std::max({grid.dims.x, grid.dims.y, grid.dims.z});
        throw Error("--lod " + std::to_string(levels) + ": the grid is " + std::to_string(longest) +
                    " voxels on its longest axis, and every level must keep at least " + std::to_string(kBrickSize) +
                    " (one brick): give --lod 0 to " + std::to_string(most));
    }
    return levels;
}

std::size_t octantBytesAtMost(int skip, bool albedo) {
    const std::size_t side = std::size_t(kBrickSize >> skip);
    return sizeof(std::uint64_t) + side * side * side * (sizeof(double) + (albedo ? 9 : 6) * sizeof(float));
}

void CoarseBrick::clear(std::uint64_t k, bool withAlbedo, int levelsSkipped) {
    YV_CHECK(levelsSkipped >= 1 && levelsSkipped <= 3);
    key = k;
    albedo = withAlbedo;
    skip = levelsSkipped;
    // The sums of untouched voxels are never read: clearing all 28 KB of
    // them for a parent with a few children was work for nothing.
    touched.fill(0);
}

void appendOctant(const VoxelBrick& brick, int skip, std::vector<std::uint8_t>& out) {
    appendOctantSums(
        brick.activeMask, skip, [&](int v, int) { return double(brick.density[v]); },
        [&](int v, int, double t[6]) { densityTensor(brick.density[v], brick.orientation[v], t); },
        !brick.albedo.empty(),
        [&](int v, int, double c[3]) {
            for (int i = 0; i < 3; ++i) c[i] = double(brick.density[v]) * brick.albedo[v][i];
        },
        out);
}

void appendOctant(const PackedBricks& packed, std::size_t i, const std::array<std::uint64_t, kBrickVoxels / 64>& active,
                  int skip, std::vector<std::uint8_t>& out) {
    // The r-th active voxel lies at firstVoxel + r.
    const std::size_t first = packed.headers[i].firstVoxel;
    appendOctantSums(
        active, skip, [&](int, int r) { return double(packed.voxels[first + r].density); },
        [&](int, int r, double t[6]) {
            const PackedVoxel& p = packed.voxels[first + r];
            densityTensor(p.density, glm::vec3(p.axis[0], p.axis[1], p.axis[2]), t);
        },
        !packed.albedo.empty(),
        [&](int, int r, double c[3]) {
            for (int k = 0; k < 3; ++k) c[k] = double(packed.voxels[first + r].density) * packed.albedo[first + r].rgb[k];
        },
        out);
}

void appendOctant(const CoarseBrick& sums, const VoxelBrick& resolved, std::vector<std::uint8_t>& out) {
    appendOctantSums(
        resolved.activeMask, 1, [&](int v, int) { return double(resolved.density[v]); },
        [&](int v, int, double t[6]) { std::copy(sums.tensor[v].begin(), sums.tensor[v].end(), t); },
        !resolved.albedo.empty(),
        // The written density and colour: the next level keeps the written colour mass.
        [&](int v, int, double c[3]) {
            for (int i = 0; i < 3; ++i) c[i] = double(resolved.density[v]) * resolved.albedo[v][i];
        },
        out);
}

void placeOctant(std::span<const std::uint8_t> bytes, std::uint64_t childKey, CoarseBrick& parent) {
    std::uint64_t mask = 0;
    if (bytes.size() < sizeof mask) throw Error("level-of-detail scratch record too short");
    std::memcpy(&mask, bytes.data(), sizeof mask);
    const int n = std::popcount(mask);
    const std::size_t colourFloats = parent.albedo ? 3 : 0;
    if (bytes.size() != sizeof mask + n * (sizeof(double) + (6 + colourFloats) * sizeof(float)))
        throw Error("level-of-detail scratch record of " + std::to_string(bytes.size()) + " bytes for " +
                    std::to_string(n) + " voxels");
    const std::uint8_t* densities = bytes.data() + sizeof mask;
    const std::uint8_t* tensors = densities + n * sizeof(double);
    const std::uint8_t* colours = tensors + n * 6 * sizeof(float);
    const int side = kBrickSize >> parent.skip;
    if (side * side * side < 64 && mask >> (side * side * side))
        throw Error("level-of-detail scratch record with blocks beyond its " + std::to_string(side * side * side));
    const glm::ivec3 o = octantOrigin(childKey, parent.skip);
    int i = 0;
    for (int block = 0; block < side * side * side; ++block) {
        if (!((mask >> block) & 1)) continue;
        const int v = brickOffset(o.x + block / (side * side), o.y + (block / side) % side, o.z + block % side);
        double d;
        float t[6];
        std::memcpy(&d, densities + i * sizeof(double), sizeof d);
        std::memcpy(t, tensors + i * 6 * sizeof(float), sizeof t);
        parent.touched[v >> 6] |= std::uint64_t(1) << (v & 63);
        parent.densitySum[v] = d;
        for (int k = 0; k < 6; ++k) parent.tensor[v][k] = t[k];
        if (parent.albedo) {
            float c[3];
            std::memcpy(c, colours + i * 3 * sizeof(float), sizeof c);
            for (int k = 0; k < 3; ++k) parent.albedoSum[v][k] = c[k];
        }
        ++i;
    }
}

bool resolveCoarseBrick(const CoarseBrick& sums, VoxelBrick& out) {
    out.key = sums.key;
    out.activeMask.fill(0);
    if (sums.albedo)
        out.albedo.assign(kBrickVoxels, glm::vec3(0.0f));
    else
        out.albedo.clear();
    // The voxels with fibre first, then their axes several at a time.
    std::array<std::uint16_t, kBrickVoxels> fibre;
    double tensors[kBrickVoxels][6];
    int count = 0;
    for (int v = 0; v < kBrickVoxels; ++v) {
        out.density[v] = 0.0f;
        out.orientation[v] = glm::vec3(0.0f);
        if (!((sums.touched[v >> 6] >> (v & 63)) & 1)) continue;
        // The mean over all the 8^skip voxels below it: empty ones count as 0.
        const float density = static_cast<float>(sums.densitySum[v] / double(1 << (3 * sums.skip)));
        if (!(density > 0.0f)) continue;
        out.density[v] = density;
        std::copy(sums.tensor[v].begin(), sums.tensor[v].end(), tensors[count]);
        fibre[count++] = static_cast<std::uint16_t>(v);
        if (sums.albedo)
            for (int k = 0; k < 3; ++k)
                out.albedo[v][k] = static_cast<float>(std::min(1.0, sums.albedoSum[v][k] / sums.densitySum[v]));
        out.activeMask[v >> 6] |= std::uint64_t(1) << (v & 63);
    }
    std::array<glm::dvec3, kBrickVoxels> axes;
    principalAxes(tensors, axes.data(), count);
    for (int k = 0; k < count; ++k) out.orientation[fibre[k]] = glm::vec3(canonicalAxis(axes[k]));
    return count > 0;
}

} // namespace yv
