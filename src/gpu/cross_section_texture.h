// The cross-section on the GPU, as the sampling shaders (append.frag,
// dense.frag) read it.
#pragma once

#include "garment/cross_section.h"

#include <epoxy/gl.h>

#include <string>

namespace yv {

/// An R8UI texture of the cross-section's density, read with texelFetch and
/// textureGather: nearest filtering, clamped to the edge (the gather then
/// clamps at the border as CrossSection::bilinear does). The caller deletes it.
GLuint uploadCrossSectionTexture(const CrossSection& xs);

/// The #define that picks the sampling shader's variant: the analytic disk's
/// exact coverage, or the texture. Each variant compiles only the code it runs.
std::string crossSectionDefine(const CrossSection& xs);

} // namespace yv
