// Voxelize what the camera sees: the part of the volume inside the view's
// pyramid, and the box and voxel size a run gives it (about a voxel a pixel
// at the point looked at, within a budget of voxels a side). Pure geometry,
// no GL: the live view asks it when the camera stops.
#pragma once

#include "core/voxel_box.h"
#include "core/voxel_grid.h"
#include "inspect/camera.h"

#include <glm/vec3.hpp>

#include <optional>
#include <string>

namespace yv {

/// The finest whole-garment resolution a view voxelization asks for: its
/// grid's voxel size is the garment's longest side over this, at least.
constexpr int kMaxViewResolution = 32768;

/// An axis-aligned box of real coordinates.
struct RealBox {
    glm::dvec3 min{0.0}, max{0.0};
    bool empty() const { return !(min.x < max.x && min.y < max.y && min.z < max.z); }
    bool contains(const RealBox& other) const;
};

/// The bounds of the part of `bounds` (voxel coordinates) inside the four
/// side planes of `camera`'s view pyramid (the near and far planes of a view
/// camera enclose the volume anyway). Empty when the camera sees none of it.
RealBox seenBox(const VoxelBox& bounds, const Camera& camera);

/// What a view voxelization runs: `voxelize --voxel-size V --bbox-world BOX`,
/// the numbers as their text says (what a command line reading the same text
/// runs on, to the bit).
struct ViewVoxelization {
    double voxelSize = 0.0;
    std::string voxelSizeText;
    RealBox world;        ///< the box, world units
    std::string boxText;  ///< "x0,y0,z0,x1,y1,z1"
    /// The yarn twist, radians per world unit, where the view set one other than the garment's.
    std::optional<double> twist;
    /// A coarser first pass, shown while the run asked for goes on (refinePass).
    bool firstPass = false;
    bool operator==(const ViewVoxelization& o) const {
        return voxelSizeText == o.voxelSizeText && boxText == o.boxText && twist == o.twist;
    }
};

/// The run for `camera` over `bounds` of a volume on `grid`: the seen box in
/// world units, grown by half a voxel and written with six significant
/// digits, and a voxel size the width of a pixel at the point looked at
/// (three significant digits), no finer than `maxSideVoxels` along the box's
/// longest side and `maxResolution` across the whole grid. None, with the
/// reason in `why`, when nothing is in view or the view's pixels are no
/// finer than the grid's voxels (voxelizing again would add nothing).
std::optional<ViewVoxelization> planViewVoxelization(const VoxelBox& bounds, const VoxelGrid& grid, const Camera& camera,
                                                     int maxSideVoxels, int maxResolution, std::string& why);

/// A view run this many voxels or more along its box's longest side is
/// shown first from a pass with voxels kRefineFactor times as large.
constexpr int kRefineFromVoxels = 128;
constexpr double kRefineFactor = 4.0;

/// The coarser first pass of `run` (the same box and twist, voxels
/// kRefineFactor times as large, three significant digits), which the view
/// shows while `run` goes on: a 64th of the voxels, there in a fraction of
/// the time. None where `run` is small (under kRefineFromVoxels along its
/// longest side) or the pass would be no finer than `openedVoxelSize`.
std::optional<ViewVoxelization> refinePass(const ViewVoxelization& run, double openedVoxelSize);

} // namespace yv
