// Where a render's bricks come from: a work directory's region files, a
// .vdb read through OpenVDB with delayed loading, or bricks in memory. A
// source lists which bricks are occupied (cheap: headers and topology) and
// then hands over the voxels of only the bricks a render asks for, one at a
// time, so no stage holds the volume.
#pragma once

#include "core/bricks.h"
#include "core/run_metadata.h"
#include "core/voxel_box.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace yv {

class KeptBricks;

/// One 8^3 brick as a source hands it over: values in brickOffset order,
/// inactive voxels 0.
struct SourceBrick {
    glm::ivec3 coord{0};                   ///< brick coordinate: voxel index / 8 (may be negative in a foreign .vdb)
    const float* density = nullptr;        ///< 512 values
    const glm::vec3* orientation = nullptr; ///< 512 unit axes, or nullptr when the source has none
    const std::uint64_t* active = nullptr;  ///< 8 words of active voxels where the source has them, else nullptr
};

class VolumeSource {
  public:
    using Visit = std::function<void(const SourceBrick&)>;
    VolumeSource();
    virtual ~VolumeSource() = default;
    VolumeSource(const VolumeSource&) = delete;
    VolumeSource& operator=(const VolumeSource&) = delete;

    /// A number no other source of this process has: what caches key on.
    std::uint64_t id() const { return id_; }

    /// The levels the source stores, ascending: 0 (the volume), then the
    /// coarse levels a .vdb holds as density_lodL grids (formats/vdb-subset.md).
    /// A stored level L's brick spans 8 * 2^L voxels of level 0.
    const std::vector<int>& storedLevels() const { return storedLevels_; }
    bool hasCoarseLevels() const { return storedLevels_.size() > 1; }
    /// Coordinates of every brick with an active voxel, sorted by brickKey
    /// order (read from headers or topology only).
    const std::vector<glm::ivec3>& occupiedBricks() const { return occupiedLevelBricks(0); }
    /// The same for stored level `level` (level bricks), read on first use.
    virtual const std::vector<glm::ivec3>& occupiedLevelBricks(int level) const;
    /// At most this many bricks are occupied at stored level `level`, without
    /// reading its topology when the source can tell from its headers.
    virtual std::uint64_t occupiedBricksAtLeast(int level) const { return occupiedLevelBricks(level).size(); }
    bool hasOrientation() const { return hasOrientation_; }
    /// The voxel box of the occupied bricks (brick-aligned).
    virtual VoxelBox bounds() const;
    /// Voxel bounds of zoom region `id`; throws yv::Error when the source has
    /// no such region (a .vdb records regions only when yarnvox wrote it).
    virtual VoxelBox regionBounds(std::uint64_t id) const = 0;
    /// Calls `visit` once for every occupied brick whose coordinate lies in
    /// [brickMin, brickMax), in any order, one call at a time. Reads only
    /// what those bricks need.
    void forEachBrick(glm::ivec3 brickMin, glm::ivec3 brickMax, const Visit& visit) const {
        visitBricks(0, brickMin, brickMax, visit, false);
    }
    /// The same for stored level `level`: coordinates and values are the level's.
    void forEachLevelBrick(int level, glm::ivec3 brickMin, glm::ivec3 brickMax, const Visit& visit) const {
        visitBricks(level, brickMin, brickMax, visit, false);
    }
    /// The same as forEachBrick, with `visit` called from several threads at
    /// once where the source reads in parallel.
    void forEachBrickConcurrently(glm::ivec3 brickMin, glm::ivec3 brickMax, const Visit& visit) const {
        visitBricks(0, brickMin, brickMax, visit, true);
    }

  protected:
    virtual void visitBricks(int level, glm::ivec3 brickMin, glm::ivec3 brickMax, const Visit& visit,
                             bool concurrent) const = 0;

    std::uint64_t id_;
    std::vector<glm::ivec3> occupied_; ///< level 0, for sources that list it when opened
    std::vector<int> storedLevels_{0};
    bool hasOrientation_ = false;
};

/// A work directory (readers take a shared lock; region checksums are checked
/// as regions are read). Throws yv::Error naming `dir` when it is not one.
std::unique_ptr<VolumeSource> openStoreSource(const std::string& dir);
/// An OpenVDB file with a float `density` grid (and a Vec3f `orientation`
/// grid where there is one). yarnvox's own files are read by its reader
/// (vdb/vdb_index.h): topology first, leaf values in parallel ranges, never
/// held, and their coarse levels are stored levels; other files go through
/// OpenVDB (openVdbSourceThroughOpenVdb). Throws yv::Error naming `path`
/// (and the grid and leaf where the file is damaged).
std::unique_ptr<VolumeSource> openVdbSource(const std::string& path);
/// The same through OpenVDB's delayed loading, level 0 only, whoever wrote
/// the file: only the leaves a render touches are read, but they stay loaded.
std::unique_ptr<VolumeSource> openVdbSourceThroughOpenVdb(const std::string& path);
/// Bricks already in memory (tests, benchmarks); regions are given as boxes by id.
std::unique_ptr<VolumeSource> memorySource(const BrickVolume& volume, std::vector<VoxelBox> regions = {});
/// A run's bricks kept in memory as it stored them (the live view's runs):
/// level 0 only, no regions recorded. Throws yv::Error when two regions hold
/// the same brick.
std::unique_ptr<VolumeSource> keptBricksSource(std::shared_ptr<const KeptBricks> bricks);
/// The box of zoom region `id` among the regions a .vdb at `path` records;
/// throws yv::Error when it records none or not that one.
VoxelBox recordedRegionBox(const std::vector<RecordedRegion>& regions, std::uint64_t id, const std::string& path);
/// A work directory or a .vdb, by what `path` is.
std::unique_ptr<VolumeSource> openVolumeSource(const std::string& path);

} // namespace yv
