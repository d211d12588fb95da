// `inspect --render slices`: which slices a frame draws, and their sort keys
// for the back-to-front order. The key is sortBackToFront's
// (src/inspect/slice_instances.cpp): the bits of the squared distance from
// the eye, inverted, so that the farthest sorts first; the index rides
// along as the value, and the stable radix sort (src/gpu/radix_sort.h)
// keeps equal distances in index order. The distance is computed as the
// host computes it (the same float operations in the same order, `precise`
// so that none is fused), so the two orders are the same slice for slice.
//
// Level of detail (uLodLevels > 0): where a yarn's slices lie closer on
// screen than uLodPixels, a run's slices are drawn in groups of 2^L, one
// slab from the group's first slice to its last standing for them all
// (inspect_slices.vert reads the span written here). The groups nest (2^L
// slices from a place that is a multiple of 2^L), and L is chosen from the
// coarsest level down by the group's first slice alone, so every slice of
// a group makes the same choice and the groups drawn cover each run once.
//
// Culling (uCull): a slab, or a group's slab, wholly outside the view
// frustum is dropped (value kDropped): the sort leaves it out and the draw
// never sees it. The test is its bounding sphere against the six planes,
// so nothing visible is dropped.
//
// Point sprites (slice_renderer.cpp): the most pixels a kept slab may cover
// across on screen, a bound from its bounding sphere, into `largestPixels`
// (0xffffffff where a slab reaches the eye's plane): the renderer draws
// points only where it is at most the largest point.
//
// Tiles (uTiles, render/slice_tiles.h): each kept slab also counts the
// 16 x 16 tiles of the picture it touches (slabs.glsl's slabTiles) into
// `tileCounts` (0 for a slice not drawn) and keeps them in `tileRects`, a
// byte a coordinate; the slabs kept go into `keptSlabs`, the nearest and
// farthest of their keys into `nearestKey` and `farthestKey`. One that spans
// more than uMaxTilesPerSlab tiles counts none and sets `tooWide`: the frame
// is drawn otherwise.

#include "slabs.glsl"

layout(local_size_x = 256) in;

layout(binding = kSliceTableUnit) uniform samplerBuffer slices; // per slice: (centre, thickness), (tangent, place in its run)
layout(std430, binding = kSortKeysInBinding) writeonly buffer Keys { uint keys[]; };
layout(std430, binding = kSortValuesInBinding) writeonly buffer Values { uint values[]; };
layout(std430, binding = kSliceSpansBinding) writeonly buffer Spans { uint spans[]; };
layout(std430, binding = kSliceLargestBinding) coherent buffer Largest { uint largestPixels; };
layout(std430, binding = kSliceTileCountsBinding) writeonly buffer Counts { uint tileCounts[]; };
layout(std430, binding = kSliceTileTotalsBinding) buffer Totals {
    uint pairs, keptSlabs, tooWide;
    uint nearestKey, farthestKey; // cleared to 0 and ~0
};
layout(std430, binding = kSliceTileRectsBinding) writeonly buffer Rects { uint tileRects[]; }; // x0 | y0 << 8 | x1 << 16 | y1 << 24

uniform uint uSlices;
uniform vec3 uEye;
uniform float uRadius;     // the yarn's, every slice's
uniform int uCull;
uniform vec4 uPlanes[6];   // the frustum's, unit normals pointing in
uniform int uLodLevels;    // the coarsest level (groups of 2^uLodLevels slices); 0: every slice
uniform float uLodPixels;  // the longest a group's slab may be on screen, pixels
uniform float uFocalPixels; // pixels a unit of length at unit depth spans
uniform vec3 uForward;     // the view direction, unit
uniform int uTiles;        // 1: count each kept slab's tiles
uniform mat4 uViewProjection;
uniform vec2 uPixels;      // the picture's size
uniform uint uMaxTilesPerSlab;

const uint kDropped = 0xffffffffu;

shared uint groupLargest, groupKept, groupNearest, groupFarthest;

// Per-thread sums of the tiles' counts, added to the group's and then the totals.
uint kept = 0u, nearest = 0u, farthest = 0xffffffffu;
bool anyWide = false;

// Counts slice i's tiles where its slab stands for `span` slices (uTiles).
void countTiles(uint i, uint span, uint key) {
    ivec4 tiles = slabTiles(slabOf(slices, i, span, uRadius), uViewProjection, uPixels);
    uint count = tiles.x <= tiles.z && tiles.y <= tiles.w ? uint(tiles.z - tiles.x + 1) * uint(tiles.w - tiles.y + 1) : 0u;
    bool wide = count > uMaxTilesPerSlab;
    tileCounts[i] = wide ? 0u : count;
    if (count > 0u && !wide) tileRects[i] = uint(tiles.x) | uint(tiles.y) << 8 | uint(tiles.z) << 16 | uint(tiles.w) << 24;
    kept++;
    anyWide = anyWide || wide;
    nearest = max(nearest, key);
    farthest = min(farthest, key);
}

