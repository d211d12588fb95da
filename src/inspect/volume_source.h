// Where a render's bricks come from: a work directory's region files, a
// .vdb read through OpenVDB with delayed loading, or bricks in memory. A
// source lists which bricks are occupied (cheap: headers and topology) and
// then hands over the voxels of only the bricks a render asks for, one at a
// time, so no stage holds the volume.
#pragma once

#include "core/bricks.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace yv {

/// Voxel box, min inclusive, max exclusive.
struct VoxelBox {
    glm::ivec3 min{0}, max{0};
    bool empty() const { return max.x <= min.x || max.y <= min.y || max.z <= min.z; }
};

/// One 8^3 brick as a source hands it over: values in brickOffset order,
/// inactive voxels 0.
struct SourceBrick {
    glm::ivec3 coord{0};                   ///< brick coordinate: voxel index / 8 (may be negative in a foreign .vdb)
    const float* density = nullptr;        ///< 512 values
    const glm::vec3* orientation = nullptr; ///< 512 unit axes, or nullptr when the source has none
};

class VolumeSource {
  public:
    virtual ~VolumeSource() = default;
    /// Coordinates of every brick with an active voxel, sorted by brickKey order
    /// after the source's origin shift (read from headers or topology only).
    const std::vector<glm::ivec3>& occupiedBricks() const { return occupied_; }
    bool hasOrientation() const { return hasOrientation_; }
    /// The voxel box of the occupied bricks (brick-aligned).
    VoxelBox bounds() const;
    /// Voxel bounds of zoom region `id`; throws yv::Error when the source has
    /// no such region (a .vdb records regions only when yarnvox wrote it).
    virtual VoxelBox regionBounds(std::uint64_t id) const = 0;
    /// Calls `visit` once for every occupied brick whose coordinate lies in
    /// [brickMin, brickMax), in any order. Reads only what those bricks need.
    virtual void forEachBrick(glm::ivec3 brickMin, glm::ivec3 brickMax,
                              const std::function<void(const SourceBrick&)>& visit) const = 0;

  protected:
    std::vector<glm::ivec3> occupied_;
    bool hasOrientation_ = false;
};

/// A work directory (readers take a shared lock; region checksums are checked
/// as regions are read). Throws yv::Error naming `dir` when it is not one.
std::unique_ptr<VolumeSource> openStoreSource(const std::string& dir);
/// An OpenVDB file with a float `density` grid (and a Vec3f `orientation`
/// grid where there is one), opened with delayed loading so only the leaves a
/// render touches are read. Throws yv::Error naming `path` otherwise.
std::unique_ptr<VolumeSource> openVdbSource(const std::string& path);
/// Bricks already in memory (tests, benchmarks); regions are given as boxes by id.
std::unique_ptr<VolumeSource> memorySource(const BrickVolume& volume, std::vector<VoxelBox> regions = {});
/// A work directory or a .vdb, by what `path` is.
std::unique_ptr<VolumeSource> openVolumeSource(const std::string& path);

} // namespace yv
