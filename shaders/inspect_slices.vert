// `inspect --render slices`: one instance a slice, drawn in the sorted order
// (instance attribute sliceIndex, farthest first). Each slice is drawn as the
// slab of yarn it stands for (slabs.glsl's sliceSlab), a box of
// 2 radius x 2 radius x thickness (a flat quad seen edge-on would cover
// nothing), whose fragments cut their ray with the yarn's disk
// (inspect_slices.frag). 14 vertices a box: one triangle strip, corners
// from the bits of gl_VertexID.
//
// With SLAB_POINTS, one point a slab instead: a square sprite over the
// screen box of the slab's eight corners, its centre and size in pixels
// (the renderer chooses points only where every slab in view lies wholly in
// front of the eye and fits the largest point). The viewport reaches a
// margin beyond the picture on every side (guardScale: the picture's share), so that a point
// whose centre lies just outside the picture, which GL would drop whole,
// still draws its part inside.

#include "slabs.glsl"

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
    Slab slab = sliceSlab(slices, spans, sliceIndex, radius);
    halfSize = slab.halfSize;
    localEye = transpose(slab.frame) * (eye - slab.centre);
    localLight = transpose(slab.frame) * lightDirection;
#ifdef SLAB_POINTS
    slabFrame = slab.frame;
    vec4 box;
    slabPixelBox(slab, viewProjection, viewportPixels, box);
    vec2 middle = 0.5 * (box.xy + box.zw);
    gl_Position = vec4((middle / viewportPixels * 2.0 - 1.0) * guardScale, 0.0, 1.0);
    // A pixel is drawn where its centre lies in the square: one more pixel
    // for the corners' rounding.
    gl_PointSize = max(box.z - box.x, box.w - box.y) + 1.0;
#else
    int bit = 1 << gl_VertexID;
    vec3 corner = vec3((0x287a & bit) != 0, (0x02af & bit) != 0, (0x31e3 & bit) != 0) * 2.0 - 1.0;
    localPosition = corner * halfSize;
    gl_Position = viewProjection * vec4(slab.centre + slab.frame * localPosition, 1.0);
#endif
}
