// `inspect --render slices`: one instance a slice, drawn in the sorted order
// (instance attribute sliceIndex, farthest first). Each slice is drawn as the
// slab of yarn it stands for, a box of 2 radius x 2 radius x thickness (a
// flat quad seen edge-on would cover nothing), whose fragments cut their
// ray with the yarn's disk (inspect_slices.frag). 14 vertices a box: one
// triangle strip, corners from the bits of gl_VertexID.
layout(location = 0) in uint sliceIndex;
layout(binding = kSliceTableUnit) uniform samplerBuffer slices; // per slice: (centre, thickness), (tangent, radius)
uniform mat4 viewProjection;
uniform vec3 eye;
uniform vec3 lightDirection; // unit, towards the light
uniform vec3 albedo;

out vec3 localPosition;  // in the slab's frame (right, up, tangent), voxel units from its centre
flat out vec3 localEye;
flat out vec3 halfSize;
flat out vec3 shade;

void main() {
    vec4 a = texelFetch(slices, int(2u * sliceIndex));
    vec4 b = texelFetch(slices, int(2u * sliceIndex + 1u));
    vec3 t = b.xyz;
    // The disk is round: any frame across the tangent will do.
    vec3 helper = abs(t.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    vec3 r = normalize(cross(t, helper));
    vec3 u = cross(t, r);
    halfSize = vec3(b.w, b.w, 0.5 * a.w);
    int bit = 1 << gl_VertexID;
    vec3 corner = vec3((0x287a & bit) != 0, (0x02af & bit) != 0, (0x31e3 & bit) != 0) * 2.0 - 1.0;
    localPosition = corner * halfSize;
    vec3 toEye = eye - a.xyz;
    localEye = vec3(dot(toEye, r), dot(toEye, u), dot(toEye, t));
    // Lambertian shading of a fibre along t under parallel light: the
    // diffuse term of a thin cylinder, sin of the angle between t and the light.
    float c = dot(t, lightDirection);
    shade = albedo * (0.25 + 0.75 * sqrt(max(0.0, 1.0 - c * c)));
    gl_Position = viewProjection * vec4(a.xyz + localPosition.x * r + localPosition.y * u + localPosition.z * t, 1.0);
}
