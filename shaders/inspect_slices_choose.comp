// `inspect --render slices`: the frame's draw, chosen on the GPU so that the
// host need not wait for the sort: every slab kept is drawn as a point where
// all of them fit the largest point (inspect_slices_keys.comp bounds their
// size), else as a box. The two draws' instance counts are written here, one
// the count the sort kept and the other zero; the renderer issues both.
layout(local_size_x = 1) in;

layout(std430, binding = kSortKeptBinding) readonly buffer Kept { uint kept; };
layout(std430, binding = kSliceLargestBinding) readonly buffer Largest { uint largestPixels; };
// glDrawArraysIndirect's commands (count, instances, first, base instance): boxes', then points'.
layout(std430, binding = kSliceDrawsBinding) writeonly buffer Draws { uint boxes[4]; uint points[4]; };

uniform float uPointPixels; // the largest point drawn; 0: no points

void main() {
    bool asPoints = uPointPixels > 0.0 && float(largestPixels) <= uPointPixels;
    boxes[1] = asPoints ? 0u : kept;
    points[1] = asPoints ? kept : 0u;
}
