// `inspect --render slices`: each slice's sort key for the back-to-front
// order, the same key as sortBackToFront (src/inspect/slice_instances.cpp):
// the bits of the squared distance from the eye, inverted, so that the
// farthest sorts first; the index rides along as the value, and the stable
// radix sort (src/gpu/radix_sort.h) keeps equal distances in index order.
// The distance is computed as the host computes it (the same float
// operations in the same order, `precise` so that none is fused), so the two
// orders are the same slice for slice.
//
// With uCull, a slice whose slab lies wholly outside the view frustum is
// dropped (value kDropped): the sort leaves it out and the draw never sees
// it, so a close-up draws only what it shows. The test is the slab's
// bounding sphere against the six planes, so nothing visible is dropped.
layout(local_size_x = 256) in;

layout(binding = kSliceTableUnit) uniform samplerBuffer slices; // per slice: (centre, thickness), (tangent, radius)
layout(std430, binding = kSortKeysInBinding) writeonly buffer Keys { uint keys[]; };
layout(std430, binding = kSortValuesInBinding) writeonly buffer Values { uint values[]; };

uniform uint uSlices;
uniform vec3 uEye;
uniform int uCull;
uniform vec4 uPlanes[6]; // the frustum's, unit normals pointing in

const uint kDropped = 0xffffffffu;

// Whether a sphere lies wholly on the outer side of one of the planes.
bool outside(vec3 centre, float radius) {
    for (int p = 0; p < 6; ++p)
        if (dot(uPlanes[p].xyz, centre) + uPlanes[p].w < -radius) return true;
    return false;
}

void main() {
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint i = gl_GlobalInvocationID.x; i < uSlices; i += stride) {
        vec4 a = texelFetch(slices, int(2u * i));
        if (uCull != 0) {
            float radius = texelFetch(slices, int(2u * i + 1u)).w;
            // The slab (2 radius x 2 radius x thickness)'s half diagonal, and
            // a little for the planes' rounding.
            float reach = sqrt(2.0 * radius * radius + 0.25 * a.w * a.w) * 1.001 + 1e-3;
            if (outside(a.xyz, reach)) {
                values[i] = kDropped;
                continue;
            }
        }
        precise vec3 d = a.xyz - uEye;
        precise float distance2 = d.x * d.x + d.y * d.y + d.z * d.z;
        keys[i] = ~floatBitsToUint(distance2);
        values[i] = i;
    }
}
