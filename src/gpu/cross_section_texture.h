// The cross-section on the GPU, as the sampling shaders (append.frag,
// dense.frag) read it.
#pragma once

#include "garment/cross_section.h"

#include <epoxy/gl.h>

#include <string>
#include <vector>

namespace yv {

/// An R8UI texture of the cross-section's density, read with texelFetch and
/// textureGather: nearest filtering, clamped to the edge (the gather then
/// clamps at the border as CrossSection::bilinear does). The caller deletes it.
GLuint uploadCrossSectionTexture(const CrossSection& xs);

/// An RGB32F texture of the fibres' colour times density (CrossSection::albedo,
/// for --albedo), read as the density texture is. The caller deletes it.
GLuint uploadAlbedoTexture(const CrossSection& xs);

/// How the sampling shader reads a bilinear lookup's four texels: one
/// textureGather, or four texelFetch (the same texels; common.glsl says which
/// is faster where). Auto: the gather on EGL's surfaceless platform (where
/// yarnvox gets Mesa's llvmpipe), fetches on an EGL device (a GPU).
enum class TexelReads { Auto, Fetch, Gather };

/// The #defines that pick the sampling shader's variant: the analytic disk's
/// exact coverage or the texture (each variant compiles only the code it
/// runs), and the texel reads, Auto resolved for `platform` (GlInfo::platform).
std::vector<std::string> crossSectionDefines(const CrossSection& xs, TexelReads reads, const std::string& platform);

} // namespace yv
