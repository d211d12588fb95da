#include "inspect/camera.h"

#include "core/error.h"
#include "core/text.h"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace yv {

Camera frameBox(const VoxelBox& box, const ViewAngles& v, int width, int height) {
    const glm::dvec3 lo(box.min), hi(box.max);
    const glm::dvec3 centre = 0.5 * (lo + hi);
    const double radius = std::max(0.5 * glm::length(hi - lo), 0.5);
    const double az = glm::radians(v.azimuth), el = glm::radians(v.elevation);
    const glm::dvec3 dir(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    Camera c;
    c.width = width, c.height = height;
    const double d = v.distance * radius;
    c.eye = centre + d * dir;
    // Looking straight down or up, z cannot be the up vector: y is.
    const glm::dvec3 up = std::abs(std::sin(el)) > 0.999 ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1);
    c.view = glm::lookAt(c.eye, centre, up);
    const double nearPlane = std::max(d - radius, 1e-3 * d), farPlane = d + radius;
    c.projection = glm::perspective(glm::radians(kFieldOfViewDegrees), double(width) / double(height), nearPlane, farPlane);
    return c;
}

Camera topDownOrthographic(double x0, double x1, double y0, double y1, double bottom, double top, int width, int height) {
    Camera c;
    c.width = width, c.height = height;
    c.eye = {0.5 * (x0 + x1), 0.5 * (y0 + y1), top + 1.0};
    c.view = glm::lookAt(c.eye, c.eye - glm::dvec3(0, 0, 1), glm::dvec3(0, 1, 0));
    c.projection = glm::ortho(x0 - c.eye.x, x1 - c.eye.x, y0 - c.eye.y, y1 - c.eye.y, 0.5, top - bottom + 1.5);
    return c;
}

ViewAngles parseView(const std::string& text) {
    const std::optional<std::vector<double>> numbers = parseNumberList(text, 3);
    if (!numbers)
        throw Error("--view '" + text + "': expected azimuth,elevation,distance (degrees, degrees, sphere radii)");
    ViewAngles v;
    v.azimuth = (*numbers)[0];
    v.elevation = (*numbers)[1];
    v.distance = (*numbers)[2];
    if (v.azimuth < -360.0 || v.azimuth > 360.0) throw Error("--view '" + text + "': azimuth must lie in [-360, 360] degrees");
    if (v.elevation < -90.0 || v.elevation > 90.0)
        throw Error("--view '" + text + "': elevation must lie in [-90, 90] degrees");
    if (v.distance <= 0.0 || v.distance > 1e6) throw Error("--view '" + text + "': distance must lie in (0, 1e6] sphere radii");
    return v;
}

LightAngles parseLight(const std::string& text) {
    const std::optional<std::vector<double>> numbers = parseNumberList(text, 2);
    if (!numbers) throw Error("--light '" + text + "': expected azimuth,elevation (degrees, degrees)");
    LightAngles l{(*numbers)[0], (*numbers)[1]};
    if (l.azimuth < -360.0 || l.azimuth > 360.0) throw Error("--light '" + text + "': azimuth must lie in [-360, 360] degrees");
    if (l.elevation < -90.0 || l.elevation > 90.0) throw Error("--light '" + text + "': elevation must lie in [-90, 90] degrees");
    return l;
}

glm::dvec3 towardsLight(const LightAngles& light) {
    const double az = glm::radians(light.azimuth), el = glm::radians(light.elevation);
    return {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
}

} // namespace yv
