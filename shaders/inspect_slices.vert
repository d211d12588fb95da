// `inspect --render slices`: one instance a slice, drawn in the sorted order
// (instance attribute sliceIndex, farthest first). Each slice is drawn as the
// slab of yarn it stands for, a box of 2 radius x 2 radius x thickness (a
// flat quad seen edge-on would cover nothing), whose fragments cut their
// ray with the yarn's disk (inspect_slices.frag). 14 vertices a box: one
// triangle strip, corners from the bits of gl_VertexID. At a coarser level
// of detail a slice stands for `span` slices of its run (inspect_slices_keys.comp):
// its slab then reaches from its own centre to the last one's, their
// thicknesses included, along the chord between them.
//
// With SLAB_POINTS, one point a slab instead: a square sprite over the
// screen box of the slab's eight corners, its centre and size in pixels
// (the renderer chooses points only where every slab in view lies wholly in
// front of the eye and fits the largest point). The viewport reaches a
// margin beyond the picture on every side (guardScale: the picture's share), so that a point
// whose centre lies just outside the picture, which GL would drop whole,
// still draws its part inside.
layout(location = 0) in uint sliceIndex;
layout(binding = kSliceTableUnit) uniform samplerBuffer slices; // per slice: (centre, thickness), (tangent, place in its run)
layout(binding = kSliceSpansUnit) uniform usamplerBuffer spans; // per slice drawn: the slices its slab stands for
uniform mat4 viewProjection;
uniform vec3 eye;
uniform vec3 lightDirection; // unit, towards the light
uniform float radius;        // the yarn's

#ifdef SLAB_POINTS
uniform vec2 viewportPixels; // the picture's size
uniform vec2 guardScale;     // the picture's share of the viewport, per axis
flat out mat3 slabFrame;     // columns: right, up, tangent
#else
out vec3 localPosition;  // in the slab's frame (right, up, tangent), voxel units from its centre
#endif
flat out vec3 localEye;
flat out vec3 halfSize;
flat out vec3 localLight; // lightDirection in the slab's frame

void main() {
    vec4 a = texelFetch(slices, int(2u * sliceIndex));
    vec3 t = texelFetch(slices, int(2u * sliceIndex + 1u)).xyz;
    vec3 centre = a.xyz;
    float thickness = a.w;
    uint span = texelFetch(spans, int(sliceIndex)).x;
    if (span > 1u) {
        vec4 last = texelFetch(slices, int(2u * (sliceIndex + span - 1u)));
        vec3 chord = last.xyz - a.xyz;
        float chordLength = length(chord);
        centre = 0.5 * (a.xyz + last.xyz);
        if (chordLength > 1e-6) t = chord / chordLength;
        thickness = chordLength + 0.5 * (a.w + last.w);
    }
    // The disk is round: any frame across the tangent will do.
    vec3 helper = abs(t.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    vec3 r = normalize(cross(t, helper));
    vec3 u = cross(t, r);
    halfSize = vec3(radius, radius, 0.5 * thickness);
    vec3 toEye = eye - centre;
    localEye = vec3(dot(toEye, r), dot(toEye, u), dot(toEye, t));
    localLight = vec3(dot(lightDirection, r), dot(lightDirection, u), dot(lightDirection, t));
#ifdef SLAB_POINTS
    slabFrame = mat3(r, u, t);
    vec2 lo = vec2(1e30), hi = vec2(-1e30);
    for (int k = 0; k < 8; ++k) {
        vec3 corner = vec3((k & 1) != 0, (k & 2) != 0, (k & 4) != 0) * 2.0 - 1.0;
        vec3 local = corner * halfSize;
        vec4 clip = viewProjection * vec4(centre + local.x * r + local.y * u + local.z * t, 1.0);
        vec2 pixel = (clip.xy / clip.w * 0.5 + 0.5) * viewportPixels;
        lo = min(lo, pixel);
        hi = max(hi, pixel);
    }
    vec2 middle = 0.5 * (lo + hi);
    gl_Position = vec4((middle / viewportPixels * 2.0 - 1.0) * guardScale, 0.0, 1.0);
    // A pixel is drawn where its centre lies in the square: one more pixel
    // for the corners' rounding.
    gl_PointSize = max(hi.x - lo.x, hi.y - lo.y) + 1.0;
#else
    int bit = 1 << gl_VertexID;
    vec3 corner = vec3((0x287a & bit) != 0, (0x02af & bit) != 0, (0x31e3 & bit) != 0) * 2.0 - 1.0;
    localPosition = corner * halfSize;
    gl_Position = viewProjection * vec4(centre + localPosition.x * r + localPosition.y * u + localPosition.z * t, 1.0);
#endif
}
