// OpenVDB output: a float grid "density" (fog volume, background 0) and a
// vec3 grid "orientation" sharing one transform, built leaf by leaf.
#pragma once

#include "core/bricks.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace yv {

struct VolumeMetadata {
    std::string input;        ///< garment file or generator description
    std::string backend;      ///< "cpu" or "gl"
    std::string crossSection; ///< "fibers", "disk" or a PNG path
    int resolution = 0;       ///< voxels on the longest axis asked for (0: from voxel size)
    std::uint64_t sliceCount = 0;
    double yarnRadius = 0.0;
    std::string yarnRadiusSource;  ///< "option", "cross-section", "file" or "estimated"
    double twist = 0.0;
    int supersample = 1;
    std::string overlap = "clamp"; ///< how interpenetrating yarns add up (mean reduction)
    double sliceSpacing = 0.0;     ///< largest distance between slices along a yarn, world units
};

/// How OpenVDB compresses each leaf's values: only the active values (no
/// codec; yarnvox's default: OpenVDB writes serially, and for fractional
/// densities this is about twice as fast as blosc for 7 to 12 % more bytes),
/// blosc (OpenVDB's default), zip, or nothing.
enum class VdbCompression { Blosc, Zip, ActiveMask, None };

const char* toString(VdbCompression c);
/// "blosc", "zip", "mask" or "none"; throws yv::Error otherwise.
VdbCompression parseVdbCompression(const std::string& name);

/// Where the time of a write went.
struct VdbWriteTimings {
    double readSeconds = 0.0;  ///< merge: regions read, verified and turned into leaves
    double treeSeconds = 0.0;  ///< leaves into two trees, in key order
    double writeSeconds = 0.0; ///< OpenVDB's serial write, fsync and rename
};

struct VdbWriteOptions {
    VdbCompression compression = VdbCompression::ActiveMask;
    VdbWriteTimings* timings = nullptr; ///< filled when given
};

/// Writes `volume` to `path` through a temporary file and a rename, so a
/// failed run never leaves a file that looks finished. Voxel (i, j, k) of the
/// grid has index (i, j, k) and its centre at grid.origin + (i + 0.5) h.
void writeVdb(const std::string& path, const BrickVolume& volume, const VolumeMetadata& metadata,
              const VdbWriteOptions& options = {});

/// What writeVdb and the brick store's merge share: bricks handed over in
/// batches become OpenVDB leaves at once (so the bricks can be freed), and
/// write() puts the leaves into the trees in key order, so the file does not
/// depend on batch order or thread count.
class VdbAssembler {
  public:
    VdbAssembler(const VoxelGrid& grid, Reduce reduce);
    ~VdbAssembler();
    VdbAssembler(const VdbAssembler&) = delete;
    VdbAssembler& operator=(const VdbAssembler&) = delete;

    /// Turns `bricks` into leaves, in parallel. Thread-safe; `source` names the batch in errors.
    void add(std::span<const VoxelBrick> bricks, const std::string& source = "");
    /// Bricks added so far.
    std::size_t brickCount() const;
    /// Builds the grids and writes them to `path` as writeVdb does; throws
    /// yv::Error when a brick was added twice. Call once.
    void write(const std::string& path, const VolumeMetadata& metadata, const VdbWriteOptions& options = {});

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace yv
