// Raster pass: appends one sample item (the slice, and this pixel of the
// region's face) for each pixel whose footprint can hold fibre. The sampling
// pass (sample.comp) then turns each item into voxel fragments on every
// compute unit; here only the test whether the footprint comes within the
// cross-section's support, widened a little, so that float rounding in this
// stage never drops a sample that sample.comp would keep.

layout(binding = 0, offset = 0) uniform atomic_uint uItemCount;
// x: the slice (its instance in the draw), y: the pixel on the region's face, x | y << 16.
layout(std430, binding = 6) writeonly buffer Items { uvec2 items[]; };
// The counter's own word, then a flag set once a slot reaches 2^31 (as for
// the fragment list, sample.comp).
layout(std430, binding = 7) buffer ItemCounter { uint itemWord; uint itemWrapped; };

uniform uint uItemCapacity;   // items the list holds; the counter goes on past it
uniform float uRadius;        // yarn radius, voxel units
uniform float uSupport;       // textureSupport() (1 for the disk), units of the radius
uniform int uSupersample;
uniform ivec3 uRegionMin;
uniform ivec3 uRegionBricks;  // region size in bricks
uniform int uMargin;          // pixels around the region's face in the viewport (slice.vert)

flat in int vInstance;
flat in int vAxis;
flat in ivec3 vAnchor;
flat in vec3 vCenter;
flat in vec3 vRight;
flat in vec3 vUp;
flat in vec3 vTangent;

// Relative slack of the support test (the exact test is sample.comp's).
const float kSupportSlack = 1e-3;

void main() {
    int a = vAxis;
    ivec2 local = ivec2(gl_FragCoord.xy) - uMargin;
    ivec2 faceSize = axisFirst(uRegionBricks * 8, a).yz * uSupersample;
    if (any(lessThan(local, ivec2(0))) || any(greaterThanEqual(local, faceSize))) return;

    vec3 center = axisFirst(vCenter, a), right = axisFirst(vRight, a), up = axisFirst(vUp, a);
    float det = axisFirst(vTangent, a).x, S = float(uSupersample);
    ivec3 regionMin = axisFirst(uRegionMin, a);
    vec2 xy = columnCrossing(local + regionMin.yz * uSupersample, uSupersample, axisFirst(vAnchor, a), center, right, up, det);
    vec2 edgeB = footprintEdgeB(right, up, det, S, uRadius), edgeC = footprintEdgeC(right, up, det, S, uRadius);
    if (footprintNearest(xy, edgeB, edgeC, uRadius) > uSupport * (1.0 + kSupportSlack) + kSupportSlack) return;

    uint slot = atomicCounterIncrement(uItemCount);
    if (slot >= 0x80000000u) itemWrapped = 1u;
    if (slot < uItemCapacity) items[slot] = uvec2(uint(vInstance), uint(local.x) | (uint(local.y) << 16));
}
