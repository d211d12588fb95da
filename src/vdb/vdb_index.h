// yarnvox's own reader of the .vdb subset it writes (formats/vdb-subset.md):
// the file's header, metadata and grid descriptors, and, per grid on
// demand, its topology as a table of leaves and where each leaf's record
// lies. Values are read later, leaf range by leaf range (vdb/leaf_reader.h),
// so no tree is ever built: OpenVDB's delayed loading keeps every leaf it
// has touched, which made one picture of an 8192 volume take 35 GB.
//
// Every size, count and offset is checked against the file before it is
// used; a file outside the subset (another compression, another transform,
// tiles, other grid types) is reported as such, and callers open it through
// OpenVDB instead.
#pragma once

#include "vdb/file_cursor.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace yv {

/// One metadata item as stored: its type name and value bytes.
struct StoredMetadata {
    std::string name, type;
    std::vector<std::uint8_t> value;
    /// The value as text (numbers, strings, vectors as OpenVDB prints them).
    std::string text() const;
};

/// One grid of the file, from its descriptor and metadata.
struct VdbGridInfo {
    std::string name, type; ///< type as stored, "_HalfFloat" removed
    bool half = false;
    bool vector = false;     ///< Vec3s values (orientation, albedo), else float
    int lodLevel = 0;        ///< grid metadata lod_level, 0 without
    std::uint64_t gridPos = 0, blockPos = 0, endPos = 0;
    std::uint64_t topologyPos = 0; ///< where the topology starts (after the transform)
    std::uint32_t compression = 0;
    double voxelSize = 0.0;
    glm::dvec3 translation{0.0};
    std::vector<StoredMetadata> metadata; ///< the grid's items but file_delayed_load
    const StoredMetadata* find(const std::string& name) const;
};

/// The leaves of one grid, in the file's (tree) order.
struct VdbLeafTable {
    std::vector<glm::ivec3> bricks;     ///< leaf origin / 8
    std::vector<std::uint64_t> records; ///< where each leaf's record starts, then where the last one ends
    std::uint64_t activeVoxels = 0;
};

class VdbIndex {
  public:
    /// Reads the header and every grid's descriptor, metadata and transform.
    /// Throws yv::Error naming the file and byte when it is damaged or not a
    /// .vdb; `inSubset()` says whether yarnvox's reader can read its leaves.
    explicit VdbIndex(const std::string& path);

    const ReadOnlyFile& file() const { return *file_; }
    const std::string& path() const { return file_->path(); }
    bool inSubset() const { return whyNotSubset_.empty(); }
    /// Why the file is outside the subset ("" when it is inside).
    const std::string& whyNotSubset() const { return whyNotSubset_; }
    std::string libraryVersion() const { return libraryVersion_; }
    const std::vector<StoredMetadata>& fileMetadata() const { return fileMetadata_; }
    const std::vector<VdbGridInfo>& grids() const { return grids_; }
    /// Where the first grid's descriptor starts and how many grids the file
    /// declares, inside the subset or not (0 and 0 for another file format version).
    std::uint64_t gridsPos() const { return gridsPos_; }
    std::uint32_t gridCount() const { return gridCount_; }
    /// The grid named `name`, or nullptr.
    const VdbGridInfo* grid(const std::string& name) const;
    /// Reads `grid`'s topology: its leaves and their records' places, each
    /// checked against the file (inSubset() only). Throws yv::Error naming
    /// the file, grid and byte or leaf.
    VdbLeafTable leaves(const VdbGridInfo& grid) const;

  private:
    std::unique_ptr<ReadOnlyFile> file_;
    std::string libraryVersion_;
    std::vector<StoredMetadata> fileMetadata_;
    std::vector<VdbGridInfo> grids_;
    std::uint64_t gridsPos_ = 0;
    std::uint32_t gridCount_ = 0;
    std::string whyNotSubset_;
};

} // namespace yv
