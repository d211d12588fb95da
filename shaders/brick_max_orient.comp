// Brick pass 4 (max only): among the fragments that reached their voxel's
// max density, the largest axis code wins, as in the CPU reduction.

#include "layout.glsl"

layout(local_size_x = 256) in;

layout(std430, binding = kFragmentsBinding) readonly buffer Fragments { Fragment fragments[]; };
layout(std430, binding = kBrickSlotsBinding) readonly buffer Slots { uint slots[]; };
layout(std430, binding = kBrickWordsBinding) buffer BrickWords { uint words[]; };

uniform uint uCount;

void main() {
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint i = gl_GlobalInvocationID.x; i < uCount; i += stride) {
        Fragment f = fragments[i];
        uint base = slots[f.key >> 9] * (2u * kBrickVoxels) + (f.key & 511u);
        if (words[base] == f.density) atomicMax(words[base + kBrickVoxels], f.axis);
    }
}
