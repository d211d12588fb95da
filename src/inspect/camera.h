// The camera of `yarnvox inspect --render`: a view of a voxel box from an
// azimuth and an elevation (degrees; z is up, azimuth 0 looks from +x), at a
// distance in radii of the box's bounding sphere. Coordinates are voxel
// indices: voxel (i, j, k) fills [i, i+1) x [j, j+1) x [k, k+1).
#pragma once

#include "inspect/volume_source.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <string>

namespace yv {

struct ViewAngles {
    double azimuth = 30.0, elevation = 20.0;
    double distance = 4.0; ///< bounding-sphere radii from the centre; 4 fits the sphere in the 30 degree field of view
};

struct Camera {
    glm::dmat4 view{1.0}, projection{1.0};
    glm::dvec3 eye{0.0};
    int width = 0, height = 0;
    glm::dmat4 viewProjection() const { return projection * view; }
};

/// Vertical field of view of the perspective camera.
constexpr double kFieldOfViewDegrees = 30.0;

/// A perspective camera looking at the centre of `box`. The near and far
/// planes enclose the bounding sphere where the eye is outside it.
Camera frameBox(const VoxelBox& box, const ViewAngles& view, int width, int height);

/// An orthographic camera looking down -z onto the rectangle [x0, x1] x [y0, y1]
/// from above `top` (for pictures that map pixels to voxel columns).
Camera topDownOrthographic(double x0, double x1, double y0, double y1, double bottom, double top, int width, int height);

/// Parses "azimuth,elevation,distance"; throws yv::Error saying what is wrong.
ViewAngles parseView(const std::string& text);

/// Where a directional light comes from (the half-angle render's): degrees
/// about +z from +x, degrees above the xy plane.
struct LightAngles {
    double azimuth = 75.0, elevation = 45.0;
};

/// Parses "azimuth,elevation"; throws yv::Error saying what is wrong.
LightAngles parseLight(const std::string& text);

/// The unit vector from the volume towards the light.
glm::dvec3 towardsLight(const LightAngles& light);

} // namespace yv
