// `inspect --render slices`: each slice's sort key for the back-to-front
// order, the same key as sortBackToFront (src/inspect/slice_instances.cpp):
// the bits of the squared distance from the eye, inverted, so that the
// farthest sorts first; the index rides along as the value, and the stable
// radix sort (src/gpu/radix_sort.h) keeps equal distances in index order.
// The distance is computed as the host computes it (the same float
// operations in the same order, `precise` so that none is fused), so the two
// orders are the same slice for slice.
layout(local_size_x = 256) in;

layout(binding = kSliceTableUnit) uniform samplerBuffer slices; // per slice: (centre, thickness), (tangent, radius)
layout(std430, binding = kSortKeysInBinding) writeonly buffer Keys { uint keys[]; };
layout(std430, binding = kSortValuesInBinding) writeonly buffer Values { uint values[]; };

uniform uint uSlices;
uniform vec3 uEye;

void main() {
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint i = gl_GlobalInvocationID.x; i < uSlices; i += stride) {
        precise vec3 d = texelFetch(slices, int(2u * i)).xyz - uEye;
        precise float distance2 = d.x * d.x + d.y * d.y + d.z * d.z;
        keys[i] = ~floatBitsToUint(distance2);
        values[i] = i;
    }
}
