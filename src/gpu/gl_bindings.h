// The binding points of the shaders' storage blocks, atomic counters,
// textures and images, by name: shaders/bindings.glsl, the one list that
// every shader is compiled with (GlProgram puts it first) and that C++
// includes here, so a buffer is bound under the name its block is declared
// with, never under a bare number. GL-free, as gpu_layout.h.
#pragma once

namespace yv {

#include "bindings.glsl"

} // namespace yv
