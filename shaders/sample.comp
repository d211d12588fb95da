// Sampling pass: one thread a sample item (a slice and a pixel that
// append.frag found), on every compute unit. It samples the cross-section at
// level 0 and appends one voxel fragment per voxel that the sample's slab
// column crosses. Each sample is found from its pixel in global (grid)
// coordinates and the slice's plane, exactly as the CPU reference does, so
// the result is the same bits whatever region the pass covers.
//
// Why not in the fragment shader: on an H100 only a few of the GPU's units
// run fragment shaders, and this work, the footprint's cells above all, then
// took most of the raster pass (bench/results/sample-pass-2026-11-24-h100).

#include "common.glsl"
#include "axis_codes.glsl"

layout(local_size_x = 128) in;

layout(binding = kCrossSectionUnit) uniform usampler2D uCrossSection; // R8UI, texel 255 = solid fibre
layout(binding = kFragmentCountAtomic, offset = 0) uniform atomic_uint uFragmentCount;
layout(std430, binding = kFragmentsBinding) writeonly buffer Fragments { Fragment fragments[]; };
// The counter's own word, then a flag set once a slot reaches 2^31: the list
// never holds that many, and a count that wrapped past 2^32 would look small.
layout(std430, binding = kFragmentCounterBinding) buffer CounterState { uint counterWord; uint counterWrapped; };
layout(std430, binding = kSlicesBinding) readonly buffer Slices { SliceRecord slices[]; };
// x: the slice (its instance in the draw), y: the pixel on the region's face, x | y << 16.
layout(std430, binding = kItemsBinding) readonly buffer Items { uvec2 items[]; };
layout(std430, binding = kItemCounterBinding) readonly buffer ItemCounter { uint itemCount; };
#ifdef ALBEDO
// --albedo (a program of its own, so the default one stays as it is): the
// fibres' linear colour times their density (CrossSection::albedo, RGB32F),
// and per fragment its fixed-point volume fraction times the sample's colour
// (R, G, B, 0), at the fragment's own slot of a second list.
layout(binding = kAlbedoUnit) uniform sampler2D uAlbedo;
layout(std430, binding = kAlbedoFragmentsBinding) writeonly buffer AlbedoFragments { uvec4 albedoFragments[]; };
#endif

uniform uint uCapacity;       // fragments the list holds; the counter goes on past it
uniform uint uItemCapacity;   // items the item list holds
uniform float uRadius;        // yarn radius, voxel units
// CROSS_SECTION_DISK (a #define, 1 or 0): the uniform disk, coverage computed
// exactly; a program of its own, so that each keeps only the code it runs.
const bool kDisk = CROSS_SECTION_DISK != 0;
uniform float uSupport;       // textureSupport(): beyond it the texture reads 0
uniform int uSupersample;
uniform ivec3 uRegionMin;
uniform ivec3 uRegionBricks;  // region size in bricks
// Voxels that take samples, grid indices, max exclusive: a --bbox run's box
// (its regions are whole bricks and may reach past it), else the whole grid.
uniform ivec3 uKeepMin, uKeepMax;

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

// Samples slice s at `local`, a pixel of the region's face, and appends its fragments.
void appendSample(SliceRecord s, ivec2 local) {
    int a = floatBitsToInt(s.center.w);
    float S = float(uSupersample);
    // The slice and the region with the projection axis first (axisFirst):
    // x is the depth axis a, y and z are the face's axes b and c.
    vec3 center = axisFirst(s.center.xyz, a), right = axisFirst(s.right.xyz, a), up = axisFirst(s.up.xyz, a);
    vec3 tangent = axisFirst(s.tangent.xyz, a), curvature = axisFirst(s.curvature.xyz, a);
    ivec3 anchor = axisFirst(s.anchor.xyz, a), regionMin = axisFirst(uRegionMin, a);
    ivec3 regionSize = axisFirst(uRegionBricks * 8, a);
    ivec2 face = local / uSupersample;
    vec2 xy = columnCrossing(local + regionMin.yz * uSupersample, uSupersample, anchor, center, right, up, tangent.x);
    float x = xy.x, y = xy.y;

    // The pixel's prism through the slab, in cells with their own coverage
    // and depth (the CPU reference's rule).
    float cellDensity[kCells], cellZ0[kCells], cellZ1[kCells], zMin, zMax;
    float cellSum = footprintCells(uCrossSection, kDisk, uSupport, S, uRadius, center, right, up, tangent, curvature,
                                   s.tangent.w, x, y, cellDensity, cellZ0, cellZ1, zMin, zMax);
    if (!(cellSum > 0.0)) return;
    float density = cellSum / float(kCells);

    // Eq. 1 of the paper: where the fibre at (x, y) sits on the next slice.
    float twistStep = s.up.w, thickness = s.right.w;
    float cs = cos(twistStep), sn = sin(twistStep);
    uint axis = encodeAxis(normalize((x * cs - y * sn - x) * s.right.xyz + (x * sn + y * cs - y) * s.up.xyz +
                                     thickness * s.tangent.xyz));
    float weight = 1.0 / (S * S * float(kCells));
#ifdef ALBEDO
    vec3 colour = sampleAlbedo(right, up, tangent.x, S, x, y, cellDensity, cellSum);
#endif

    // One fragment per voxel the cells' columns cross (a box filter in depth).
    for (float v = floor(zMin); v < zMax; v += 1.0) {
        float share = layerShare(v, cellDensity, cellZ0, cellZ1);
        if (!(weight * share >= kMinVoxelShare)) continue;
        int depth = int(v) + anchor.x - regionMin.x;
        if (depth < 0 || depth >= regionSize.x) continue;
        ivec3 voxel = axisBack(ivec3(depth, face), a);
        ivec3 inGrid = voxel + uRegionMin;
        if (any(lessThan(inGrid, uKeepMin)) || any(greaterThanEqual(inGrid, uKeepMax))) continue;
        ivec3 brick = voxel >> 3;
        uint brickIndex = uint(brick.x + uRegionBricks.x * (brick.y + uRegionBricks.y * brick.z));
        ivec3 inBrick = voxel & 7;
        uint key = (brickIndex << 9) | uint((inBrick.x << 6) | (inBrick.y << 3) | inBrick.z);
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

void main() {
    // Grid-stride loop over the items the raster appended (as many as the
    // list holds: a pass whose items overflowed is redone in pieces).
    uint count = min(itemCount, uItemCapacity);
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint i = gl_GlobalInvocationID.x; i < count; i += stride) {
        uvec2 item = items[i];
        appendSample(slices[item.x], ivec2(item.y & 0xffffu, item.y >> 16));
    }
}
