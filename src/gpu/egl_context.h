// Headless OpenGL 4.5 core context through EGL: the device platform for real
// GPUs, the surfaceless platform (Mesa llvmpipe) where there is none.
#pragma once

#include <memory>
#include <string>

namespace yv {

struct GlContextOptions {
    /// Index among the EGL devices that can give a GL 4.5 context; -1 picks the
    /// first hardware device, else the surfaceless (software) platform.
    int device = -1;
    bool debug = false; ///< Request a debug context and print driver messages.
    /// With device -1: take the hardware device at this index modulo the usable
    /// count (the processes of an MPI run on one node spread over its GPUs).
    int spreadIndex = 0;
};

/// Where a context comes from: a GPU through EGL's device platform, or Mesa's
/// software rasteriser (llvmpipe) through the surfaceless platform.
enum class GlPlatform { Device, Surfaceless };

/// "device" or "surfaceless", as --stats and messages say it.
inline const char* platformName(GlPlatform p) { return p == GlPlatform::Device ? "device" : "surfaceless"; }

/// Limits and names read off the live context; budgets are derived from these.
struct GlInfo {
    std::string vendor, renderer, version;
    GlPlatform platform = GlPlatform::Surfaceless;
    /// A GPU (the device platform), not the software rasteriser.
    bool hardware() const { return platform == GlPlatform::Device; }
    long long maxSsboBlockSize = 0; ///< GL_MAX_SHADER_STORAGE_BLOCK_SIZE, bytes
    int maxComputeWorkGroupCountX = 0;
    int maxTextureSize = 0;
    int max3dTextureSize = 0;
    int maxViewportDims[2] = {0, 0};
    /// Free GPU memory in bytes where the driver reports it (NVX_gpu_memory_info,
    /// ATI_meminfo), else -1.
    long long freeMemoryBytes = -1;
    bool hasConservativeRaster = false; ///< GL_NV_conservative_raster
};

/// Owns an EGL display and a current GL 4.5 core context (no surface). Creating
/// one throws yv::Error with one line that says what is missing and what to
/// install (or to use --backend cpu) when no GL 4.5 context can be had.
class GlContext {
  public:
    explicit GlContext(const GlContextOptions& options = {});
    ~GlContext();
    GlContext(const GlContext&) = delete;
    GlContext& operator=(const GlContext&) = delete;

    const GlInfo& info() const;
    /// Re-reads free GPU memory (-1 when the driver cannot tell).
    long long queryFreeMemoryBytes() const;

    /// Makes the context current on the calling thread (one made, or
    /// released, on another).
    void makeCurrent() const;
    /// Leaves the calling thread without a current context, so that another
    /// thread may make this one current.
    void releaseCurrent() const;

    /// True when a context can be created here (for tests that skip cleanly).
    static bool available();

    /// A second context on this one's display and device that shares its
    /// objects (programs, buffers, textures), current on the calling thread:
    /// work for this context done on another thread. Throws yv::Error.
    std::unique_ptr<GlContext> makeSharing() const;

  private:
    struct Impl;
    explicit GlContext(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

} // namespace yv
