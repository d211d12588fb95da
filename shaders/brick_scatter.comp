// Brick pass 3: scatter fragments into their brick slots with atomics.
// Mean (default): fixed-point volume fraction and structure tensor, summed.
// REDUCE_MAX: atomicMax on the density bits; brick_max_orient.comp then
// picks the winning sample's axis. ALBEDO (mean only): three more words, the
// fragments' volume fraction times colour from the second fragment list.

#include "layout.glsl"
#include "axis_codes.glsl"

layout(local_size_x = 256) in;

layout(std430, binding = kFragmentsBinding) readonly buffer Fragments { Fragment fragments[]; };
layout(std430, binding = kBrickSlotsBinding) readonly buffer Slots { uint slots[]; };
layout(std430, binding = kBrickWordsBinding) buffer BrickWords { uint words[]; };
#ifdef ALBEDO
layout(std430, binding = kAlbedoFragmentsBinding) readonly buffer AlbedoFragments { uvec4 albedoFragments[]; };
const uint kWords = 10u;
#else
const uint kWords = 7u;
#endif

uniform uint uCount;

void main() {
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint i = gl_GlobalInvocationID.x; i < uCount; i += stride) {
        Fragment f = fragments[i];
#ifdef REDUCE_MAX
        uint base = slots[f.key >> 9] * (2u * kBrickVoxels) + (f.key & 511u);
        atomicMax(words[base], f.density);
#else
        uint base = slots[f.key >> 9] * (kWords * kBrickVoxels) + (f.key & 511u);
        atomicAdd(words[base], f.weight);
        vec3 o = decodeAxis(f.axis);
        float w = float(f.weight);
        float terms[6] = float[6](o.x * o.x, o.y * o.y, o.z * o.z, o.x * o.y, o.x * o.z, o.y * o.z);
        for (int t = 0; t < 6; ++t) atomicAdd(words[base + uint(1 + t) * kBrickVoxels], uint(int(round(w * terms[t]))));
#ifdef ALBEDO
        uvec4 colour = albedoFragments[i];
        for (uint k = 0u; k < 3u; ++k) atomicAdd(words[base + (7u + k) * kBrickVoxels], colour[k]);
#endif
#endif
    }
}
