// Raster pass: appends one sample item (the slice, and this pixel of the
// region's face) for each pixel whose footprint can hold fibre. The sampling
// pass (sample.comp) then turns each item into voxel fragments on every
// compute unit; here only the test whether the footprint comes within the
// cross-section's support, widened a little, so that float rounding in this
// stage never drops a sample that sample.comp would keep.

// Nothing to test against (no depth or stencil): whether the hardware then
// drops its ordering of fragments with side effects.
layout(early_fragment_tests) in;

layout(binding = 0, offset = 0) uniform atomic_uint uItemCount;
// x: the slice (its instance in the draw), y: the pixel on the region's face, x | y << 16.
layout(std430, binding = 6) writeonly buffer Items { uvec2 items[]; };
// The counter's own word, then a flag set once a slot reaches 2^31 (as for
// the fragment list, sample.comp).
layout(std430, binding = 7) buffer ItemCounter { uint itemWord; uint itemWrapped; };

uniform uint uItemCapacity;   // items the list holds; the counter goes on past it
uniform int uMargin;          // pixels around the region's face in the viewport (slice.vert)

flat in int vInstance;
// The test's terms, from the slice (slice.vert).
flat in ivec4 vFace;
flat in vec2 vAtOrigin;
flat in vec4 vSteps;
flat in float vLimit;

void main() {
    ivec2 local = ivec2(gl_FragCoord.xy) - uMargin;
    if (any(lessThan(local, ivec2(0))) || any(greaterThanEqual(local, vFace.zw))) return;
    // Where the column through this pixel meets the slice (columnCrossing),
    // and whether the footprint about it comes within the support (by the
    // footprint's reach, slice.vert, widened by its slack).
    vec2 steps = vec2(local - vFace.xy);
    vec2 xy = vAtOrigin + steps.x * vSteps.xy + steps.y * vSteps.zw;
    if (dot(xy, xy) > vLimit * vLimit) return;

    uint slot = atomicCounterIncrement(uItemCount);
    if (slot >= 0x80000000u) itemWrapped = 1u;
    if (slot < uItemCapacity) items[slot] = uvec2(uint(vInstance), uint(local.x) | (uint(local.y) << 16));
}
