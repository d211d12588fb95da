// `inspect --render slices` composited by tiles of the picture
// (src/render/slice_tiles.h): the pairs the compositing reads, made from the
// slabs inspect_slices_keys.comp kept. Three phases (uPhase):
//   0: each kept slab counts the 16 x 16 tiles of the picture that hold
//      pixels whose centre lies in its screen box (common.glsl's
//      slabPixelBox and slabPixelRange) into `tileCounts`, the slabs kept into `keptSlabs` and
//      the nearest and farthest of their distances into `nearestKey` and
//      `farthestKey` (as the keys pass writes them: inverted); a slab
//      whose box is unbounded (it reaches the eye's plane) touches every
//      tile. One that spans more than uMaxTilesPerSlab tiles counts none
//      and sets `tooWide`: the frame is drawn otherwise.
//   1: after the counts' exclusive scan (gpu/gpu_scan.h), each kept slab
//      writes one pair a tile from its place on: key (tile << uDepthBits |
//      its depth, quantized), value its slice. Sorted by key, stably, the
//      pairs of a tile are then its slabs nearest first (equal depths in
//      slice order).
//   2: on the sorted pairs, each tile's run: its first pair and one past
//      its last into `ranges` (cleared to 0 before: a tile with none).
// The depth is the slab centre's distance from the eye, the keys pass's
// (the bits of its square, inverted), mapped from the nearest kept slab's
// to the farthest's onto 2^uDepthBits steps.
layout(local_size_x = 256) in;

layout(binding = kSliceTableUnit) uniform samplerBuffer slices; // per slice: (centre, thickness), (tangent, place in its run)
layout(binding = kSliceSpansUnit) uniform usamplerBuffer spans; // per slice: the slices its slab stands for
layout(std430, binding = kSortKeysInBinding) readonly buffer Distances { uint distanceKeys[]; };
layout(std430, binding = kSortValuesInBinding) readonly buffer KeptSlices { uint keptSlices[]; };
layout(std430, binding = kSliceTileCountsBinding) buffer Counts { uint tileCounts[]; };
layout(std430, binding = kSliceTileTotalsBinding) buffer Totals {
    uint pairs, keptSlabs, tooWide;
    uint nearestKey, farthestKey; // cleared to 0 and ~0
};
layout(std430, binding = kSliceTileKeysBinding) buffer PairKeys { uint pairKeys[]; };
layout(std430, binding = kSliceTileValuesBinding) writeonly buffer PairValues { uint pairValues[]; };
layout(std430, binding = kSliceTileRangesBinding) writeonly buffer Ranges { uint ranges[]; };

uniform int uPhase;
uniform uint uSlices;          // phases 0 and 1: the slices; 2: the pairs
uniform mat4 uViewProjection;
uniform vec2 uPixels;          // the picture's size
uniform int uTilesX;           // tiles across the picture
uniform float uRadius;         // the yarn's
uniform uint uMaxTilesPerSlab;
uniform uint uDepthBits;

const uint kDropped = 0xffffffffu;
const int kTileShift = 4; // 16 pixels a tile
shared uint groupKept, groupNearest, groupFarthest;

// The tiles slab i touches, inclusive (x0, y0, x1, y1; none where x0 > x1
// or y0 > y1): every tile where its box is unbounded.
ivec4 slabTiles(uint i) {
    Slab s = sliceSlab(slices, spans, i, uRadius);
    vec4 box;
    slabPixelBox(s, uViewProjection, uPixels, box);
    vec4 range = slabPixelRange(box, vec2(0.0), uPixels - 1.0);
    ivec2 lo = max(ivec2(range.xy), ivec2(0)), hi = min(ivec2(range.zw), ivec2(uPixels) - 1);
    return lo.x <= hi.x && lo.y <= hi.y ? ivec4(lo >> kTileShift, hi >> kTileShift) : ivec4(1, 1, 0, 0);
}

// The pairs slab i makes (0 where it spans more than uMaxTilesPerSlab
// tiles: `wide`), and its tiles.
uint tilePairs(uint i, out ivec4 tiles, out bool wide) {
    tiles = slabTiles(i);
    wide = false;
    if (tiles.x > tiles.z || tiles.y > tiles.w) return 0u;
    uint count = uint(tiles.z - tiles.x + 1) * uint(tiles.w - tiles.y + 1);
    wide = count > uMaxTilesPerSlab;
    return wide ? 0u : count;
}

void main() {
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (uPhase == 2) {
        uint pairCount = uSlices;
        for (uint e = gl_GlobalInvocationID.x; e < pairCount; e += stride) {
            uint tile = pairKeys[e] >> uDepthBits;
            if (e == 0u || (pairKeys[e - 1u] >> uDepthBits) != tile) ranges[2u * tile] = e;
            if (e + 1u == pairCount || (pairKeys[e + 1u] >> uDepthBits) != tile) ranges[2u * tile + 1u] = e + 1u;
        }
        return;
    }
    if (gl_LocalInvocationIndex == 0u) {
        groupKept = 0u;
        groupNearest = 0u;
        groupFarthest = 0xffffffffu;
    }
    barrier();
    uint kept = 0u, nearest = 0u, farthest = 0xffffffffu;
    bool anyWide = false;
    float near = 0.0, depthScale = 0.0;
    if (uPhase == 1) {
        near = sqrt(uintBitsToFloat(~nearestKey));
        float far = sqrt(uintBitsToFloat(~farthestKey));
        depthScale = float((1u << uDepthBits) - 1u) / max(far - near, 1e-20);
    }
    for (uint i = gl_GlobalInvocationID.x; i < uSlices; i += stride) {
        if (keptSlices[i] == kDropped) {
            if (uPhase == 0) tileCounts[i] = 0u;
            continue;
        }
        ivec4 tiles;
        bool wide;
        uint count = tilePairs(i, tiles, wide);
        if (uPhase == 0) {
            tileCounts[i] = count;
            kept++;
            anyWide = anyWide || wide;
            nearest = max(nearest, distanceKeys[i]);
            farthest = min(farthest, distanceKeys[i]);
            continue;
        }
        if (count == 0u) continue;
        float distance = sqrt(uintBitsToFloat(~distanceKeys[i]));
        uint depth = uint(clamp((distance - near) * depthScale, 0.0, float((1u << uDepthBits) - 1u)));
        uint at = tileCounts[i];
        for (int y = tiles.y; y <= tiles.w; ++y)
            for (int x = tiles.x; x <= tiles.z; ++x, ++at) {
                pairKeys[at] = (uint(y * uTilesX + x) << uDepthBits) | depth;
                pairValues[at] = i;
            }
    }
    if (uPhase != 0) return;
    if (anyWide) atomicOr(tooWide, 1u);
    atomicAdd(groupKept, kept);
    atomicMax(groupNearest, nearest);
    atomicMin(groupFarthest, farthest);
    barrier();
    if (gl_LocalInvocationIndex == 0u) {
        atomicAdd(keptSlabs, groupKept);
        atomicMax(nearestKey, groupNearest);
        atomicMin(farthestKey, groupFarthest);
    }
}
