#include "inspect/proxy_geometry.h"

#include <unordered_set>

namespace yv {

std::vector<glm::vec3> proxyTriangles(const LevelPlan& plan) {
    std::unordered_set<std::uint64_t> occupied;
    for (const glm::ivec3& b : plan.bricks) occupied.insert(brickKey(b));
    const auto isOccupied = [&](glm::ivec3 b) {
        return b.x >= 0 && b.y >= 0 && b.z >= 0 && occupied.count(brickKey(b));
    };
    const float span = float(kBrickSize * plan.scale);
    const glm::vec3 origin(plan.originVoxel);
    std::vector<glm::vec3> out;
    for (const glm::ivec3& b : plan.bricks)
        for (int axis = 0; axis < 3; ++axis)
            for (int side = 0; side < 2; ++side) {
                glm::ivec3 n = b;
                n[axis] += side ? 1 : -1;
                if (isOccupied(n)) continue;
                // The face's four corners: the brick's corner moved to the face, then along the other two axes.
                const int u = (axis + 1) % 3, v = (axis + 2) % 3;
                glm::vec3 p0(b);
                p0[axis] += float(side);
                glm::vec3 du(0.0f), dv(0.0f);
                du[u] = 1.0f, dv[v] = 1.0f;
                const glm::vec3 c[4] = {p0, p0 + du, p0 + du + dv, p0 + dv};
                for (int i : {0, 1, 2, 0, 2, 3}) out.push_back(origin + span * c[i]);
            }
    return out;
}

} // namespace yv
