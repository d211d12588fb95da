#include "plan/box_request.h"

#include "core/error.h"
#include "core/text.h"
#include "core/world_units.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace yv {
namespace {

/// "i0,j0,k0,i1,j1,k1".
std::string boxText(const VoxelBox& b) {
    std::string out;
    for (int v : {b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z}) out += (out.empty() ? "" : ",") + std::to_string(v);
    return out;
}

/// Voxel index coordinate `u` (possibly huge) rounded by `round`, held within
/// a range no grid reaches past (grids stay below 2^24 voxels an axis), so it
/// converts to int and clips to the grid as it would have unclamped.
int clampedIndex(double u) { return int(std::clamp(u, -double(1 << 30), double(1 << 30))); }

} // namespace

BoxRequest parseBoxRequest(bool world, const std::string& text) {
    BoxRequest r;
    r.world = world;
    r.text = text;
    const auto fail = [&](const std::string& why) { throw Error(r.named() + ": " + why); };
    std::stringstream in(text);
    std::size_t count = 0;
    for (std::string item; std::getline(in, item, ',');) {
        char* end = nullptr;
        const double x = std::strtod(item.c_str(), &end);
        if (item.empty() || end != item.c_str() + item.size())
            fail("'" + item + "' is not a number: expected six numbers x0,y0,z0,x1,y1,z1");
        if (count == 6) fail("more than six numbers: expected x0,y0,z0,x1,y1,z1");
        if (const std::string p = coordinateProblem(x); !p.empty()) fail("a coordinate " + p);
        if (!world && x != std::floor(x))
            fail(numberText(x) + " is not a whole number: voxel indices are (use --bbox-world for world units)");
        r.values[count++] = x;
    }
    if (count != 6) fail(std::to_string(count) + " numbers: expected six, x0,y0,z0,x1,y1,z1");
    for (int a = 0; a < 3; ++a)
        if (!(r.values[a + 3] > r.values[a]))
            fail(std::string("holds nothing along ") + "xyz"[a] + ": " + numberText(r.values[a + 3]) +
                 " is not above " + numberText(r.values[a]) +
                 (world ? "" : " (the maximum is exclusive and must exceed the minimum)"));
    return r;
}

std::string BoxOnGrid::text() const { return boxText(box); }

BoxOnGrid placeBox(const BoxRequest& request, const VoxelGrid& grid) {
    BoxOnGrid out;
    const std::array<double, 6>& v = request.values;
    for (int a = 0; a < 3; ++a) {
        if (request.world) {
            // Voxel i covers origin + [i, i+1) h: the cells that overlap [x0, x1].
            const double u0 = (v[a] - grid.origin[a]) / grid.voxelSize, u1 = (v[a + 3] - grid.origin[a]) / grid.voxelSize;
            out.asked.min[a] = clampedIndex(std::floor(u0));
            out.asked.max[a] = clampedIndex(std::ceil(u1));
            // A box thinner than a voxel within one cell still holds that voxel.
            if (out.asked.max[a] <= out.asked.min[a]) out.asked.max[a] = out.asked.min[a] + 1;
        } else {
            out.asked.min[a] = clampedIndex(v[a]);
            out.asked.max[a] = clampedIndex(v[a + 3]);
        }
    }
    out.box = intersect(out.asked, {glm::ivec3(0), grid.dims});
    if (out.box.empty()) {
        const glm::dvec3 far = grid.origin + glm::dvec3(grid.dims) * grid.voxelSize;
        throw Error(request.named() + ": the box lies outside the garment's grid (voxels 0,0,0 to " +
                    std::to_string(grid.dims.x) + "," + std::to_string(grid.dims.y) + "," + std::to_string(grid.dims.z) +
                    " exclusive, world " + numberText(grid.origin.x) + "," + numberText(grid.origin.y) + "," +
                    numberText(grid.origin.z) + " to " + numberText(far.x) + "," + numberText(far.y) + "," +
                    numberText(far.z) + "): nothing to voxelize");
    }
    out.clipped = !(out.box == out.asked);
    return out;
}

} // namespace yv
