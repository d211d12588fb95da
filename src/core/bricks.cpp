#include "core/bricks.h"

#include "core/principal_axes.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <array>
#include <bit>
#include <cmath>

namespace yv {

void combineAccumulators(Reduce reduce, std::uint32_t* dst, const std::uint32_t* src, bool albedo) {
    if (reduce == Reduce::Mean) {
        // Unsigned wrap-around addition is also correct two's-complement
        // addition for the signed tensor terms.
        const int words = wordsPerVoxel(reduce, albedo) * kBrickVoxels;
        for (int i = 0; i < words; ++i) dst[i] += src[i];
        return;
    }
    std::uint32_t* density = dst;
    std::uint32_t* code = dst + kBrickVoxels;
    for (int v = 0; v < kBrickVoxels; ++v) {
        const std::uint32_t d = src[v], c = src[kBrickVoxels + v];
        // Lexicographic max on (density, orientation code): the same winner
        // whatever order samples arrive in.
        if (d > density[v] || (d == density[v] && c > code[v])) {
            density[v] = d;
            code[v] = c;
        }
    }
}

int VoxelBrick::activeCount() const {
    return activeVoxelCount(activeMask);
}

glm::dvec3 principalAxis(const double t[6]) {
    double a[3][3] = {{t[0], t[3], t[4]}, {t[3], t[1], t[5]}, {t[4], t[5], t[2]}};
    double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int sweep = 0; sweep < 12; ++sweep) {
        const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        const double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if (off <= 1e-30 * diag || off == 0.0) break;
        for (int p = 0; p < 2; ++p)
            for (int q = p + 1; q < 3; ++q) {
                if (a[p][q] == 0.0) continue;
                const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                const double tt = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(tt * tt + 1.0), s = tt * c;
                for (int k = 0; k < 3; ++k) { // A <- A J
                    const double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; ++k) { // A <- J^T A
                    const double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; ++k) { // V <- V J
                    const double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
    }
    int best = 0;
    for (int i = 1; i < 3; ++i)
        if (a[i][i] > a[best][best]) best = i;
    return glm::normalize(glm::dvec3(v[0][best], v[1][best], v[2][best]));
}

namespace {

/// The principal axis of each voxel with fibre of a mean's accumulator
/// (the others are left as they are), several voxels at a time.
void fibreAxes(const std::uint32_t* w, glm::dvec3* axes) {
    double tensors[kBrickVoxels][6];
    std::array<std::uint16_t, kBrickVoxels> voxels;
    int count = 0;
    for (int v = 0; v < kBrickVoxels; ++v) {
        if (w[v] == 0) continue;
        for (int i = 0; i < 6; ++i) tensors[count][i] = static_cast<std::int32_t>(w[(1 + i) * kBrickVoxels + v]);
        voxels[count++] = static_cast<std::uint16_t>(v);
    }
    std::array<glm::dvec3, kBrickVoxels> found;
    principalAxes(tensors, found.data(), count);
    for (int k = 0; k < count; ++k) axes[voxels[k]] = found[k];
}

} // namespace

ResolveTally& ResolveTally::operator+=(const ResolveTally& o) {
    activeVoxels += o.activeVoxels;
    voxelsOverOne += o.voxelsOverOne;
    densitySum += o.densitySum;
    rawDensitySum += o.rawDensitySum;
    excessOverOne += o.excessOverOne;
    return *this;
}

bool resolveBrick(Reduce reduce, Overlap overlap, const BrickAccumulator& acc, VoxelBrick& out, ResolveTally* tally) {
    out.key = acc.key;
    out.activeMask.fill(0);
    const std::uint32_t* w = acc.words.data();
    const bool albedo = reduce == Reduce::Mean && acc.hasAlbedo();
    if (albedo)
        out.albedo.assign(kBrickVoxels, glm::vec3(0.0f));
    else
        out.albedo.clear();
    bool any = false;
    ResolveTally local;
    std::array<glm::dvec3, kBrickVoxels> axes;
    if (reduce == Reduce::Mean) fibreAxes(w, axes.data());
    for (int v = 0; v < kBrickVoxels; ++v) {
        float density = 0.0f;
        glm::dvec3 axis(0.0);
        if (reduce == Reduce::Mean) {
            const double raw = w[v] / kFixedScale;
            local.rawDensitySum += raw;
            if (raw > 1.0) {
                local.excessOverOne += raw - 1.0;
                local.voxelsOverOne += raw > 1.0 + kOverOneMargin;
            }
            density = static_cast<float>(overlap == Overlap::Clamp ? std::min(raw, 1.0) : raw);
            if (w[v] != 0) {
                axis = canonicalAxis(axes[v]);
                if (albedo)
                    for (int i = 0; i < 3; ++i)
                        out.albedo[v][i] = static_cast<float>(
                            std::min(1.0, double(w[(kMeanWords + i) * kBrickVoxels + v]) / double(w[v])));
            }
        } else {
            density = bitsFloat(w[v]);
            local.rawDensitySum += density;
            if (w[v] != 0) axis = decodeAxis(w[kBrickVoxels + v]);
        }
        out.density[v] = density;
        out.orientation[v] = glm::vec3(axis);
        if (density > 0.0f) {
            out.activeMask[v >> 6] |= std::uint64_t(1) << (v & 63);
            any = true;
            ++local.activeVoxels;
            local.densitySum += density;
        }
    }
    if (tally) *tally += local;
    return any;
}

std::uint64_t BrickVolume::activeVoxelCount() const {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, bricks.size()), std::uint64_t(0),
        [&](const tbb::blocked_range<std::size_t>& r, std::uint64_t n) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) n += bricks[i].activeCount();
            return n;
        },
        std::plus<>());
}

double BrickVolume::totalMass() const {
    // Fixed order of summation, so the same volume always gives the same bits.
    double sum = 0.0;
    for (const VoxelBrick& b : bricks)
        for (float d : b.density) sum += d;
    return sum * grid.voxelSize * grid.voxelSize * grid.voxelSize;
}

BrickVolume resolveVolume(const VoxelGrid& grid, Reduce reduce, Overlap overlap,
                          std::vector<BrickAccumulator>& accumulators) {
    tbb::parallel_sort(accumulators.begin(), accumulators.end(),
                       [](const BrickAccumulator& a, const BrickAccumulator& b) { return a.key < b.key; });
    BrickVolume volume;
    volume.grid = grid;
    volume.reduce = reduce;
    std::vector<VoxelBrick> bricks(accumulators.size());
    std::vector<std::uint8_t> keep(accumulators.size());
    std::vector<ResolveTally> tallies(accumulators.size());
    tbb::parallel_for(std::size_t(0), accumulators.size(), [&](std::size_t i) {
        keep[i] = resolveBrick(reduce, overlap, accumulators[i], bricks[i], &tallies[i]);
    });
    volume.bricks.reserve(bricks.size());
    for (std::size_t i = 0; i < bricks.size(); ++i) {
        volume.tally += tallies[i]; // in key order: the same bits for the same volume
        if (keep[i]) volume.bricks.push_back(bricks[i]);
    }
    return volume;
}

} // namespace yv
