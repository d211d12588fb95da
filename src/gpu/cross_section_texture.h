// The cross-section on the GPU, as the sampling shaders (append.frag,
// dense.frag) read it.
#pragma once

#include "garment/cross_section.h"
#include "gpu/gl_objects.h"

#include <string>
#include <vector>

namespace yv {

/// How the sampling shader reads a bilinear lookup's four texels (all give
/// the same texels, clamped at the border as CrossSection::bilinear clamps):
/// Quad: one texelFetch of an RGBA8UI texture whose texel holds the four;
/// Gather: one textureGather of the R8UI density texture; Fetch: four
/// texelFetch of it. Auto is Quad, the fastest on both drivers measured: on
/// NVIDIA's the four fetches took a quarter of the raster's time and a gather
/// 1.7 times as long as they did; on llvmpipe the quad takes a quarter off
/// the gather's raster time, and the gather a third off the fetches'.
enum class TexelReads { Auto, Fetch, Gather, Quad };

/// `reads` with Auto resolved.
TexelReads texelReadsFor(TexelReads reads);

/// The cross-section's density as the texel reads `reads` (not Auto) expect:
/// R8UI for Fetch and Gather; for Quad, (size + 1)^2 RGBA8UI texels, texel
/// (u, v) holding the density at (u - 1, v - 1), (u, v - 1), (u - 1, v) and
/// (u, v), each coordinate clamped to [0, size - 1]. Nearest filtering,
/// clamped to the edge.
GlTexture uploadCrossSectionTexture(const CrossSection& xs, TexelReads reads);

/// An RGB32F texture of the fibres' colour times density (CrossSection::albedo,
/// for --albedo), read with four texelFetch.
GlTexture uploadAlbedoTexture(const CrossSection& xs);

/// The #defines that pick the sampling shader's variant: the analytic disk's
/// exact coverage or the texture (each variant compiles only the code it
/// runs), and the texel reads `reads` (not Auto).
std::vector<std::string> crossSectionDefines(const CrossSection& xs, TexelReads reads);

} // namespace yv
