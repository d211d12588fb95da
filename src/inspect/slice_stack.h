// The proxy geometry of slice-based volume rendering: planes perpendicular
// to one direction, cut by a box into convex polygons (3 to 6 corners) and
// fanned into triangles, as in the texture-slicing recipe.
#pragma once

#include <glm/vec3.hpp>

#include <vector>

namespace yv {

/// The polygon where the plane dot(normal, p) = offset cuts the box [lo, hi],
/// its corners in order around `normal`; empty where the plane misses it.
std::vector<glm::dvec3> boxSlice(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3& normal, double offset);

/// Slices `spacing` apart through the box, nearest to -normal first.
struct SliceStack {
    std::vector<glm::vec3> triangles; ///< every slice's fan, slice after slice
    std::vector<int> first, count;    ///< each slice's vertices in `triangles`
    double spacing = 0.0;
};

/// Planes at offsets (k + 1/2) * spacing past the box's lowest dot(normal, corner),
/// as many as cover the box (`normal` need not be unit length).
SliceStack sliceStack(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3& normal, double spacing);

/// The box's extent along a unit `direction`.
double boxDepth(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3& direction);

} // namespace yv
