// The transfer function as the shaders read it: a 1D texture of its 256
// RGBA entries (32-bit floats), linearly filtered and clamped at the ends.
// The ray caster, the slicing renderers and the splats share it (the
// context must be current).
#pragma once

#include "gpu/gl_objects.h"
#include "inspect/transfer_function.h"

namespace yv {

class TransferFunctionTexture {
  public:
    explicit TransferFunctionTexture(const TransferFunction& tf);
    /// Replaces the entries (the next draw reads them).
    void update(const TransferFunction& tf);
    GLuint id() const { return texture_.id(); }

  private:
    GlTexture texture_;
};

} // namespace yv
