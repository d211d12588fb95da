// The sampling rule shared by every backend. formats/sampling-rule.md explains
// it; shaders/layout.glsl, axis_codes.glsl and common.glsl mirror these
// constants and functions.
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

namespace yv {

enum class Reduce { Mean, Max };

inline const char* toString(Reduce r) { return r == Reduce::Mean ? "mean" : "max"; }

/// What a mean voxel reads where yarns interpenetrate: Clamp keeps the fibre
/// volume fraction at or below 1 (a voxel cannot hold more fibre than its
/// volume); Sum keeps the plain sum of every yarn's share.
enum class Overlap { Clamp, Sum };

inline const char* toString(Overlap o) { return o == Overlap::Clamp ? "clamp" : "sum"; }

/// Version of the CPU side of the rule (src/cpu, this file, src/garment's
/// slices): raise it with any change that can alter a brick's bits, so that
/// `--resume` refuses regions an older rule made. The GL side needs no number:
/// the run fingerprint hashes the embedded shader texts.
constexpr std::uint32_t kCpuSamplingRuleVersion = 1;

/// Fixed-point scale of accumulated volume fractions: 2^24 units per 1.0.
/// Integer sums make results identical for any order and thread count.
constexpr double kFixedScale = 16777216.0;

/// Smallest share of a voxel's volume a sample gives it: below this (a sliver
/// of a column that rounding alone can create or remove) the share is
/// dropped by both reductions, so that float and double backends agree on
/// which voxels are active. The volume lost is at most this per voxel a
/// column's end grazes.
constexpr double kMinVoxelShare = 1.0 / 65536.0;

/// Words of accumulator state per voxel. Mean: density, then the six terms of
/// the density-weighted structure tensor (xx yy zz xy xz yz). Max: density
/// (float bits), then the orientation code of the densest sample.
constexpr int kMeanWords = 7;
constexpr int kMaxWords = 2;
/// With albedo (mean only), three more words: the volume-fraction-weighted
/// linear colour, R G B, in the same fixed point as the density.
constexpr int kAlbedoWords = 3;
inline int wordsPerVoxel(Reduce r, bool albedo = false) {
    return r == Reduce::Mean ? kMeanWords + (albedo ? kAlbedoWords : 0) : kMaxWords;
}

/// Relative margin within which two components of a slice normal count as a
/// tie. The GL backend computes normals in float, the CPU in double: at exactly
/// 45 degrees they differ in the last bits, and a plain comparison would send
/// the same slice along different axes. With the margin both take the lower
/// index; they can only disagree for a normal within float rounding of
/// |n[i]| = |n[j]| (1 - kAxisTieMargin), which no common geometry produces.
constexpr double kAxisTieMargin = 1.0 / 1024.0;

/// Projection axis of a slice: the dominant axis of its normal; components
/// within kAxisTieMargin of the largest go to the lowest index.
inline int dominantAxis(const glm::dvec3& n) {
    const glm::dvec3 a = glm::abs(n);
    const double floor = std::max({a.x, a.y, a.z}) * (1.0 - kAxisTieMargin);
    return a.x >= floor ? 0 : (a.y >= floor ? 1 : 2);
}

/// std::lround's result (halves away from zero) without its library call,
/// for finite |x| < 2^62: a sample's fixed-point rounding took 4 % of the CPU
/// backend's time in that call. The truncation is exact, and so is the
/// fraction left (x and its truncation lie within a factor of two).
inline long long roundHalfAway(double x) {
    const long long t = static_cast<long long>(x);
    const double fraction = x - static_cast<double>(t);
    return t + (fraction >= 0.5) - (fraction <= -0.5);
}

/// Rounds a non-negative volume fraction to fixed point.
inline std::uint32_t toFixed(double v) { return static_cast<std::uint32_t>(roundHalfAway(v * kFixedScale)); }
inline std::int32_t toFixedSigned(double v) { return static_cast<std::int32_t>(roundHalfAway(v * kFixedScale)); }

/// Orientation as an axis: v and -v name the same fibre, so directions are
/// folded onto the hemisphere z > 0 (then y > 0, then x >= 0 on the rim).
inline glm::dvec3 canonicalAxis(glm::dvec3 v) {
    if (v.z < 0 || (v.z == 0 && (v.y < 0 || (v.y == 0 && v.x < 0)))) v = -v;
    return v;
}

/// 16+16-bit octahedral code of a canonical unit axis (upper hemisphere), and back.
inline std::uint32_t encodeAxis(const glm::dvec3& axis) {
    const glm::dvec3 v = canonicalAxis(axis);
    const double s = std::abs(v.x) + std::abs(v.y) + std::abs(v.z);
    const double u = v.x / s, w = v.y / s; // in the diamond |u| + |w| <= 1
    auto q = [](double t) { return static_cast<std::uint32_t>(roundHalfAway((std::clamp(t, -1.0, 1.0) * 0.5 + 0.5) * 65535.0)); };
    return (q(u) << 16) | q(w);
}
inline glm::dvec3 decodeAxis(std::uint32_t code) {
    const double u = ((code >> 16) / 65535.0) * 2.0 - 1.0, w = ((code & 0xffff) / 65535.0) * 2.0 - 1.0;
    return glm::normalize(glm::dvec3(u, w, std::max(0.0, 1.0 - std::abs(u) - std::abs(w))));
}

/// Float bits of a non-negative float order like the float itself: atomicMax on
/// the bits is a max on the values.
inline std::uint32_t floatBits(float f) {
    std::uint32_t u;
    static_assert(sizeof u == sizeof f);
    __builtin_memcpy(&u, &f, sizeof u);
    return u;
}
inline float bitsFloat(std::uint32_t u) {
    float f;
    __builtin_memcpy(&f, &u, sizeof f);
    return f;
}

} // namespace yv
