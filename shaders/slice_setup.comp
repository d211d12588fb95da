// Places every slice of a draw once, on every compute unit, before the draw:
// record i is instance i of the draw's segment list (slice.vert reads it for
// the sprite, sample.comp for the sampling). On an H100 only a few units run
// vertex shaders, where this curve work was a fifth of the raster's time.

#include "slice_placement.glsl"

layout(local_size_x = 256) in;

layout(std430, binding = kSegmentsBinding) readonly buffer Segments { GpuSegment segments[]; };
// Segments this draw covers (indices into `segments`), and the first
// instance of each, for the search from instance to segment.
layout(std430, binding = kDrawListBinding) readonly buffer DrawList { uvec2 drawList[]; }; // x: segment, y: first instance
layout(std430, binding = kSlicesBinding) writeonly buffer Slices { SliceRecord slices[]; };

uniform int uDrawCount;        // entries in drawList
uniform uint uUniformSlices;   // slices of every segment when all have the same count, else 0
uniform uint uInstances;       // instances of the draw

void main() {
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint instance = gl_GlobalInvocationID.x; instance < uInstances; instance += stride) {
        // Last list entry whose first instance is <= instance: a division
        // when every segment has the same slice count, else a binary search.
        int lo = uUniformSlices != 0u ? int(instance / uUniformSlices) : 0;
        int hi = uUniformSlices != 0u ? lo : uDrawCount - 1;
        while (lo < hi) {
            int mid = (lo + hi + 1) >> 1;
            if (drawList[mid].y <= instance) lo = mid; else hi = mid - 1;
        }
        slices[instance] = placeSlice(segments[drawList[lo].x], instance - drawList[lo].y);
    }
}
