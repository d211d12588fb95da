#include "pipeline/voxelize_job.h"

#include "core/error.h"
#include "core/output_path.h"
#include "core/voxelize_settings.h"

namespace yv {

void checkJob(const VoxelizeJob& job, bool sharedByRanks) {
    // Where the results go is checked before minutes of work, not after.
    if (job.bricksOnly() && (job.throughWorkDir(sharedByRanks) || job.method == VoxelizeMethod::Dense))
        throw Error("a run that keeps its bricks in memory and writes no file needs the sparse method without a work dir");
    if (!job.bricksOnly()) checkOutputPath(job.output, "-o", {job.input});
    if (!job.statsPath.empty()) {
        checkOutputPath(job.statsPath, "--stats", {job.input, job.output});
        if (job.statsPath == job.output)
            throw Error("--stats " + job.statsPath + ": is the same file as -o: refusing to overwrite it");
    }
    const bool dense = job.method == VoxelizeMethod::Dense;
    if (job.box && dense) throw Error(job.box->named() + ": a box needs the sparse method (--method dense voxelizes the whole grid)");
    if (dense && sharedByRanks) throw Error("--method dense runs in one process, not under mpirun -np 2 or more");
    if (dense && job.backend == BackendRequest::Cpu) throw Error("--method dense needs --backend gl");
    if (job.sampleItems != SampleItemsRequest::Auto && (dense || job.backend == BackendRequest::Cpu))
        throw Error(std::string("--sample-items ") + toString(job.sampleItems) +
                    ": goes with the GL backend's sparse method (not --backend cpu or --method dense)");
    if (dense && (!job.workDir.empty() || job.resume)) throw Error("--work-dir and --resume need the sparse method");
    // Without it the run went to memory and --resume was silently ignored.
    if (job.resume && job.workDir.empty())
        throw Error("--resume needs --work-dir DIR: the work directory of the run to go on with (one kept by "
                    "--keep-work-dir is " + job.output + ".work)");
    // --albedo's limits: the sparse method with the mean reduction carries the colour (on either backend).
    if (job.albedo && dense) throw Error("--albedo: the dense method has no albedo; use --method sparse");
    if (job.albedo && job.reduce != Reduce::Mean)
        throw Error("--albedo needs --reduce mean (a colour is averaged like the density, not maxed)");
    // The box selects voxels of the grid the options define; it never defines one.
    if (job.box && job.resolution == 0 && job.voxelSize == 0.0)
        throw Error(job.box->named() + ": the box lies on the grid of the whole garment, which is not defined yet: "
                    "give --resolution N (voxels on the longest axis) or --voxel-size H");
    if (job.resolution == 0 && job.voxelSize == 0.0)
        throw Error("give --resolution N (voxels on the longest axis) or --voxel-size H");
    checkSupersample(job.supersample);
}

LodRequest lodOf(const VoxelizeJob& job) {
    if (job.method == VoxelizeMethod::Dense && job.lod.kind == LodRequest::Kind::Preview) return LodRequest::none();
    return job.lod;
}

void throwIfCancelled(const VoxelizeJob& job, const std::string& where) {
    if (job.cancel && job.cancel->load()) throw RunCancelled("given up " + where + ": nothing was written");
}

const char* toString(BackendRequest b) {
    switch (b) {
    case BackendRequest::Gl: return "gl";
    case BackendRequest::Cpu: return "cpu";
    case BackendRequest::Auto: break;
    }
    return "auto";
}

const char* toString(SampleItemsRequest r) {
    switch (r) {
    case SampleItemsRequest::Raster: return "raster";
    case SampleItemsRequest::Compute: return "compute";
    case SampleItemsRequest::Auto: break;
    }
    return "auto";
}

const char* toString(VoxelizeMethod m) { return m == VoxelizeMethod::Dense ? "dense" : "sparse"; }

} // namespace yv
