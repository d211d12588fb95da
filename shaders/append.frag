// Raster pass: appends one sample item (a slice, and this pixel of the
// region's face) for each slice drawn here (one, or with point sprites a run
// of them: slice.vert) whose footprint at this pixel can hold fibre. The
// sampling pass (sample.comp) then turns each item into voxel fragments on
// every compute unit; here only the test whether the footprint comes within
// the cross-section's support, widened a little, so that float rounding in
// this stage never drops a sample that sample.comp would keep.

#include "layout.glsl"

layout(binding = kItemCountAtomic, offset = 0) uniform atomic_uint uItemCount;
// x: the slice (its instance in the draw), y: the pixel on the region's face, x | y << 16.
layout(std430, binding = kItemsBinding) writeonly buffer Items { uvec2 items[]; };
// The counter's own word, then a flag set once a slot reaches 2^31 (as for
// the fragment list, sample.comp).
layout(std430, binding = kItemCounterBinding) buffer ItemCounter { uint itemWord; uint itemWrapped; };

uniform uint uItemCapacity;   // items the list holds; the counter goes on past it
uniform int uMargin;          // pixels around the region's face in the viewport (slice.vert)

// The slices drawn (slice.vert: a run of them with point sprites, else
// one) and each one's test terms.
flat in ivec4 vRun;
flat in vec4 vAt[kRunSlices];
flat in vec4 vSteps[kRunSlices];

void main() {
    ivec2 local = ivec2(gl_FragCoord.xy) - uMargin;
    ivec2 face = ivec2(vRun.w & 0xffff, vRun.w >> 16);
    if (any(lessThan(local, ivec2(0))) || any(greaterThanEqual(local, face))) return;
    vec2 steps = vec2(local - vRun.xy);
    for (int i = 0; i < kRunSlices; ++i) {
        // Where the column through this pixel meets the slice
        // (columnCrossing), and whether the footprint about it comes within
        // the support (by the footprint's reach, slice.vert, widened by its
        // slack).
        vec2 xy = vAt[i].xy + steps.x * vSteps[i].xy + steps.y * vSteps[i].zw;
        if (dot(xy, xy) > vAt[i].z) continue;

        uint slot = atomicCounterIncrement(uItemCount);
        if (slot >= 0x80000000u) itemWrapped = 1u;
        if (slot < uItemCapacity) items[slot] = uvec2(uint(vRun.z + i), uint(local.x) | (uint(local.y) << 16));
    }
}
