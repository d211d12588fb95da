// Samples the cross-section at level 0 and appends one voxel fragment per
// sample on fibre. Each fragment finds its sample from its pixel in global
// (grid) coordinates and the slice's plane, exactly as the CPU reference
// does, so the result is the same bits whatever region the pass covers.

layout(binding = 0) uniform usampler2D uCrossSection; // R8UI, texel 255 = solid fibre
layout(binding = 0, offset = 0) uniform atomic_uint uFragmentCount;
layout(std430, binding = 2) writeonly buffer Fragments { Fragment fragments[]; };

uniform uint uCapacity;       // fragments the list holds; the counter goes on past it
uniform float uRadius;        // yarn radius, voxel units
uniform float uTwist;         // radians per voxel unit of yarn length
uniform int uSupersample;
uniform ivec3 uRegionMin;
uniform ivec3 uRegionBricks;  // region size in bricks

flat in int vAxis;
flat in vec3 vCenter;
flat in vec3 vRight;
flat in vec3 vUp;
flat in vec3 vTangent;
flat in float vThickness;
flat in float vWeightScale;

void main() {
    int a = vAxis, b = (a + 1) % 3, c = (a + 2) % 3;
    float S = float(uSupersample);
    // Global pixel of this fragment on the (b, c) face, and its centre in voxel units.
    ivec2 pixel = ivec2(gl_FragCoord.xy) + ivec2(uRegionMin[b], uRegionMin[c]) * uSupersample;
    float db = (float(pixel.x) + 0.5) / S - vCenter[b];
    float dc = (float(pixel.y) + 0.5) / S - vCenter[c];
    // Where the column through the pixel centre meets the slice: right x up =
    // tangent, so the 2x2 system has determinant tangent[a].
    float det = vTangent[a];
    float x = (db * vUp[c] - dc * vUp[b]) / det;
    float y = (vRight[b] * dc - vRight[c] * db) / det;
    if (x < -uRadius || x >= uRadius || y < -uRadius || y >= uRadius) return;

    ivec3 voxel;
    voxel[a] = int(floor(vCenter[a] + x * vRight[a] + y * vUp[a]));
    voxel[b] = pixel.x / uSupersample;
    voxel[c] = pixel.y / uSupersample;
    voxel -= uRegionMin;
    if (any(lessThan(voxel, ivec3(0))) || any(greaterThanEqual(voxel, uRegionBricks * 8))) return;

    int size = textureSize(uCrossSection, 0).x;
    ivec2 texel = clamp(ivec2(floor((vec2(x, y) / uRadius + 1.0) * 0.5 * float(size))), ivec2(0), ivec2(size - 1));
    uint value = texelFetch(uCrossSection, texel, 0).r;
    if (value == 0u) return;
    float density = float(value) / 255.0;

    // Eq. 1 of the paper: where the fibre at (x, y) sits on the next slice.
    float step = uTwist * vThickness;
    float cs = cos(step), sn = sin(step);
    vec3 dir = (x * cs - y * sn - x) * vRight + (x * sn + y * cs - y) * vUp + vThickness * vTangent;

    ivec3 brick = voxel >> 3;
    uint brickIndex = uint(brick.x + uRegionBricks.x * (brick.y + uRegionBricks.y * brick.z));
    ivec3 local = voxel & 7;
    uint key = (brickIndex << 9) | uint((local.x << 6) | (local.y << 3) | local.z);

    uint slot = atomicCounterIncrement(uFragmentCount);
    if (slot < uCapacity)
        fragments[slot] = Fragment(key, uint(round(density * vWeightScale * kFixedScale)), encodeAxis(normalize(dir)),
                                   floatBitsToUint(density));
}
