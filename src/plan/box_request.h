// `voxelize --bbox` and `--bbox-world`: the box of the garment a run
// voxelizes, as asked on the command line, and where it lies on the grid
// that the whole garment and --resolution or --voxel-size fix.
#pragma once

#include "core/voxel_box.h"
#include "core/voxel_grid.h"

#include <array>
#include <string>

namespace yv {

/// The box as asked: six numbers x0,y0,z0,x1,y1,z1, voxel indices (--bbox,
/// max exclusive) or world units (--bbox-world).
struct BoxRequest {
    bool world = false;
    std::array<double, 6> values{};
    std::string text; ///< as typed, for messages

    /// "--bbox 0,0,0,64,64,32", as messages name it.
    std::string named() const { return (world ? "--bbox-world " : "--bbox ") + text; }
};

/// Parses `text` as the option says (`world`: --bbox-world). Throws yv::Error
/// "OPTION TEXT: why" for anything but six comma-separated finite numbers
/// (whole ones for --bbox) within yarnvox's coordinate range, each maximum
/// above its minimum.
BoxRequest parseBoxRequest(bool world, const std::string& text);

/// Where a box request lies on a grid.
struct BoxOnGrid {
    VoxelBox asked;       ///< the voxels asked for, perhaps reaching past the grid
    VoxelBox box;         ///< those of the grid: what the run voxelizes
    bool clipped = false; ///< asked != box

    /// "i0,j0,k0,i1,j1,k1" of `box`, as the run records it.
    std::string text() const;
};

/// The voxels of `grid` the request holds: --bbox as given, --bbox-world
/// every voxel whose cell overlaps the world box (a face that lies on a
/// voxel boundary takes no voxel beyond it), then clipped to the grid.
/// Throws yv::Error naming the option, its value and the grid's extent when
/// the box and the grid share no voxel.
BoxOnGrid placeBox(const BoxRequest& request, const VoxelGrid& grid);

} // namespace yv
