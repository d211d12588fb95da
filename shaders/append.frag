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
#ifdef ALBEDO
// --albedo (a program of its own, so the default one stays as it is): the
// fibres' linear colour times their density (CrossSection::albedo, RGB32F),
// and per fragment its fixed-point volume fraction times the sample's colour
// (R, G, B, 0), at the fragment's own slot of a second list.
layout(binding = 1) uniform sampler2D uAlbedo;
layout(std430, binding = 4) writeonly buffer AlbedoFragments { uvec4 albedoFragments[]; };
#endif

uniform uint uCapacity;       // fragments the list holds; the counter goes on past it
uniform float uRadius;        // yarn radius, voxel units
// CROSS_SECTION_DISK (a #define, 1 or 0): the uniform disk, coverage computed
// exactly; a program of its own, so that each keeps only the code it runs.
const bool kDisk = CROSS_SECTION_DISK != 0;
uniform float uSupport;       // textureSupport(): beyond it the texture reads 0
uniform int uSupersample;
uniform ivec3 uRegionMin;
uniform ivec3 uRegionBricks;  // region size in bricks
uniform int uMargin;          // pixels around the region's face in the viewport (slice.vert)

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

#ifdef ALBEDO
// Density times colour, bilinear at slice-local c (units of the radius), 0
// outside the slice square (CrossSection::bilinearAlbedo).
vec3 bilinearAlbedo(vec2 c) {
    if (!(c.x >= -1.0 && c.x < 1.0 && c.y >= -1.0 && c.y < 1.0)) return vec3(0.0);
    int size = textureSize(uAlbedo, 0).x;
    vec2 f = (c + 1.0) * 0.5 * float(size) - 0.5;
    vec2 f0 = floor(f), t = f - f0;
    ivec2 i0 = clamp(ivec2(f0), ivec2(0), ivec2(size - 1)), i1 = clamp(ivec2(f0) + 1, ivec2(0), ivec2(size - 1));
    vec3 top = texelFetch(uAlbedo, ivec2(i0.x, i0.y), 0).rgb * (1.0 - t.x) + texelFetch(uAlbedo, ivec2(i1.x, i0.y), 0).rgb * t.x;
    vec3 bottom = texelFetch(uAlbedo, ivec2(i0.x, i1.y), 0).rgb * (1.0 - t.x) + texelFetch(uAlbedo, ivec2(i1.x, i1.y), 0).rgb * t.x;
    return top * (1.0 - t.y) + bottom * t.y;
}

// The sample's colour: the density-weighted mean over its footprint cells
// with fibre, at the cell centres footprintCells uses (src/cpu/slice_sampler.h).
// `right` and `up` come axis first (axisFirst).
vec3 sampleAlbedo(vec3 right, vec3 up, float det, float S, float x, float y, float cellDensity[kCells], float cellSum) {
    CellGrid cells = footprintCellGrid(right, up, det, S, uRadius, x, y);
    vec3 sum = vec3(0.0);
    for (int q = 0; q < kFootprintCells; ++q)
        for (int p = 0; p < kFootprintCells; ++p) {
            if (!(cellDensity[q * kFootprintCells + p] > 0.0)) continue;
            sum += bilinearAlbedo(cells.first + float(p) * cells.stepP + float(q) * cells.stepQ);
        }
    return min(sum / cellSum, vec3(1.0));
}
#endif

void main() {
    int a = vAxis;
    float S = float(uSupersample);
    // The slice and the region with the projection axis first (axisFirst):
    // x is the depth axis a, y and z are the face's axes b and c.
    vec3 center = axisFirst(vCenter, a), right = axisFirst(vRight, a), up = axisFirst(vUp, a);
    vec3 tangent = axisFirst(vTangent, a), curvature = axisFirst(vCurvature, a);
    ivec3 anchor = axisFirst(vAnchor, a), regionMin = axisFirst(uRegionMin, a);
    ivec3 regionSize = axisFirst(uRegionBricks * 8, a);
    // Global pixel of this fragment on the (b, c) face, and its centre
    // relative to the slice centre (integers first: exact, then small floats).
    ivec2 pixel = ivec2(gl_FragCoord.xy) - uMargin + regionMin.yz * uSupersample;
    ivec2 fromAnchor = pixel - anchor.yz * uSupersample;
    float db = (float(fromAnchor.x) + 0.5) / S - center.y;
    float dc = (float(fromAnchor.y) + 0.5) / S - center.z;
    // Where the column through the pixel centre meets the slice: right x up =
    // tangent, so the 2x2 system has determinant tangent[a].
    float det = tangent.x;
    float x = (db * up.z - dc * up.y) / det;
    float y = (right.y * dc - right.z * db) / det;

    ivec2 face = ivec2(pixel.x / uSupersample, pixel.y / uSupersample) - regionMin.yz;
    if (face.x < 0 || face.y < 0 || face.x >= regionSize.y || face.y >= regionSize.z) return;

    // The pixel's prism through the slab, in cells with their own coverage
    // and depth (the CPU reference's rule).
    float cellDensity[kCells], cellZ0[kCells], cellZ1[kCells], zMin, zMax;
    float cellSum = footprintCells(uCrossSection, kDisk, uSupport, S, uRadius, center, right, up, tangent, curvature,
                                   vDepthScale, x, y, cellDensity, cellZ0, cellZ1, zMin, zMax);
    if (!(cellSum > 0.0)) return;
    float density = cellSum / float(kCells);

    // Eq. 1 of the paper: where the fibre at (x, y) sits on the next slice.
    float cs = cos(vTwistStep), sn = sin(vTwistStep);
    uint axis = encodeAxis(normalize((x * cs - y * sn - x) * vRight + (x * sn + y * cs - y) * vUp + vThickness * vTangent));
    float weight = 1.0 / (S * S * float(kCells));
#ifdef ALBEDO
    vec3 colour = sampleAlbedo(right, up, det, S, x, y, cellDensity, cellSum);
#endif

    // One fragment per voxel the cells' columns cross (a box filter in depth).
    for (float v = floor(zMin); v < zMax; v += 1.0) {
        float share = layerShare(v, cellDensity, cellZ0, cellZ1);
        if (!(weight * share >= kMinVoxelShare)) continue;
        int depth = int(v) + anchor.x - regionMin.x;
        if (depth < 0 || depth >= regionSize.x) continue;
        ivec3 voxel = axisBack(ivec3(depth, face), a);
        ivec3 brick = voxel >> 3;
        uint brickIndex = uint(brick.x + uRegionBricks.x * (brick.y + uRegionBricks.y * brick.z));
        ivec3 local = voxel & 7;
        uint key = (brickIndex << 9) | uint((local.x << 6) | (local.y << 3) | local.z);
        uint slot = atomicCounterIncrement(uFragmentCount);
        if (slot >= 0x80000000u) counterWrapped = 1u;
        if (slot < uCapacity) {
            fragments[slot] = Fragment(key, uint(round(weight * share * kFixedScale)), axis, floatBitsToUint(density));
#ifdef ALBEDO
            albedoFragments[slot] = uvec4(uvec3(round(weight * share * colour * kFixedScale)), 0u);
#endif
        }
    }
}
