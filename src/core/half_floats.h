// Floats to IEEE halves in bulk, as a .vdb saved with half precision holds
// them: the same bits as OpenVDB's math::half (Imath: round to nearest, ties
// to even), eight at a time with F16C where the CPU has it. At 8192 the
// writer rounds four values a voxel twice (the record and its statistics),
// over a billion voxels; one Imath call a value was a fifth of its time.
#pragma once

#include <cstddef>
#include <cstdint>

namespace yv {

/// Writes the halves of in[0..n) to `out` as 2n little-endian bytes (any alignment).
void floatsToHalves(const float* in, void* out, std::size_t n);

/// out[i] = in[i] rounded to a half and back: the value a reader gets from a
/// half grid. `out` may be `in`.
void roundThroughHalves(const float* in, float* out, std::size_t n);

} // namespace yv
