// Places one slice (its record from slice_setup.comp), or with point sprites
// a run of consecutive slices (slice_runs.comp), and projects it along the
// dominant axis of its normal onto the region's face, one pixel per
// (supersampled) voxel column. A run is drawn as one point sprite around
// its slices' projections (SLICE_POINTS, src/gpu/gl_voxelizer.h:
// SlicePrimitive); a slice alone as one triangle around the part of it that
// can hold fibre, or as its square where the fibre may fill the square (a
// strip of kSliceVertices, src/gpu/gpu_layout.h, with repeated corners). Any
// of them covers every pixel whose sample can hold fibre; what is sampled
// there depends on the pixel alone, so what is written never depends on the
// shape drawn, the runs or the region.

#include "common.glsl"

layout(std430, binding = kSlicesBinding) readonly buffer Slices { SliceRecord slices[]; };
#if SLICE_POINTS && SLICE_RUN > 1
// x: a run's first slice, y: its slices, all with one projection axis.
layout(std430, binding = kRunsBinding) readonly buffer Runs { uvec2 runs[]; };
#endif

uniform float uRadius;         // yarn radius, voxel units
uniform float uSupport;        // textureSupport(), units of the radius (1 for the disk)
uniform int uSupersample;
uniform ivec3 uRegionMin;      // region box in voxels
uniform ivec3 uRegionBricks;   // region size in bricks
uniform vec2 uViewport;        // viewport size in pixels (covers every axis' face)
uniform int uMargin;           // pixels around the region's face (SLICE_POINTS: sprites whose centre lies outside it)

#if !SLICE_POINTS
// What dense.frag reads (one slice, drawn as a triangle).
flat out int vAxis;
flat out ivec3 vAnchor;    // integer voxel the slice's coordinates are relative to
flat out vec3 vCenter;     // voxel units from vAnchor
flat out vec3 vRight;
flat out vec3 vUp;
flat out vec3 vTangent;
flat out vec3 vCurvature;  // curvature vector, 1 / voxel units
flat out float vThickness; // voxel units
flat out float vTwistStep; // radians the cross-section turns by at the next slice
flat out float vDepthScale; // slab depth along the projection axis, voxel units, before the bend's scale
#endif

// What append.frag's test needs, worked out once a slice rather than once a
// pixel (the raster's fragment shaders run on few units of an H100, where
// they are most of its time): where the column through a pixel meets the
// slice is affine in the pixel.
// vRun: xy, the face pixel (region-local) the tests are expanded about; z,
// the first slice's record; w, the face's size in pixels, x | y << 16.
// vAt[i]: xy, slice-local (x, y), units of the radius, where the column
// through vRun.xy's centre meets slice i; z, the square of the farthest
// |(x, y)| a kept sample can have (the support, its slack and the
// footprint's reach), or -1 past the run's end. vSteps[i]: xy, (x, y) a
// pixel along the face's axis b (footprintEdgeB); zw, along c
// (footprintEdgeC). Four components a slot: each array element takes a slot
// of its own, and the fragment shader's inputs, slot by slot, cost the
// raster on an H100 (bench/results/slice-runs-2026-11-25-h100).
flat out ivec4 vRun;
flat out vec4 vAt[kRunSlices];
flat out vec4 vSteps[kRunSlices];

void main() {
#if SLICE_POINTS && SLICE_RUN > 1
    uvec2 run = runs[gl_VertexID];
    int first = int(run.x), count = int(run.y);
#elif SLICE_POINTS
    int first = gl_VertexID, count = 1;
#else
    int first = gl_InstanceID, count = 1;
#endif
    SliceRecord s = slices[first];
    int a = floatBitsToInt(s.center.w); // every slice of a run has it (slice_runs.comp)
    int b = (a + 1) % 3, c = (a + 2) % 3;
    float S = float(uSupersample);

    // The face pixel holding the first slice's centre: the tests' terms are
    // expanded about it.
    ivec2 origin = sliceFacePixel(s, a, uRegionMin, uSupersample);
    ivec2 face = axisFirst(uRegionBricks * 8, a).yz * uSupersample; // at most 1024 x 16 pixels (regionCap_)
    vRun = ivec4(origin, first, face.x | (face.y << 16));

#if SLICE_POINTS
    // One point sprite a run: the axis-aligned square on the face around
    // each slice's square about the projection of its disk of radius `reach`
    // (or of its square's corners), widened by the same 0.05 pixel as the
    // triangle (SlicePrimitive); the viewport's margin keeps the sprite's
    // centre in it.
    vec2 lo = vec2(3.0e38), hi = vec2(-3.0e38);
    for (int i = 0; i < kRunSlices; ++i) {
        if (i < count) {
            SliceRecord si = slices[first + i];
            SliceTerms t = sliceTerms(si, a, origin, uRadius, uSupport, uSupersample, uRegionMin);
            vAt[i] = vec4(t.atOrigin, t.limit * t.limit, 0.0);
            vSteps[i] = t.steps;
            vec4 box = sliceFaceBox(si, a, t, uRegionMin, S);
            lo = min(lo, box.xy);
            hi = max(hi, box.zw);
        } else {
            vAt[i] = vec4(0.0, 0.0, -1.0, 0.0); // no pixel passes
            vSteps[i] = vec4(0.0);
        }
    }
    gl_Position = vec4((0.5 * (lo + hi) + float(uMargin)) / uViewport * 2.0 - 1.0, 0.0, 1.0);
    gl_PointSize = max(hi.x - lo.x, hi.y - lo.y) + 0.1;
#else
    SliceTerms t = sliceTerms(s, a, origin, uRadius, uSupport, uSupersample, uRegionMin);
    vAt[0] = vec4(t.atOrigin, t.limit * t.limit, 0.0);
    vSteps[0] = t.steps;

    // Why one triangle: fragments run in 2x2 quads, and a quad that an edge
    // between two triangles cuts runs in both, the sampling code twice over.
    // The square's diagonal runs through the middle of the fibre; the
    // triangle's edges lie outside the disk, where samples end at the skip.
    // On the real sweater this took 16 to 31 % off the raster's time (H100),
    // though the triangle covers more pixels than the disk needs.
    vec3 center = s.center.xyz, right = s.right.xyz, sliceUp = s.up.xyz;
    vec2 local;
    int vertex = gl_VertexID;
    if (t.reach <= t.extent) {
        // Equilateral, with inradius `reach`: corners at 2 reach; the strip's
        // fourth vertex repeats the third (a zero-area triangle draws nothing).
        float angle = float(min(vertex, 2)) * 2.0943951023931953 + 1.5707963267948966;
        local = 2.0 * t.reach * vec2(cos(angle), sin(angle));
    } else {
        // Strip order of the square's corners: (-1,-1), (1,-1), (-1,1), (1,1).
        local = t.extent * vec2((vertex & 1) != 0 ? 1.0 : -1.0, (vertex & 2) != 0 ? 1.0 : -1.0);
    }
    vec3 p = center + local.x * right + local.y * sliceUp;
    vec3 fromRegion = vec3(s.anchor.xyz - uRegionMin) + p;
    vec2 pixel = vec2(fromRegion[b], fromRegion[c]) * S;
    gl_Position = vec4(pixel / uViewport * 2.0 - 1.0, 0.0, 1.0);

    vAxis = a;
    vAnchor = s.anchor.xyz;
    vCenter = center;
    vRight = right;
    vUp = sliceUp;
    vTangent = s.tangent.xyz;
    vCurvature = s.curvature.xyz;
    vThickness = s.right.w;
    vTwistStep = s.up.w;
    vDepthScale = s.tangent.w;
#endif
}
