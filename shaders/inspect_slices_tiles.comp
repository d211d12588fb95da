// `inspect --render slices` composited by tiles of the picture
// (src/render/slice_tiles.h): the pairs the compositing reads, made from the
// slabs inspect_slices_keys.comp kept and counted the tiles of. Two phases
// (uPhase):
//   1: after the counts' exclusive scan (gpu/gpu_scan.h), each slab with
//      pairs writes one a tile of its `tileRects` from its place on: key
//      (tile << uDepthBits | its depth, quantized), value its slice. Sorted
//      by key, stably, the pairs of a tile are then its slabs nearest first
//      (equal depths in slice order).
//   2: on the sorted pairs, each tile's run: its first pair and one past
//      its last into `ranges` (cleared to 0 before: a tile with none).
// The depth is the slab centre's distance from the eye, the keys pass's
// (the bits of its square, inverted), mapped from the nearest kept slab's
// to the farthest's onto 2^uDepthBits steps.
layout(local_size_x = 256) in;

layout(std430, binding = kSortKeysInBinding) readonly buffer Distances { uint distanceKeys[]; };
layout(std430, binding = kSortValuesInBinding) readonly buffer KeptSlices { uint keptSlices[]; };
layout(std430, binding = kSliceTileCountsBinding) readonly buffer Counts { uint tileCounts[]; };
layout(std430, binding = kSliceTileTotalsBinding) readonly buffer Totals {
    uint pairs, keptSlabs, tooWide;
    uint nearestKey, farthestKey;
};
layout(std430, binding = kSliceTileKeysBinding) buffer PairKeys { uint pairKeys[]; };
layout(std430, binding = kSliceTileValuesBinding) writeonly buffer PairValues { uint pairValues[]; };
layout(std430, binding = kSliceTileRangesBinding) writeonly buffer Ranges { uint ranges[]; };
layout(std430, binding = kSliceTileRectsBinding) readonly buffer Rects { uint tileRects[]; }; // x0 | y0 << 8 | x1 << 16 | y1 << 24

uniform int uPhase;
uniform uint uSlices; // phase 1: the slices; 2: the pairs
uniform int uTilesX;  // tiles across the picture
uniform uint uDepthBits;

const uint kDropped = 0xffffffffu;

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
    float near = sqrt(uintBitsToFloat(~nearestKey)), far = sqrt(uintBitsToFloat(~farthestKey));
    float depthScale = float((1u << uDepthBits) - 1u) / max(far - near, 1e-20);
    for (uint i = gl_GlobalInvocationID.x; i < uSlices; i += stride) {
        // A slab without pairs (not drawn, or outside the picture) has no tiles kept.
        uint at = tileCounts[i];
        if (keptSlices[i] == kDropped || (i + 1u < uSlices ? tileCounts[i + 1u] : pairs) == at) continue;
        uint rect = tileRects[i];
        ivec4 tiles = ivec4(rect & 255u, (rect >> 8) & 255u, (rect >> 16) & 255u, rect >> 24);
        float distance = sqrt(uintBitsToFloat(~distanceKeys[i]));
        uint depth = uint(clamp((distance - near) * depthScale, 0.0, float((1u << uDepthBits) - 1u)));
        for (int y = tiles.y; y <= tiles.w; ++y)
            for (int x = tiles.x; x <= tiles.z; ++x, ++at) {
                pairKeys[at] = (uint(y * uTilesX + x) << uDepthBits) | depth;
                pairValues[at] = i;
            }
    }
}
