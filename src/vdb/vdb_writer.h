// OpenVDB output: a float grid "density" (fog volume, background 0) and a
// vec3 grid "orientation" sharing one transform, written leaf by leaf; with
// --albedo, a vec3 grid "albedo" (linear RGB) too; with a pyramid (--lod,
// the preview by default), the same grids again at each coarser level.
#pragma once

#include "core/bricks.h"
#include "core/packed_bricks.h"
#include "core/run_metadata.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace yv {

/// How each leaf's values are compressed (OpenVDB's options): only the
/// active values, no codec (yarnvox's default: for fractional densities about
/// twice as fast as blosc for 7 to 12 % more bytes), blosc (OpenVDB's
/// default), zip (OpenVDB skips zip on fog volumes, so it applies to the
/// orientation grid only), or nothing.
enum class VdbCompression { Blosc, Zip, ActiveMask, None };

const char* toString(VdbCompression c);
/// "blosc", "zip", "mask" or "none"; throws yv::Error otherwise.
VdbCompression parseVdbCompression(const std::string& name);
/// OpenVDB's archive flags (io::COMPRESS_*) for `c`.
std::uint32_t archiveFlags(VdbCompression c);

/// What `voxelize` and `merge` do about streaming leaves (VdbWriteOptions::
/// streamLeaves): yes, unless YV_STREAM_LEAVES=0 (1 is yes too; anything
/// else throws yv::Error in one line).
bool streamLeavesFromEnvironment();

/// How the grids' floats are stored: 32-bit, or 16-bit halves (OpenVDB's
/// saveFloatAsHalf; a density step of at most 2^-11 relative).
enum class VdbPrecision { Float, Half };
const char* toString(VdbPrecision p);
/// "float" or "half"; throws yv::Error otherwise.
VdbPrecision parseVdbPrecision(const std::string& name);
/// What `voxelize` and `merge` write without --precision: half, whose
/// renders in Cycles match float's within the sampling noise
/// (bench/half_vs_float.sh) for about half the bytes. VdbWriteOptions keeps
/// float: a caller of the writer asks for the rounding.
inline constexpr VdbPrecision kDefaultVdbPrecision = VdbPrecision::Half;

/// Where the time of a write went.
struct VdbWriteTimings {
    double readSeconds = 0.0;     ///< merge: regions read, verified and handed to the writer
    double encodeSeconds = 0.0;   ///< leaves compressed and put in the scratch file, summed over threads,
                                  ///< and the level-of-detail pyramid built (--lod)
    double topologySeconds = 0.0; ///< leaves sorted into tree order, topology made
    double writeSeconds = 0.0;    ///< the file written in parallel, fsync and rename
    /// Bytes of leaf records written while bricks were still being added
    /// (VdbAssembler::streamRegions), and the seconds that took on the stream's thread.
    std::uint64_t streamedBytes = 0;
    std::uint64_t streamedBeforeEndBytes = 0; ///< of those, while some region was not done yet
    double streamSeconds = 0.0;
};

struct VdbWriteOptions {
    VdbCompression compression = VdbCompression::ActiveMask;
    VdbPrecision precision = VdbPrecision::Float;
    /// --lod: grids density_lodL and orientation_lodL for L = lodFirstLevel
    /// ..lodLevels (none when lodLevels is 0), level L at 2^-L of level 0's
    /// resolution (vdb/lod_pyramid.h); lodLevels at most maxLodLevels(grid).
    /// The first level is 1 (the full pyramid, --lod N) or 3 (the preview,
    /// vdb/lod_request.h): any of 1 to 3 is built from level 0 directly.
    int lodLevels = 0;
    int lodFirstLevel = 1;
    /// --albedo: a third grid "albedo" from VoxelBrick::albedo, which every
    /// brick must then have (and albedo_lodL with lodLevels).
    bool albedo = false;
    VdbWriteTimings* timings = nullptr; ///< added to when given
    /// Whether a run's regions (without a work dir, or merged from one) have
    /// their leaves streamed into the file as they come
    /// (VdbAssembler::streamRegions); streamLeavesFromEnvironment() for the commands.
    bool streamLeaves = false;
    /// Bytes of the scratch space for encoded leaves held in memory, the
    /// rest in a file beside the output (vdb/spill_file.h; spillMemoryBytes()
    /// for the commands, shared by the processes of a node).
    std::uint64_t scratchMemoryBytes = 0;
    /// Bytes per chunk of the output (vdb/chunked_output.h; 0: its default).
    /// Tests make it small, so that chunks cut through leaf records.
    std::uint64_t outputChunkBytes = 0;
};

/// Writes `volume` to `path` through a temporary file and a rename, so a
/// failed run never leaves a file that looks finished. Voxel (i, j, k) of the
/// grid has index (i, j, k) and its centre at grid.origin + (i + 0.5) h; in
/// level L of the pyramid, h is replaced by 2^L h.
void writeVdb(const std::string& path, const BrickVolume& volume, const VolumeMetadata& metadata,
              const VdbWriteOptions& options = {});

/// yarnvox's streaming .vdb writer (formats/vdb-subset.md): bricks handed
/// over in batches, from any thread, are encoded into OpenVDB leaf records at
/// once (in parallel) and kept in an unnamed scratch file beside the output,
/// so no tree is ever held; write() puts the topology and then the leaves in
/// tree order, in parallel. The file has the bytes OpenVDB's own writer gives
/// for the same grids (but its random UUID), whatever the batch order or thread count.
class VdbAssembler {
  public:
    /// Throws yv::Error when `grid` cannot have options.lodLevels levels (checkedLodLevels).
    /// lodFirstLevel is 1 to 3, and at most lodLevels when that is not 0.
    VdbAssembler(std::string path, const VoxelGrid& grid, Reduce reduce, const VdbWriteOptions& options = {});
    ~VdbAssembler();
    VdbAssembler(const VdbAssembler&) = delete;
    VdbAssembler& operator=(const VdbAssembler&) = delete;

    /// Encodes `bricks`. Thread-safe; `source` names the batch in errors.
    void add(std::span<const VoxelBrick> bricks, const std::string& source = "");
    /// The same for bricks the GPU resolved, read where they came back
    /// packed (same records, without unpacking them first).
    void add(const PackedBricks& bricks, const std::string& source = "");
    /// Starts writing level 0's leaf records into the output while bricks
    /// are still being added (vdb/leaf_stream.h), where the output's file
    /// system can cut holes out of a file (ext4, XFS): the bricks then come
    /// region by region, every brick of region i at or after tree order key
    /// firstOrders[i] (vdb/tree_order.h; not decreasing with i), and
    /// regionDone(i) says when region i has all its bricks. Returns whether
    /// the records stream (not for one region, whose leaves all come at the
    /// end); if not, they are written at the end as without.
    /// The file then differs from OpenVDB's writer's by a few zero bytes
    /// before each of level 0's grids' data (formats/vdb-subset.md).
    bool streamRegions(std::vector<std::uint64_t> firstOrders);
    /// Every brick of region i is added (after streamRegions). Thread-safe.
    void regionDone(std::size_t region);
    /// Bricks added so far.
    std::size_t brickCount() const;
    /// Builds the level-of-detail grids (options.lodFirstLevel..lodLevels)
    /// from the bricks' octants and writes the file; throws yv::Error when a
    /// brick was added twice. Call once.
    void write(const VolumeMetadata& metadata);

  private:
    template <typename Batch> void addBatchOf(const Batch& bricks, const std::string& source);

    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace yv
