// Joins the placed slices of a draw into runs of consecutive slices that one
// point sprite draws (slice.vert with SLICE_POINTS). On an H100 the raster
// spends about 3 ns on each point apart from its pixels, most of a small
// sprite's time, and the sprites of consecutive slices cover nearly the same
// pixels: a run pays that once, and each of its pixels runs the fragment
// shader once for all its slices. A run's slices share the projection axis
// (one face) and their centres lie within uRunSpread pixels of each other on
// it, so its sprite is at most that much wider than its widest slice's
// (chooseSlicePrimitive's margin allows for it). Which slices join changes
// what is drawn, not what is sampled: append.frag tests every pixel against
// each slice of its run.

#include "common.glsl"

layout(local_size_x = 256) in;

layout(std430, binding = kSlicesBinding) readonly buffer Slices { SliceRecord slices[]; };
// x: the run's first slice (its record), y: its slices (1 to kRunSlices).
layout(std430, binding = kRunsBinding) writeonly buffer Runs { uvec2 runs[]; };
// glDrawArraysIndirect's command: the runs (points to draw), 1 instance,
// from 0; the host sets it to (0, 1, 0, 0) before this pass.
layout(std430, binding = kRunDrawBinding) buffer RunDraw { uint runCount; uint drawInstances; uint drawFirst; uint drawBaseInstance; };

uniform uint uInstances;   // slices of the draw
uniform int uSupersample;
uniform float uRunSpread;  // pixels the centres of a run's slices may spread over on the face, on each axis

shared uint groupRuns, groupBase;

// Where slice `s` lies on the face of its axis `a`, in pixels from `anchor0`:
// integers first, so floats keep their precision anywhere in the grid.
vec2 onFace(SliceRecord s, int a, ivec3 anchor0) {
    return axisFirst(vec3(s.anchor.xyz - anchor0) + s.center.xyz, a).yz * float(uSupersample);
}

void main() {
    // Each thread joins the slices of one block of kRunSlices; a run never
    // spans two blocks. The loop is the same for every thread of a work
    // group (its barriers), which gathers its runs into one global atomic.
    uint blocks = (uInstances + uint(kRunSlices) - 1u) / uint(kRunSlices);
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint base = gl_WorkGroupID.x * gl_WorkGroupSize.x; base < blocks; base += stride) {
        uint block = base + gl_LocalInvocationID.x;
        uvec2 found[kRunSlices];
        uint n = 0u;
        if (block < blocks) {
            uint first = block * uint(kRunSlices), end = min(first + uint(kRunSlices), uInstances);
            // The run so far: its first slice, axis, and the box of its
            // slices' centres on the face.
            SliceRecord s0 = slices[first];
            ivec3 anchor0 = s0.anchor.xyz;
            uint start = first;
            int axis = floatBitsToInt(s0.center.w);
            vec2 lo = onFace(s0, axis, anchor0), hi = lo;
            for (uint i = first + 1u; i < end; ++i) {
                SliceRecord s = slices[i];
                int a = floatBitsToInt(s.center.w);
                vec2 p = onFace(s, a, anchor0);
                vec2 newLo = min(lo, p), newHi = max(hi, p);
                if (a == axis && max(newHi.x - newLo.x, newHi.y - newLo.y) <= uRunSpread) {
                    lo = newLo;
                    hi = newHi;
                } else {
                    found[n++] = uvec2(start, i - start);
                    start = i;
                    axis = a;
                    lo = hi = p;
                }
            }
            found[n++] = uvec2(start, end - start);
        }

        if (gl_LocalInvocationID.x == 0u) groupRuns = 0u;
        barrier();
        uint slot = atomicAdd(groupRuns, n);
        barrier();
        if (gl_LocalInvocationID.x == 0u) groupBase = atomicAdd(runCount, groupRuns);
        barrier();
        for (uint k = 0u; k < n; ++k) runs[groupBase + slot + k] = found[k];
        barrier(); // groupRuns and groupBase are read before the next round resets them
    }
}
