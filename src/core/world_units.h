// The range of world-unit numbers yarnvox accepts, checked where each number
// enters (command line, BCC file, cross-section PNG), so that an absurd value
// is named where it came from instead of turning into an empty volume later.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

namespace yv {

/// Lengths (yarn radius, voxel size, slice spacing, yarn spacing) and
/// coordinates lie within [1e-12, 1e12] in magnitude: their squares and cubes
/// (areas, voxel volumes, fibre volume) then stay normal 32-bit floats, and a
/// garment cannot span more voxels than the brick keys can address anyway.
constexpr double kMinLength = 1e-12;
constexpr double kMaxLength = 1e12;
/// Twist is radians per world unit: the reciprocal of a length.
constexpr double kMaxTwist = 1e12;

/// A number as a message shows it: %g, so 1e-30 and nan read as typed.
inline std::string numberText(double v) {
    char s[32];
    std::snprintf(s, sizeof s, "%.6g", v);
    return s;
}

/// Empty when `v` is an acceptable length, else why not ("is not a finite number", ...).
inline std::string lengthProblem(double v) {
    if (!std::isfinite(v)) return numberText(v) + " is not a finite number";
    if (!(v > 0.0)) return numberText(v) + " is not a positive length";
    if (v < kMinLength) return numberText(v) + " is below the smallest length yarnvox accepts, 1e-12 (wrong units?)";
    if (v > kMaxLength) return numberText(v) + " is above the largest length yarnvox accepts, 1e12 (wrong units?)";
    return {};
}

/// Empty when `v` is an acceptable coordinate (finite, magnitude at most
/// 1e12), else "is nan, expected a finite number" and the like.
inline std::string coordinateProblem(double v) {
    if (!std::isfinite(v)) return "is " + numberText(v) + ", expected a finite number";
    if (std::abs(v) > kMaxLength)
        return "is " + numberText(v) + ", beyond 1e12 in magnitude (the largest coordinate yarnvox accepts)";
    return {};
}

} // namespace yv
