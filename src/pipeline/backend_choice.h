// The one place a run's backend is chosen: from the job and whether a GPU's
// GL context could be made. Every later stage receives the choice.
#pragma once

#include "gpu/egl_context.h"
#include "pipeline/voxelize_job.h"

#include <exception>
#include <memory>

namespace yv {

/// What rasterizes the garment.
enum class Backend {
    Cpu,     ///< the TBB reference, region by region (cpu/cpu_region_backend.h)
    Gl,      ///< the GL backend, region by region (gpu/gl_voxelizer.h)
    GlDense, ///< the paper's dense 3D textures on GL (gpu/dense_voxelizer.h)
};

/// "cpu" or "gl" (the dense method too), as --stats, the .vdb's metadata and
/// the run fingerprint name the backend.
const char* backendName(Backend b);

/// The GL context made for a run before the backend is chosen (on the thread
/// that will drive the GPU, while another thread slices the garment), or the
/// one the job keeps, or the error making one threw; none where the job
/// never runs on GL.
struct GlStart {
    std::unique_ptr<GlContext> context; ///< made for this run
    const GlContext* kept = nullptr;    ///< the job's own (VoxelizeJob::glContext)
    std::exception_ptr error;
    double seconds = 0.0; ///< how long making it took
    /// The context the run drives, made or kept; null where there is none.
    const GlContext* current() const { return context ? context.get() : kept; }
};

/// Makes the job's GL context on this thread (or makes the job's own
/// current here) unless the job asks for the CPU backend. `spreadIndex`:
/// the MPI rank on its node (each rank its own GPU).
GlStart startGl(const VoxelizeJob& job, int spreadIndex);

/// The backend `job` runs on. --backend gl and the dense method need the
/// context (its error is thrown here when there is none); auto takes the GL
/// backend on a GPU, else the CPU reference, which on a machine without a GPU
/// is far faster than GL through a software rasteriser. `gl` keeps its
/// context only where the GL backend runs.
Backend chooseBackend(const VoxelizeJob& job, GlStart& gl);

} // namespace yv
