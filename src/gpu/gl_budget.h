// What the GL backend may use on a context: how it draws the slices, and the
// budgets of a pass (fragments, bricks, region size), from the context's
// limits, its free memory and the slice plan.
#pragma once

#include "gpu/egl_context.h"
#include "gpu/gl_voxelizer.h"

#include <epoxy/gl.h>

#include <cstdint>

namespace yv {

/// How the raster draws the slices (GlVoxelizeSettings::slicePrimitive settled).
struct SliceDrawing {
    /// Pixels around a region's face with point sprites, which keep every
    /// sprite's centre in the viewport (a point whose centre is clipped is
    /// dropped whole); 0: triangles.
    int pointMargin = 0;
    /// Slices a point sprite draws at most; 1 with triangles and in compute.
    int runSlices = 1;
    /// No draw: the sample items appended by a compute pass (slice_items.comp).
    bool compute = false;
    bool points() const { return pointMargin > 0; }
    /// "compute", "point" or "triangle", as --stats says it.
    const char* name() const { return compute ? "compute" : (points() ? "point" : "triangle"); }
};

/// Sample items in compute where asked for (and by Auto); else point
/// sprites where asked for (Raster: on a GPU) and where the driver's
/// point sizes hold the largest sprite the vertex shader can ask for; runs of
/// slices where the yarn is thin on the face. `support`: textureSupport() of
/// the cross-section. Throws yv::Error for a sliceRun out of range.
SliceDrawing chooseSliceDrawing(const GlVoxelizeSettings& settings, const SlicePlan& plan, const VoxelGrid& grid,
                                double support, const GlInfo& info);

/// The budgets of one pass on this context.
struct GlBudget {
    std::uint64_t capacity = 0;    ///< fragments (and sample items) a pass may append
    std::uint64_t brickBudget = 0; ///< bricks a pass may touch
    std::uint64_t maxBlock = 0;    ///< GL_MAX_SHADER_STORAGE_BLOCK_SIZE, bytes
    int regionCap = 1024;          ///< largest region edge in voxels
    GLuint maxGroups = 65535;      ///< work groups of one dispatch
    std::uint32_t uniformSlices = 0; ///< slices per segment when all segments agree, else 0
};

/// Every buffer within one shader storage block, all within half of the free
/// GPU memory (where the driver tells); regions within the viewport, less the
/// sprites' margin. `words`: wordsPerVoxel of the run. Throws yv::Error when
/// the fragment budget cannot hold what one segment puts into one brick.
GlBudget chooseBudget(const GlVoxelizeSettings& settings, const SlicePlan& plan, const VoxelGrid& grid,
                      const GlContext& context, const SliceDrawing& drawing, int words, bool albedo);

} // namespace yv
