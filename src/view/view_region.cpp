#include "view/view_region.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace yv {
namespace {

using Plane = glm::dvec4; ///< inside where dot(plane, (p, 1)) >= 0

/// The four side planes of a perspective camera (Gribb and Hartmann): the
/// rows of viewProjection with |x| <= w and |y| <= w.
std::array<Plane, 4> sidePlanes(const Camera& camera) {
    const glm::dmat4 m = glm::transpose(camera.viewProjection()); // m[r] is row r
    return {m[3] + m[0], m[3] - m[0], m[3] + m[1], m[3] - m[1]};
}

double side(const Plane& p, const glm::dvec3& v) { return glm::dot(glm::dvec3(p), v) + p.w; }

/// Sutherland-Hodgman: the part of convex polygon `poly` inside `plane`.
std::vector<glm::dvec3> clip(const std::vector<glm::dvec3>& poly, const Plane& plane) {
    std::vector<glm::dvec3> out;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const glm::dvec3& a = poly[i];
        const glm::dvec3& b = poly[(i + 1) % poly.size()];
        const double da = side(plane, a), db = side(plane, b);
        if (da >= 0.0) out.push_back(a);
        if ((da >= 0.0) != (db >= 0.0)) out.push_back(a + (b - a) * (da / (da - db)));
    }
    return out;
}

/// `v` written with `digits` significant digits, rounded towards `direction`
/// (-1 down, +1 up, 0 nearest), and the value that text parses to.
std::string roundedText(double v, int digits, int direction, double& parsed) {
    char text[40];
    std::snprintf(text, sizeof text, "%.*g", digits, v);
    parsed = std::strtod(text, nullptr);
    if (direction != 0 && (direction < 0 ? parsed > v : parsed < v)) {
        // One unit in the last digit further: the text then holds v on the side asked.
        const double unit = std::pow(10.0, std::floor(std::log10(std::max(std::abs(v), 1e-300))) - (digits - 1));
        std::snprintf(text, sizeof text, "%.*g", digits, parsed + direction * unit);
        parsed = std::strtod(text, nullptr);
    }
    return text;
}

} // namespace

bool RealBox::contains(const RealBox& o) const {
    return o.min.x >= min.x && o.min.y >= min.y && o.min.z >= min.z && o.max.x <= max.x && o.max.y <= max.y &&
           o.max.z <= max.z;
}

RealBox seenBox(const VoxelBox& bounds, const Camera& camera) {
    const glm::dvec3 lo(bounds.min), hi(bounds.max);
    const auto corner = [&](int bits) {
        return glm::dvec3(bits & 1 ? hi.x : lo.x, bits & 2 ? hi.y : lo.y, bits & 4 ? hi.z : lo.z);
    };
    // The box's six faces, each clipped by the pyramid: every corner of the
    // part inside lies on a face, but the eye, which is one where it lies inside.
    static constexpr int kFaces[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
    const std::array<Plane, 4> planes = sidePlanes(camera);
    RealBox seen{glm::dvec3(HUGE_VAL), glm::dvec3(-HUGE_VAL)};
    const auto take = [&](const glm::dvec3& p) {
        seen.min = glm::min(seen.min, p);
        seen.max = glm::max(seen.max, p);
    };
    for (const auto& face : kFaces) {
        std::vector<glm::dvec3> poly = {corner(face[0]), corner(face[1]), corner(face[2]), corner(face[3])};
        for (const Plane& plane : planes) poly = clip(poly, plane);
        for (const glm::dvec3& p : poly) take(p);
    }
    if (bounds.contains(glm::ivec3(glm::floor(camera.eye)))) take(camera.eye);
    // Keep it within the bounds against rounding in the clipping.
    seen.min = glm::max(seen.min, lo);
    seen.max = glm::min(seen.max, hi);
    return seen;
}

std::optional<ViewVoxelization> planViewVoxelization(const VoxelBox& bounds, const VoxelGrid& grid, const Camera& camera,
                                                     int maxSideVoxels, int maxResolution, std::string& why) {
    const RealBox seen = seenBox(bounds, camera);
    if (seen.empty()) {
        why = "nothing of the volume is in view";
        return std::nullopt;
    }
    // A pixel's width at the depth of the seen box's centre (projection[1][1] is 1 / tan(fov / 2)).
    const glm::dmat4 inverseView = glm::inverse(camera.view);
    const glm::dvec3 forward = -glm::dvec3(inverseView[2]);
    const double depth = std::max(glm::dot(0.5 * (seen.min + seen.max) - camera.eye, forward), 1e-6);
    const double pixelVoxels = 2.0 * depth / (camera.projection[1][1] * camera.height);
    const glm::dvec3 extent = seen.max - seen.min;
    const double longest = std::max({extent.x, extent.y, extent.z});
    const double wholeLongest = double(std::max({grid.dims.x, grid.dims.y, grid.dims.z}));
    // In voxels of `grid`: no finer than the budgets allow.
    const double sizeVoxels = std::max({pixelVoxels, longest / maxSideVoxels, wholeLongest / maxResolution});
    if (sizeVoxels >= 0.95) {
        why = "the view's pixels are no finer than the volume's voxels: zoom in to voxelize what the camera sees";
        return std::nullopt;
    }
    ViewVoxelization run;
    run.voxelSizeText = roundedText(sizeVoxels * grid.voxelSize, 3, +1, run.voxelSize);
    const double margin = 0.5 * run.voxelSize;
    const glm::dvec3 lo = grid.origin + seen.min * grid.voxelSize - margin;
    const glm::dvec3 hi = grid.origin + seen.max * grid.voxelSize + margin;
    for (int axis = 0; axis < 3; ++axis) {
        if (axis) run.boxText += ",";
        run.boxText += roundedText(lo[axis], 6, -1, run.world.min[axis]);
    }
    for (int axis = 0; axis < 3; ++axis) run.boxText += "," + roundedText(hi[axis], 6, +1, run.world.max[axis]);
    return run;
}

std::optional<ViewVoxelization> refinePass(const ViewVoxelization& run, double openedVoxelSize) {
    const glm::dvec3 extent = run.world.max - run.world.min;
    const double longest = std::max({extent.x, extent.y, extent.z});
    if (run.firstPass || longest < kRefineFromVoxels * run.voxelSize) return std::nullopt;
    ViewVoxelization first = run;
    first.firstPass = true;
    first.voxelSizeText = roundedText(kRefineFactor * run.voxelSize, 3, +1, first.voxelSize);
    if (first.voxelSize >= 0.95 * openedVoxelSize) return std::nullopt;
    return first;
}

} // namespace yv
