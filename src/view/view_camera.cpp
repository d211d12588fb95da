#include "view/view_camera.h"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>

namespace yv {

Camera viewCamera(const VoxelBox& box, const ViewCamera& v, int width, int height) {
    const glm::dvec3 lo(box.min), hi(box.max);
    const glm::dvec3 centre = 0.5 * (lo + hi);
    const double radius = viewRadius(box);
    const double az = glm::radians(v.azimuth), el = glm::radians(v.elevation);
    const glm::dvec3 dir(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    // Looking straight down or up, z cannot be the up vector: y is (as frameBox).
    const glm::dvec3 up = std::abs(std::sin(el)) > 0.999 ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1);
    const glm::dvec3 right = glm::normalize(glm::cross(-dir, up));
    const glm::dvec3 pictureUp = glm::cross(right, -dir);
    const glm::dvec3 target = centre + radius * (v.panX * right + v.panY * pictureUp);
    const double d = v.distance * radius;
    Camera c;
    c.width = width, c.height = height;
    c.eye = target + d * dir;
    c.view = glm::lookAt(c.eye, target, up);
    // The planes enclose the bounding sphere, wherever the pan put its centre.
    const double toCentre = glm::length(centre - c.eye);
    const double nearPlane = std::max(toCentre - radius, 1e-3 * d), farPlane = toCentre + radius;
    c.projection = glm::perspective(glm::radians(kFieldOfViewDegrees), double(width) / double(height), nearPlane, farPlane);
    return c;
}

double viewRadius(const VoxelBox& box) { return std::max(0.5 * glm::length(glm::dvec3(box.max - box.min)), 0.5); }

Camera enclosing(const Camera& camera, const VoxelBox& box) {
    const double radius = viewRadius(box);
    const double d = glm::length(camera.eye - 0.5 * glm::dvec3(box.min + box.max));
    const double n = std::max(d - radius, 1e-3 * std::max(d, radius)), f = d + radius;
    // glm::perspective's depth terms; the field of view, aspect and any pan stay.
    Camera c = camera;
    c.projection[2][2] = -(f + n) / (f - n);
    c.projection[3][2] = -2.0 * f * n / (f - n);
    return c;
}

Camera mapCamera(const Camera& camera, double scale, const glm::dvec3& offset) {
    if (scale == 1.0 && offset == glm::dvec3(0.0)) return camera;
    Camera c = camera;
    c.eye = scale * camera.eye + offset;
    // The rotation stays; eye space is `scale` times larger, so the near and
    // far planes are too: of glm::perspective's terms only [3][2] scales.
    const glm::dmat3 rotation(camera.view);
    c.view = glm::dmat4(rotation);
    c.view[3] = glm::dvec4(-(rotation * c.eye), 1.0);
    c.projection[3][2] *= scale;
    return c;
}

} // namespace yv
