// Samples the cross-section at level 0 and appends one voxel fragment per
// voxel that the sample's slab column crosses. Each fragment finds its sample
// from its pixel in global (grid) coordinates and the slice's plane, exactly
// as the CPU reference does, so the result is the same bits whatever region
// the pass covers.

layout(binding = 0) uniform usampler2D uCrossSection; // R8UI, texel 255 = solid fibre
layout(binding = 0, offset = 0) uniform atomic_uint uFragmentCount;
layout(std430, binding = 2) writeonly buffer Fragments { Fragment fragments[]; };
// The counter's own word, then a flag set once a slot reaches 2^31: the list
// never holds that many, and a count that wrapped past 2^32 would look small.
layout(std430, binding = 3) buffer CounterState { uint counterWord; uint counterWrapped; };

uniform uint uCapacity;       // fragments the list holds; the counter goes on past it
uniform float uRadius;        // yarn radius, voxel units
// CROSS_SECTION_DISK (a #define, 1 or 0): the uniform disk, coverage computed
// exactly; a program of its own, so that each keeps only the code it runs.
const bool kDisk = CROSS_SECTION_DISK != 0;
uniform float uSupport;       // textureSupport(): beyond it the texture reads 0
uniform int uSupersample;
uniform ivec3 uRegionMin;
uniform ivec3 uRegionBricks;  // region size in bricks

flat in int vAxis;
flat in ivec3 vAnchor;
flat in vec3 vCenter;
flat in vec3 vRight;
flat in vec3 vUp;
flat in vec3 vTangent;
flat in vec3 vCurvature;
flat in float vThickness;
flat in float vTwistStep;
flat in float vDepthScale;

void main() {
    int a = vAxis, b = (a + 1) % 3, c = (a + 2) % 3;
    float S = float(uSupersample);
    // Global pixel of this fragment on the (b, c) face, and its centre
    // relative to the slice centre (integers first: exact, then small floats).
    ivec2 pixel = ivec2(gl_FragCoord.xy) + ivec2(uRegionMin[b], uRegionMin[c]) * uSupersample;
    ivec2 fromAnchor = pixel - ivec2(vAnchor[b], vAnchor[c]) * uSupersample;
    float db = (float(fromAnchor.x) + 0.5) / S - vCenter[b];
    float dc = (float(fromAnchor.y) + 0.5) / S - vCenter[c];
    // Where the column through the pixel centre meets the slice: right x up =
    // tangent, so the 2x2 system has determinant tangent[a].
    float det = vTangent[a];
    float x = (db * vUp[c] - dc * vUp[b]) / det;
    float y = (vRight[b] * dc - vRight[c] * db) / det;

    ivec2 face = ivec2(pixel.x / uSupersample, pixel.y / uSupersample) - ivec2(uRegionMin[b], uRegionMin[c]);
    ivec3 regionSize = uRegionBricks * 8;
    if (face.x < 0 || face.y < 0 || face.x >= regionSize[b] || face.y >= regionSize[c]) return;

    // The pixel's prism through the slab, in cells with their own coverage
    // and depth (the CPU reference's rule).
    float cellDensity[kCells], cellZ0[kCells], cellZ1[kCells], zMin, zMax;
    float cellSum = footprintCells(uCrossSection, kDisk, uSupport, a, b, c, S, uRadius, vCenter, vRight, vUp, vTangent,
                                   vCurvature, vDepthScale, x, y, cellDensity, cellZ0, cellZ1, zMin, zMax);
    if (!(cellSum > 0.0)) return;
    float density = cellSum / float(kCells);

    // Eq. 1 of the paper: where the fibre at (x, y) sits on the next slice.
    float cs = cos(vTwistStep), sn = sin(vTwistStep);
    uint axis = encodeAxis(normalize((x * cs - y * sn - x) * vRight + (x * sn + y * cs - y) * vUp + vThickness * vTangent));
    float weight = 1.0 / (S * S * float(kCells));

    // One fragment per voxel the cells' columns cross (a box filter in depth).
    ivec3 voxel;
    voxel[b] = face.x;
    voxel[c] = face.y;
    for (float v = floor(zMin); v < zMax; v += 1.0) {
        float share = layerShare(v, cellDensity, cellZ0, cellZ1);
        if (!(weight * share >= kMinVoxelShare)) continue;
        voxel[a] = int(v) + vAnchor[a] - uRegionMin[a];
        if (voxel[a] < 0 || voxel[a] >= regionSize[a]) continue;
        ivec3 brick = voxel >> 3;
        uint brickIndex = uint(brick.x + uRegionBricks.x * (brick.y + uRegionBricks.y * brick.z));
        ivec3 local = voxel & 7;
        uint key = (brickIndex << 9) | uint((local.x << 6) | (local.y << 3) | local.z);
        uint slot = atomicCounterIncrement(uFragmentCount);
        if (slot >= 0x80000000u) counterWrapped = 1u;
        if (slot < uCapacity)
            fragments[slot] = Fragment(key, uint(round(weight * share * kFixedScale)), axis, floatBitsToUint(density));
    }
}
