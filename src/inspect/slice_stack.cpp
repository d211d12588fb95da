#include "inspect/slice_stack.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace yv {

std::vector<glm::dvec3> boxSlice(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3& normal, double offset) {
    const glm::dvec3 n = glm::normalize(normal);
    auto corner = [&](int i) { return glm::dvec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z); };
    std::vector<glm::dvec3> points;
    // The 12 edges: corner pairs that differ in one bit.
    for (int a = 0; a < 8; ++a)
        for (int bit = 1; bit < 8; bit <<= 1) {
            if (a & bit) continue;
            const glm::dvec3 p = corner(a), q = corner(a | bit);
            const double dp = glm::dot(n, p) - offset, dq = glm::dot(n, q) - offset;
            if ((dp < 0.0) == (dq < 0.0) || dp == dq) continue;
            points.push_back(p + (q - p) * (dp / (dp - dq)));
        }
    if (points.size() < 3) return {};
    glm::dvec3 centre(0.0);
    for (const glm::dvec3& p : points) centre += p;
    centre /= double(points.size());
    // Order the corners by angle in a basis of the plane.
    const glm::dvec3 u = glm::normalize(glm::cross(n, std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    const glm::dvec3 v = glm::cross(n, u);
    std::sort(points.begin(), points.end(), [&](const glm::dvec3& a, const glm::dvec3& b) {
        return std::atan2(glm::dot(a - centre, v), glm::dot(a - centre, u)) <
               std::atan2(glm::dot(b - centre, v), glm::dot(b - centre, u));
    });
    return points;
}

double boxDepth(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3& direction) {
    return glm::dot(glm::abs(direction), hi - lo);
}

SliceStack sliceStack(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3& normal, double spacing) {
    const glm::dvec3 n = glm::normalize(normal);
    const double low = glm::dot(n, 0.5 * (lo + hi)) - 0.5 * boxDepth(lo, hi, n);
    const int slices = std::max(1, int(std::ceil(boxDepth(lo, hi, n) / spacing)));
    SliceStack s;
    s.spacing = spacing;
    for (int k = 0; k < slices; ++k) {
        const std::vector<glm::dvec3> polygon = boxSlice(lo, hi, n, low + (k + 0.5) * spacing);
        s.first.push_back(int(s.triangles.size()));
        for (std::size_t i = 1; i + 1 < polygon.size(); ++i)
            for (const glm::dvec3& p : {polygon[0], polygon[i], polygon[i + 1]}) s.triangles.emplace_back(p);
        s.count.push_back(int(s.triangles.size()) - s.first.back());
    }
    return s;
}

} // namespace yv
