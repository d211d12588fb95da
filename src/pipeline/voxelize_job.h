// What `yarnvox voxelize` is asked, typed and checked once: the CLI parses
// its options into a VoxelizeJob (src/cli/cmd_voxelize.cpp), checkJob states
// every rule between them, and the pipeline (voxelize_run.h) only reads it.
#pragma once

#include "core/error.h"
#include "core/sampling.h"
#include "plan/box_request.h"
#include "vdb/lod_request.h"
#include "vdb/vdb_writer.h"

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace yv {

class GlContext;
class KeptBricks;
class SlicePlanCache;

/// Where a run's warnings and notes go, one line at a time.
using Tell = std::function<void(const std::string&)>;

/// --backend: which rasterizer runs the zoom regions (chooseBackend settles Auto).
enum class BackendRequest { Auto, Gl, Cpu };
/// --method: yarnvox's sparse bricks, or the paper's dense 3D textures (a benchmark baseline).
enum class VoxelizeMethod { Sparse, Dense };
/// --sample-items: how the GL backend finds the pixels each slice can put
/// fibre in: the slices drawn and the fragment shader appending them
/// (Raster), or a compute pass testing each slice's pixels (Compute); Auto
/// settles it by the device (rasterizers.cpp).
enum class SampleItemsRequest { Auto, Raster, Compute };

/// One garment's voxelization (option names in the comments).
struct VoxelizeJob {
    std::string input, output;                          ///< INPUT, -o
    BackendRequest backend = BackendRequest::Auto;      ///< --backend
    SampleItemsRequest sampleItems = SampleItemsRequest::Auto; ///< --sample-items
    VoxelizeMethod method = VoxelizeMethod::Sparse;     ///< --method
    std::string crossSection = "fibers";                ///< --cross-section: fibers, disk or FILE.png
    Reduce reduce = Reduce::Mean;                       ///< --reduce
    Overlap overlap = Overlap::Clamp;                   ///< --overlap
    VdbCompression compression = VdbCompression::ActiveMask; ///< --vdb-compression
    VdbPrecision precision = kDefaultVdbPrecision;      ///< --precision
    std::string statsPath, workDir;                     ///< --stats, --work-dir
    int resolution = 0;                                 ///< --resolution (0: --voxel-size)
    double voxelSize = 0.0;                             ///< --voxel-size
    double yarnRadius = 0.0;                            ///< --yarn-radius (0: from the files, else estimated)
    int slicesPerSegment = 0;                           ///< --slices-per-segment
    double spacing = 0.0;                               ///< --slice-spacing
    double twist = 0.0;                                 ///< --twist
    int supersample = 1;                                ///< --supersample
    int device = -1;                                    ///< --device (-1: first GPU, else llvmpipe)
    std::uint64_t fragmentCapacity = 0;                 ///< --fragment-budget (0: from the machine)
    LodRequest lod;                                     ///< --lod: level-of-detail grids in the .vdb (lodOf)
    /// --bbox or --bbox-world: voxelize only this box, on the grid the whole
    /// garment and --resolution or --voxel-size fix (none: the whole garment).
    std::optional<BoxRequest> box;
    bool albedo = false;  ///< --albedo: the cross-section PNG's colour as an "albedo" grid
    bool resume = false, keepWorkDir = false;           ///< --resume, --keep-work-dir
    /// Where set, the garment read and its slice plan are taken from (and
    /// kept for) runs of the same file and slice options: the live view's runs.
    std::shared_ptr<SlicePlanCache> sliceCache;
    /// Where set, a run whose regions go straight into the .vdb (no work
    /// dir) also keeps its resolved bricks here. With no output (an empty
    /// `output`) the run writes nothing and keeps only these: the live view
    /// draws its runs from them and voxelizes again into a file only when
    /// one is saved. Runs through a work dir keep nothing.
    std::shared_ptr<KeptBricks> keepBricks;
    /// No file is written: the bricks are kept, and nothing else (see keepBricks).
    bool bricksOnly() const { return output.empty() && keepBricks; }
    /// Where set, the caller may give the run up by setting it (the live
    /// view, when a newer view is asked for): the run stops once the garment
    /// is sliced, within its planning (ZoomPlanOptions::stop) or at its next
    /// zoom region boundary, and throws RunCancelled before the .vdb is written;
    /// a run into the .vdb alone leaves nothing, one through a work dir the
    /// regions written so far (a resume goes on from them).
    std::shared_ptr<const std::atomic<bool>> cancel;
    /// Where set, a run on the GL backend drives this context (made current
    /// on the calling thread, and left current there) instead of making one
    /// and freeing it: the live view's voxelizer keeps one a thread between
    /// its runs (making and freeing one took about 75 ms a run on the H200).
    /// One run at a time.
    std::shared_ptr<GlContext> glContext;
    bool quiet = false, verbose = false;                ///< --quiet, --verbose
    /// Under mpirun: this rank voxelizes the garment by itself, as one
    /// process would (whole garments handed out to ranks), on its own GPU.
    bool alone = false;

    /// The regions go through a work directory (asked for, kept, resumed, or
    /// shared by the ranks of an MPI run) rather than straight into the .vdb.
    bool throughWorkDir(bool sharedByRanks) const { return !workDir.empty() || keepWorkDir || resume || sharedByRanks; }
};

/// A run given up through VoxelizeJob::cancel: nothing written.
class RunCancelled : public Error {
  public:
    explicit RunCancelled(const std::string& what) : Error(what) {}
};

/// Throws RunCancelled, saying `where`, when `job` has been given up.
void throwIfCancelled(const VoxelizeJob& job, const std::string& where);

/// Every rule between a job's options, each stated here once, checked
/// before any work: where the results go (-o and --stats writable and
/// distinct from the input), a grid size given, the supersample range, what
/// the dense method, --albedo and --bbox need. `sharedByRanks`: the run's regions are
/// shared by the ranks of an MPI run. Throws yv::Error with one line.
void checkJob(const VoxelizeJob& job, bool sharedByRanks);

/// The pyramid the job's .vdb gets: --lod as asked, but the preview (the
/// default) only with the sparse method: the dense method is the paper's
/// baseline and writes no pyramid unless --lod N asks for one.
LodRequest lodOf(const VoxelizeJob& job);

/// "auto", "gl" or "cpu", as the option is spelled.
const char* toString(BackendRequest b);
const char* toString(SampleItemsRequest r);
/// "sparse" or "dense".
const char* toString(VoxelizeMethod m);

} // namespace yv
