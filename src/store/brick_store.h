// The on-disk brick store of the out-of-core pipeline: a work directory with a
// manifest and one checksummed, lz4-compressed file of resolved bricks per
// region. Layout and rules: formats/brick-store.md.
#pragma once

#include "core/bricks.h"
#include "core/read_only_file.h"
#include "core/sampling.h"
#include "core/voxel_grid.h"
#include "store/manifest.h"
#include "store/region_file.h" // xxh64, for callers hashing their run fingerprint

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace yv {

/// One region file as its header describes it.
struct RegionInfo {
    std::uint64_t id = 0;
    glm::ivec3 min{0}, max{0}; ///< voxel bounds, min inclusive, max exclusive
    std::uint64_t brickCount = 0, activeVoxels = 0, bytesOnDisk = 0;
};

/// Where writeRegion spent its time (for the pipeline's counters).
struct RegionWriteTimings {
    double encodeSeconds = 0.0; ///< serialise, compress, checksum
    double writeSeconds = 0.0;  ///< write, fsync, rename, fsync the directory
};

/// Tag for the constructor that joins a store another process opened.
struct JoinStore {};

class BrickStore {
  public:
    /// Opens `dir` (created if missing) for a run. resume: keep the regions of
    /// an earlier run with the same fingerprint, grid and reduce mode (throws
    /// yv::Error naming the difference otherwise). !resume: start over, deleting
    /// the store's own files; throws instead when `dir` holds any file the
    /// store did not write. Holds an exclusive lock on `dir` while alive.
    BrickStore(std::string dir, const StoreManifest& manifest, bool resume);
    /// Joins the store that rank 0 of an MPI run opened for writing (it holds
    /// the lock for all ranks): takes no lock and deletes nothing; throws
    /// yv::Error when the manifest on disk is of a different run.
    BrickStore(std::string dir, const StoreManifest& manifest, JoinStore);
    /// Opens an existing store read-only (merge, inspection): shared lock, no
    /// file is changed or deleted; hasVerifiedRegion, writeRegion and markComplete throw.
    explicit BrickStore(std::string dir);
    ~BrickStore();
    BrickStore(const BrickStore&) = delete;
    BrickStore& operator=(const BrickStore&) = delete;

    /// What verifyRegion found of a region's file.
    enum class RegionState {
        Verified, ///< on disk, of this run and these bounds, every check passed
        Missing,  ///< no file: the run never wrote it
        Damaged,  ///< a file that fails a check (or is another run's): deleted
    };
    /// Whether region `id` is on disk, belongs to this run with these bounds and
    /// passes every check (checksums, decompression). A file that fails is
    /// deleted and the reason put in `whyNot` ("not on disk" when there is
    /// none): the caller recomputes the region.
    RegionState verifyRegion(std::uint64_t id, glm::ivec3 min, glm::ivec3 max, std::string* whyNot = nullptr);
    bool hasVerifiedRegion(std::uint64_t id, glm::ivec3 min, glm::ivec3 max, std::string* whyNot = nullptr) {
        return verifyRegion(id, min, max, whyNot) == RegionState::Verified;
    }
    /// Writes the bricks of one region (any order; written sorted by key)
    /// atomically: afterwards the file is complete, or absent after a crash.
    /// Bricks must be distinct and overlap [min, max). Also call it for a region
    /// without bricks, so a resumed run knows it is done. Thread-safe for distinct ids.
    RegionInfo writeRegion(std::uint64_t id, glm::ivec3 min, glm::ivec3 max, std::vector<VoxelBrick> bricks,
                           RegionWriteTimings* timings = nullptr);
    /// Every region file, sorted by id, from its header (checksum, size and run
    /// checked); throws yv::Error on a damaged or foreign one rather than skip it.
    std::vector<RegionInfo> listRegions() const;
    /// Ids of the region files on disk, sorted, from their names alone (nothing read).
    std::vector<std::uint64_t> regionIds() const;
    /// One region file from its header (checksum, size and run checked); throws yv::Error when damaged.
    RegionInfo regionInfo(std::uint64_t id) const;
    /// The bricks of region `id`, sorted by key, after every check; throws yv::Error when damaged.
    std::vector<VoxelBrick> readRegion(std::uint64_t id) const;
    class ChunkReader;
    /// Calls `visit` once for each chunk of region `id`'s bricks, from
    /// several threads at once, each chunk read and decoded on its own into
    /// the calling thread's buffers: memory stays at two chunks (32 MiB) a
    /// thread whatever the region's size. Every check of readRegion is made;
    /// the first failure throws yv::Error after the other chunks were visited,
    /// so a caller keeps what it gathered only when no error came.
    void forEachChunk(std::uint64_t id, const std::function<void(const RawBricks&)>& visit) const;
    /// Records in the manifest that the run wrote all `regionCount` regions;
    /// throws when the directory holds a different number of region files.
    /// `stages`: the seconds the run spent in each stage, kept beside it.
    void markComplete(std::uint64_t regionCount, const StageSeconds& stages = {});

    /// Path of region `id`'s file.
    std::string regionPath(std::uint64_t id) const;
    const std::string& dir() const { return dir_; }
    const StoreManifest& manifest() const { return manifest_; }
    bool readOnly() const { return readOnly_; }
    /// Total size of the region files now on disk.
    std::uint64_t bytesOnDisk() const;

  private:
    void requireWritable(const char* what) const;

    std::string dir_;
    StoreManifest manifest_;
    bool readOnly_ = false;
    int dirFd_ = -1; ///< held open for the lock and for fsyncing the directory
};

/// One region file opened for reading chunk by chunk: the header, key index
/// and chunk table are read and checked when it opens; each chunk is read
/// and checked when asked for, from any thread.
class BrickStore::ChunkReader {
  public:
    /// Throws yv::Error naming the file when it is missing, damaged or of another run.
    ChunkReader(const BrickStore& store, std::uint64_t id);
    std::size_t chunkCount() const { return table_.chunks.size(); }
    /// The region's brick keys, ascending (from the checked key index).
    const std::vector<std::uint64_t>& keys() const { return table_.keys; }
    /// Reads chunk `c` into `stored` and decodes it into `raw` (both reused
    /// across calls), after its checksums; throws yv::Error naming the chunk.
    RawBricks read(std::size_t c, std::vector<std::uint8_t>& stored, std::vector<std::uint8_t>& raw) const;
    /// Throws yv::Error unless the chunks' active voxels, summed by the caller
    /// over every chunk, are what the header says.
    void checkActiveVoxels(std::uint64_t counted) const;

  private:
    ReadOnlyFile file_;
    RegionHeader header_;
    RegionTable table_;
};

/// Reads the manifest of an existing work directory (for `yarnvox merge WORKDIR`).
StoreManifest readManifest(const std::string& dir);

} // namespace yv
