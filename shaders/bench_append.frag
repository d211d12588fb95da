// Append microbenchmark: the least a fragment of append.frag must do, one
// atomic counter increment and one 16-byte Fragment store per fragment.

#include "layout.glsl"

layout(binding = 0, offset = 0) uniform atomic_uint uFragmentCount;
layout(std430, binding = 2) writeonly buffer Fragments { Fragment fragments[]; };
uniform uint uCapacity;

void main() {
    uint slot = atomicCounterIncrement(uFragmentCount);
    if (slot < uCapacity) {
        uvec2 p = uvec2(gl_FragCoord.xy);
        fragments[slot] = Fragment(p.x << 12 | p.y, slot, 0u, 0u);
    }
}
