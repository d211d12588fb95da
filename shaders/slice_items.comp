// Sample items in compute, in place of the raster (slice.vert and
// append.frag): for each placed slice of a draw, every pixel of the
// region's face whose footprint can hold fibre, appended to the item list
// as (slice, pixel). On an H100 or H200 only a few units run the graphics
// pipeline, and a point sprite costs them about 3 ns whatever its pixels;
// here every unit tests pixels, and a work group's items take one global
// atomic. Each slice tests the pixels whose centres lie in its box on the
// face (sliceFaceBox, which a sprite covers too) with append.frag's test, so
// the items are the raster's; sample.comp decides from the item alone, so
// the voxels are the same, bit for bit.

#include "common.glsl"

layout(local_size_x = 256) in;
// Loops kept as loops: NVIDIA's compiler links this program 10 ms sooner with
// no shader cache (54 -> 44 ms on an H100) and the raster takes as long
// (bench/results/README.md, 2026-12-06). Other drivers ignore the pragma.
#pragma optionNV(unroll none)

layout(std430, binding = kSlicesBinding) readonly buffer Slices { SliceRecord slices[]; };
// x: the slice (its record), y: the pixel on the region's face, x | y << 16.
layout(std430, binding = kItemsBinding) writeonly buffer Items { uvec2 items[]; };
// The counter's own word, then a flag set once a slot reaches 2^31 (as
// append.frag sets it).
layout(std430, binding = kItemCounterBinding) buffer ItemCounter { uint itemWord; uint itemWrapped; };

uniform float uRadius;       // yarn radius, voxel units
uniform float uSupport;      // textureSupport(), units of the radius
uniform int uSupersample;
uniform ivec3 uRegionMin;    // region box in voxels
uniform ivec3 uRegionBricks; // region size in bricks
uniform uint uItemCapacity;  // items the list holds; the counter goes on past it
uniform uint uInstances;     // slices of the draw

shared uint groupItems, groupBase;

// One slice's test: the pixels it tests (lo to hi, inclusive, on the face)
// and append.frag's terms about `origin`.
struct SliceTest {
    ivec2 lo, hi, origin;
    vec2 at;
    vec4 steps;
    float limitSquared;
};

SliceTest sliceTest(uint index) {
    SliceRecord s = slices[index];
    int a = floatBitsToInt(s.center.w);
    SliceTest test;
    test.origin = sliceFacePixel(s, a, uRegionMin, uSupersample);
    SliceTerms t = sliceTerms(s, a, test.origin, uRadius, uSupport, uSupersample, uRegionMin);
    test.at = t.atOrigin;
    test.steps = t.steps;
    test.limitSquared = t.limit * t.limit;
    // Pixel centres (i + 0.5) within the box, and a little more; the face's
    // pixels only (at most 1024 x 16 on a side: regionCap_).
    vec4 box = sliceFaceBox(s, a, t, uRegionMin, float(uSupersample));
    ivec2 face = axisFirst(uRegionBricks * 8, a).yz * uSupersample;
    test.lo = max(ivec2(floor(box.xy - 0.6)), ivec2(0));
    test.hi = min(ivec2(ceil(box.zw - 0.4)), face - 1);
    return test;
}

// append.frag's test: where the column through `pixel` meets the slice, and
// whether the footprint about it comes within the support.
bool holdsFibre(SliceTest test, ivec2 pixel) {
    vec2 steps = vec2(pixel - test.origin);
    vec2 xy = test.at + steps.x * test.steps.xy + steps.y * test.steps.zw;
    return dot(xy, xy) <= test.limitSquared;
}

void main() {
    // Each thread tests one slice at a time; the loop is the same for every
    // thread of a work group (its barriers), which gathers its items into
    // one global atomic.
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint base = gl_WorkGroupID.x * gl_WorkGroupSize.x; base < uInstances; base += stride) {
        uint index = base + gl_LocalInvocationID.x;
        bool live = index < uInstances;
        SliceTest test;
        uint count = 0u;
        if (live) {
            test = sliceTest(index);
            for (int y = test.lo.y; y <= test.hi.y; ++y)
                for (int x = test.lo.x; x <= test.hi.x; ++x)
                    if (holdsFibre(test, ivec2(x, y))) ++count;
        }
        if (gl_LocalInvocationID.x == 0u) groupItems = 0u;
        barrier();
        uint offset = count > 0u ? atomicAdd(groupItems, count) : 0u;
        barrier();
        if (gl_LocalInvocationID.x == 0u && groupItems > 0u) {
            groupBase = atomicAdd(itemWord, groupItems);
            if (groupBase >= 0x80000000u || groupBase + (groupItems - 1u) >= 0x80000000u) itemWrapped = 1u;
        }
        barrier();
        if (count > 0u) {
            uint slot = groupBase + offset;
            for (int y = test.lo.y; y <= test.hi.y; ++y)
                for (int x = test.lo.x; x <= test.hi.x; ++x)
                    if (holdsFibre(test, ivec2(x, y))) {
                        if (slot < uItemCapacity) items[slot] = uvec2(index, uint(x) | (uint(y) << 16));
                        ++slot;
                    }
        }
        barrier(); // groupItems and groupBase are read above before the next round sets them
    }
}
