#include "inspect/region_outlines.h"

#include <glm/common.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>

namespace yv {
namespace {

void setPixel(RgbImage& image, int x, int y, glm::vec3 c) {
    if (x < 0 || y < 0 || x >= image.width || y >= image.height) return;
    std::uint8_t* p = image.at(x, y);
    for (int k = 0; k < 3; ++k) p[k] = std::uint8_t(std::lround(255.0f * std::clamp(c[k], 0.0f, 1.0f)));
}

/// One edge from a to b (voxel coordinates), clipped to the near side of the camera.
void drawEdge(RgbImage& image, const Camera& camera, glm::dvec3 a, glm::dvec3 b, glm::vec3 colour) {
    const glm::dmat4 vp = camera.viewProjection();
    glm::dvec4 ca = vp * glm::dvec4(a, 1.0), cb = vp * glm::dvec4(b, 1.0);
    // Clip against the near plane (z >= -w) where the edge crosses it.
    const double da = ca.z + ca.w, db = cb.z + cb.w;
    if (da < 0.0 && db < 0.0) return;
    if (da < 0.0) ca = glm::mix(ca, cb, da / (da - db));
    if (db < 0.0) cb = glm::mix(cb, ca, db / (db - da));
    const auto toPixel = [&](const glm::dvec4& c) {
        return glm::dvec2((c.x / c.w + 1.0) * 0.5 * camera.width, (1.0 - c.y / c.w) * 0.5 * camera.height);
    };
    const glm::dvec2 pa = toPixel(ca), pb = toPixel(cb);
    // Lines far outside the picture: only the part near it is walked.
    const double steps = std::min(std::ceil(std::max(std::abs(pb.x - pa.x), std::abs(pb.y - pa.y))) + 1.0, 1e5);
    for (double i = 0.0; i <= steps; ++i) {
        const glm::dvec2 p = glm::mix(pa, pb, i / steps);
        setPixel(image, int(std::floor(p.x)), int(std::floor(p.y)), colour);
    }
}

} // namespace

glm::vec3 heatColour(double t) {
    const glm::vec3 ramp[] = {{0.1f, 0.3f, 1.0f}, {0.95f, 0.1f, 0.1f}, {1.0f, 1.0f, 0.2f}};
    const float s = float(std::clamp(t, 0.0, 1.0)) * 2.0f;
    const int i = std::min(int(s), 1);
    return glm::mix(ramp[i], ramp[i + 1], s - float(i));
}

void drawRegionOutlines(RgbImage& image, const Camera& camera, const std::vector<RegionHeat>& regions) {
    if (regions.empty()) return;
    double low = regions.front().heat, high = low;
    for (const RegionHeat& r : regions) low = std::min(low, r.heat), high = std::max(high, r.heat);
    for (const RegionHeat& r : regions) {
        const glm::vec3 colour = heatColour(high > low ? (r.heat - low) / (high - low) : 1.0);
        const glm::dvec3 lo(r.box.min), hi(r.box.max);
        const auto corner = [&](int c) { return glm::dvec3(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z); };
        for (int c = 0; c < 8; ++c)
            for (int axis = 0; axis < 3; ++axis)
                if (!(c & (1 << axis))) drawEdge(image, camera, corner(c), corner(c | (1 << axis)), colour);
    }
    // The legend: the ramp, coolest at the left, along the bottom left.
    const int length = std::min(image.width / 3, 256), thickness = std::max(2, image.height / 60);
    if (length < 8) return;
    for (int x = 0; x < length; ++x)
        for (int y = 0; y < thickness; ++y)
            setPixel(image, 2 + x, image.height - 3 - y, heatColour(double(x) / double(length - 1)));
}

} // namespace yv
