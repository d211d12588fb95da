#include "inspect/volume_cut.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace yv {

CutPlane parseCut(const std::string& text) {
    const auto bad = [&] { return Error("--cut '" + text + "': expected x:INDEX, y:INDEX or z:INDEX (a voxel index)"); };
    if (text.size() < 3 || text[1] != ':' || (text[0] != 'x' && text[0] != 'y' && text[0] != 'z')) throw bad();
    char* end = nullptr;
    const long v = std::strtol(text.c_str() + 2, &end, 10);
    if (end != text.c_str() + text.size() || v < -(1L << 30) || v > (1L << 30)) throw bad();
    return {text[0] - 'x', int(v)};
}

RgbImage renderCut(const VolumeSource& source, const VoxelBox& box, const CutPlane& cut) {
    const int a = cut.axis;
    if (cut.index < box.min[a] || cut.index >= box.max[a])
        throw Error("--cut " + std::string(1, char('x' + a)) + ":" + std::to_string(cut.index) + ": outside the volume's voxels [" +
                    std::to_string(box.min[a]) + ", " + std::to_string(box.max[a]) + ") along " + std::string(1, char('x' + a)));
    // Image axes: u to the right, v up.
    const int u = a == 0 ? 1 : 0, v = a == 2 ? 1 : 2;
    RgbImage image(box.max[u] - box.min[u], box.max[v] - box.min[v]);
    glm::ivec3 lo = box.min >> 3, hi = (box.max + 7) >> 3;
    lo[a] = cut.index >> 3, hi[a] = lo[a] + 1;
    const int local = cut.index & 7;
    source.forEachBrick(lo, hi, [&](const SourceBrick& b) {
        for (int i = 0; i < 8; ++i)
            for (int j = 0; j < 8; ++j) {
                glm::ivec3 l;
                l[a] = local, l[u] = i, l[v] = j;
                const glm::ivec3 voxel = b.coord * 8 + l;
                const int px = voxel[u] - box.min[u], py = box.max[v] - 1 - voxel[v];
                if (px < 0 || px >= image.width || py < 0 || py >= image.height) continue;
                const float d = std::clamp(b.density[brickOffset(l.x, l.y, l.z)], 0.0f, 1.0f);
                const auto grey = std::uint8_t(std::lround(255.0f * d));
                std::uint8_t* p = image.at(px, py);
                p[0] = p[1] = p[2] = grey;
            }
    });
    return image;
}

} // namespace yv
