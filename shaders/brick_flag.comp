// Brick pass 1: flag every brick of the region that a fragment touches.

#include "layout.glsl"

layout(local_size_x = 256) in;

layout(std430, binding = kFragmentsBinding) readonly buffer Fragments { Fragment fragments[]; };
layout(std430, binding = kBrickSlotsBinding) buffer Flags { uint flags[]; };

uniform uint uCount;

void main() {
    // Grid-stride loop: the dispatch size stays under the work-group limit.
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint i = gl_GlobalInvocationID.x; i < uCount; i += stride) flags[fragments[i].key >> 9] = 1u;
}
