// `--render volumetric-triangles`: a garment previewed as a soft volume
// without voxelizing it. Every slice's square (two triangles) is drawn as a
// Gaussian-blurred volumetric triangle, after the appendix of
// ../shared/reference/volumetric-triangle-shader-appendix.txt: a geometry
// shader bounds each triangle on screen, a fragment shader integrates its
// absorbance along the view ray, and the absorbances add up per pixel.
#pragma once

#include "garment/slices.h"
#include "gpu/gl_buffer.h"
#include "gpu/gl_objects.h"
#include "gpu/gl_program.h"
#include "inspect/transfer_function.h"
#include "inspect/volume_source.h"
#include "plan/grid.h"
#include "render/renderer.h"

namespace yv {

/// The box of brick-aligned voxels the slices of `plan` reach on `grid`,
/// clipped to the grid: what a volume voxelized from them frames.
VoxelBox sliceBox(const SlicePlan& plan, const VoxelGrid& grid);

class VolumetricTriangleRenderer : public Renderer {
  public:
    /// Draws the slices of `plan`, placed on `grid` (coordinates in its
    /// voxels). Each slice's slab holds fibre of density `yarnDensity`
    /// inside the yarn's disk; the picture's colour and opacity per voxel of
    /// yarn are `tf`'s at that density, as the ray cast of a volume of it
    /// would show. Throws yv::Error when the plan has no slices.
    VolumetricTriangleRenderer(const SlicePlan& plan, const VoxelGrid& grid, const TransferFunction& tf,
                               double yarnDensity = 1.0);

    /// The absorbance per pixel: the length of yarn on its ray, in voxels.
    std::vector<GLenum> targetFormats() const override { return {GL_R32F}; }
    /// Places every slice on the host, in batches, and draws them.
    void draw(const Frame& frame) override;
    /// The absorbance as the fibre's colour and opacity, over black (read and made on the host).
    PendingRgbImage startPicture(const Frame& frame) override;

  private:
    void setUniforms(const Camera& camera) const;

    const SlicePlan& plan_;
    const VoxelGrid& grid_;
    TransferFunction tf_;
    double yarnDensity_;
    GlProgram program_;
    GlBuffer batchBuffer_;
    GlVertexArray batchArray_;
};

} // namespace yv
