#include "vdb/lod_pyramid.h"

#include "core/error.h"

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

/// Sums over each block of 2^skip voxels a side of a brick: block (x, y, z)
/// of the (8 >> skip)^3 covers voxels (2^skip x .. 2^skip (x + 1) - 1, ...).
/// `density(v)` and `tensor(v, t)` read voxel v. `colour(v, c)`, when
/// `withAlbedo`, gives voxel v's density times colour.
template <typename DensityFn, typename TensorFn, typename ColourFn>
void appendOctantSums(const std::array<std::uint64_t, kBrickVoxels / 64>& active, int skip, DensityFn density,
                      TensorFn tensor, bool withAlbedo, ColourFn colour, std::vector<std::uint8_t>& out) {
    constexpr int kMostBlocks = 64;
    const int side = kBrickSize >> skip, size = 1 << skip;
    std::uint64_t mask = 0;
    double densities[kMostBlocks];
    float tensors[kMostBlocks][6];
    float colours[kMostBlocks][3];
    int n = 0;
    for (int bx = 0; bx < side; ++bx)
        for (int by = 0; by < side; ++by)
            for (int bz = 0; bz < side; ++bz) {
                double d = 0.0, t[6] = {0, 0, 0, 0, 0, 0}, rgb[3] = {0, 0, 0};
                bool any = false;
                // Voxels in OpenVDB's voxel order: the same sum on every run.
                for (int c = 0; c < size * size * size; ++c) {
                    const int v = brickOffset(size * bx + (c >> (2 * skip)), size * by + ((c >> skip) & (size - 1)),
                                              size * bz + (c & (size - 1)));
                    if (!((active[v >> 6] >> (v & 63)) & 1)) continue;
                    any = true;
                    d += density(v);
                    double tv[6];
                    tensor(v, tv);
                    for (int i = 0; i < 6; ++i) t[i] += tv[i];
                    if (withAlbedo) {
                        double cv[3];
                        colour(v, cv);
                        for (int i = 0; i < 3; ++i) rgb[i] += cv[i];
                    }
                }
                if (!any) continue;
                const int block = (bx * side + by) * side + bz;
                mask |= std::uint64_t(1) << block;
                densities[n] = d;
                for (int i = 0; i < 6; ++i) tensors[n][i] = static_cast<float>(t[i]);
                for (int i = 0; i < 3; ++i) colours[n][i] = static_cast<float>(rgb[i]);
                ++n;
            }
    const std::size_t at = out.size();
    const int colourFloats = withAlbedo ? 3 : 0;
    out.resize(at + sizeof mask + n * (sizeof(double) + (6 + colourFloats) * sizeof(float)));
    std::uint8_t* p = out.data() + at;
    std::memcpy(p, &mask, sizeof mask);
    p += sizeof mask;
    std::memcpy(p, densities, n * sizeof(double));
    p += n * sizeof(double);
    std::memcpy(p, tensors, n * 6 * sizeof(float));
    p += n * 6 * sizeof(float);
    if (withAlbedo) std::memcpy(p, colours, n * 3 * sizeof(float));
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
    // The sums of untouched voxels are never read: at 28 KB a brick,
    // clearing them was most of a sparse parent's time.
    touched.fill(0);
}

void appendOctant(const VoxelBrick& brick, int skip, std::vector<std::uint8_t>& out) {
    appendOctantSums(
        brick.activeMask, skip, [&](int v) { return double(brick.density[v]); },
        [&](int v, double t[6]) { densityTensor(brick.density[v], brick.orientation[v], t); },
        !brick.albedo.empty(),
        [&](int v, double c[3]) {
            for (int i = 0; i < 3; ++i) c[i] = double(brick.density[v]) * brick.albedo[v][i];
        },
        out);
}

void appendOctant(const PackedBricks& packed, std::size_t i, const std::array<std::uint64_t, kBrickVoxels / 64>& active,
                  int skip, std::vector<std::uint8_t>& out) {
    // Voxel v's place among the packed voxels: firstVoxel plus the active voxels before it.
    std::array<std::uint32_t, kBrickVoxels> at{};
    std::uint32_t n = packed.headers[i].firstVoxel;
    for (int w = 0; w < kBrickVoxels / 64; ++w)
        for (std::uint64_t bits = active[w]; bits; bits &= bits - 1) at[w * 64 + std::countr_zero(bits)] = n++;
    const bool withAlbedo = !packed.albedo.empty();
    appendOctantSums(
        active, skip, [&](int v) { return double(packed.voxels[at[v]].density); },
        [&](int v, double t[6]) {
            const PackedVoxel& p = packed.voxels[at[v]];
            densityTensor(p.density, glm::vec3(p.axis[0], p.axis[1], p.axis[2]), t);
        },
        withAlbedo,
        [&](int v, double c[3]) {
            for (int k = 0; k < 3; ++k) c[k] = double(packed.voxels[at[v]].density) * packed.albedo[at[v]].rgb[k];
        },
        out);
}

void appendOctant(const CoarseBrick& sums, const VoxelBrick& resolved, std::vector<std::uint8_t>& out) {
    appendOctantSums(
        resolved.activeMask, 1, [&](int v) { return double(resolved.density[v]); },
        [&](int v, double t[6]) { std::copy(sums.tensor[v].begin(), sums.tensor[v].end(), t); },
        !resolved.albedo.empty(),
        // The written density and colour: the next level keeps the written colour mass.
        [&](int v, double c[3]) {
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
    bool any = false;
    for (int v = 0; v < kBrickVoxels; ++v) {
        out.density[v] = 0.0f;
        out.orientation[v] = glm::vec3(0.0f);
        if (!((sums.touched[v >> 6] >> (v & 63)) & 1)) continue;
        // The mean over all the 8^skip voxels below it: empty ones count as 0.
        const float density = static_cast<float>(sums.densitySum[v] / double(1 << (3 * sums.skip)));
        if (!(density > 0.0f)) continue;
        out.density[v] = density;
        out.orientation[v] = glm::vec3(canonicalAxis(principalAxis(sums.tensor[v].data())));
        if (sums.albedo)
            for (int k = 0; k < 3; ++k)
                out.albedo[v][k] = static_cast<float>(std::min(1.0, sums.albedoSum[v][k] / sums.densitySum[v]));
        out.activeMask[v >> 6] |= std::uint64_t(1) << (v & 63);
        any = true;
    }
    return any;
}

} // namespace yv