// A bound on the pixels a sphere covers across on screen: one of radius R at
// depth z, a lateral distance l off the view axis, projects to at most
// 2 R / (z - R) (1 + l / z) of focal length across.
uint coveredPixels(vec3 centre, float reach) {
    vec3 toCentre = centre - uEye;
    float depth = dot(toCentre, uForward);
    if (depth - reach <= 1e-6 * max(depth, 1.0)) return 0xffffffffu;
    float lateral = length(toCentre - depth * uForward);
    float pixels = 2.0 * reach / (depth - reach) * (1.0 + lateral / depth) * uFocalPixels;
    return pixels >= 4.0e9 ? 0xffffffffu : uint(ceil(pixels));
}

float placeOf(uint i) { return texelFetch(slices, int(2u * i + 1u)).w; }

// Whether a sphere lies wholly on the outer side of one of the planes.
bool outside(vec3 centre, float radius) {
    for (int p = 0; p < 6; ++p)
        if (dot(uPlanes[p].xyz, centre) + uPlanes[p].w < -radius) return true;
    return false;
}

// The slices of slice i's run from i on, at most `size` (the first `size`
// places after i that hold the next places of the run: a binary search,
// since once a place does not, none after it does).
uint runFrom(uint i, float place, uint size) {
    uint lo = 1u, hi = min(size, uSlices - i);
    while (lo < hi) {
        uint mid = (lo + hi + 1u) >> 1;
        if (placeOf(i + mid - 1u) == place + float(mid - 1u)) lo = mid;
        else hi = mid - 1u;
    }
    return lo;
}

void main() {
    if (gl_LocalInvocationIndex == 0u) {
        groupLargest = groupKept = groupNearest = 0u;
        groupFarthest = 0xffffffffu;
    }
    barrier();
    uint largest = 0u;
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint i = gl_GlobalInvocationID.x; i < uSlices; i += stride) {
        vec4 a = texelFetch(slices, int(2u * i));
        float place = placeOf(i);
        uint span = 1u;
        bool drawn = true;
        for (int level = uLodLevels; level >= 1; --level) {
            uint size = 1u << uint(level);
            uint first = i - (uint(place) & (size - 1u)); // the group's first slice
            vec4 f = first == i ? a : texelFetch(slices, int(2u * first));
            if (float(size) * f.w * uFocalPixels <= uLodPixels * dot(f.xyz - uEye, uForward)) {
                if (first == i) span = runFrom(i, place, size);
                else drawn = false;
                break;
            }
        }
        if (!drawn) {
            values[i] = kDropped;
            if (uTiles != 0) tileCounts[i] = 0u;
            continue;
        }
        vec3 centre = a.xyz;
        float thickness = a.w;
        if (span > 1u) {
            vec4 last = texelFetch(slices, int(2u * (i + span - 1u)));
            centre = 0.5 * (a.xyz + last.xyz);
            thickness = length(last.xyz - a.xyz) + max(a.w, last.w);
        }
        // The slab (2 radius x 2 radius x thickness)'s half diagonal, and
        // a little for the planes' rounding.
        float reach = sqrt(2.0 * uRadius * uRadius + 0.25 * thickness * thickness) * 1.001 + 1e-3;
        if (uCull != 0 && outside(centre, reach)) {
            values[i] = kDropped;
            if (uTiles != 0) tileCounts[i] = 0u;
            continue;
        }
        largest = max(largest, coveredPixels(centre, reach));
        precise vec3 d = centre - uEye;
        precise float distance2 = d.x * d.x + d.y * d.y + d.z * d.z;
        uint key = ~floatBitsToUint(distance2);
        keys[i] = key;
        values[i] = i;
        spans[i] = span;
        if (uTiles != 0) countTiles(i, span, key);
    }
    atomicMax(groupLargest, largest);
    if (uTiles != 0) {
        atomicAdd(groupKept, kept);
        atomicMax(groupNearest, nearest);
        atomicMin(groupFarthest, farthest);
    }
    barrier();
    if (gl_LocalInvocationIndex == 0u) {
        atomicMax(largestPixels, groupLargest);
        if (uTiles != 0) {
            atomicAdd(keptSlabs, groupKept);
            atomicMax(nearestKey, groupNearest);
            atomicMin(farthestKey, groupFarthest);
        }
    }
    if (uTiles != 0 && anyWide) atomicOr(tooWide, 1u);
}
