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

// Relative slack of append.frag's support test (the exact test is
// sample.comp's): float rounding here must never drop a sample it keeps.
const float kSupportSlack = 1e-3;

// One slice on the face of its projection axis `a`.
struct SliceTerms {
    float reach;    // voxel units in the slice plane: the disk holding every footprint centre whose sample can read fibre
    float extent;   // voxel units: half the side of the slice's square grown by two pixels
    vec2 atOrigin;  // the test's terms about face pixel `origin` (vAt, vSteps)
    vec4 steps;
    float limit;
};

SliceTerms sliceTerms(SliceRecord s, int a, ivec2 origin) {
    vec3 center = s.center.xyz, right = s.right.xyz, sliceUp = s.up.xyz, tangent = s.tangent.xyz;
    SliceTerms t;
    // The slice's square grown by two pixels of margin in the plane: those
    // are at least one pixel on the face, since the face foreshortens the
    // plane by |tangent[a]| >= 1/sqrt(3), so every pixel whose square meets
    // the slice square has its centre in it.
    float S = float(uSupersample);
    t.extent = uRadius + 2.0 / S;
    // A sample can hold fibre only where what it reads of its footprint (the
    // pixel seen on the slice plane, a parallelogram) comes within the
    // support: with the disk, the whole parallelogram, whose farthest point
    // lies half its longer diagonal from its centre; with a texture, the
    // centres of its cells (footprintCells), (m - 1) / 2m of that diagonal.
    // footprintCells skips by half the edges' sum, which is never less: a
    // footprint between the bounds reads 0 there. A disk of radius `reach`
    // in the plane (the margin covers float rounding and the rasterizer's
    // snapping).
#if CROSS_SECTION_DISK
    const float kFootprintReach = 0.5;
#else
    const float kFootprintReach = 0.5 * float(kFootprintCells - 1) / float(kFootprintCells);
#endif
    vec3 centerA = axisFirst(center, a), rightA = axisFirst(right, a), upA = axisFirst(sliceUp, a);
    float det = tangent[a];
    vec2 edgeB = footprintEdgeB(rightA, upA, det, S, uRadius), edgeC = footprintEdgeC(rightA, upA, det, S, uRadius);
    float footprintReach = kFootprintReach * max(length(edgeB + edgeC), length(edgeB - edgeC)); // units of the radius
    t.reach = (uSupport + footprintReach) * uRadius * 1.001 + 0.05 / S;

    ivec3 anchorA = axisFirst(s.anchor.xyz, a), regionMinA = axisFirst(uRegionMin, a);
    t.atOrigin = columnCrossing(origin + regionMinA.yz * uSupersample, uSupersample, anchorA, centerA, rightA, upA, det) / uRadius;
    t.steps = vec4(edgeB, edgeC);
    t.limit = uSupport * (1.0 + kSupportSlack) + kSupportSlack + footprintReach;
    return t;
}

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
    ivec3 anchorA = axisFirst(s.anchor.xyz, a), regionMinA = axisFirst(uRegionMin, a);
    ivec2 origin = ivec2(floor((vec2(anchorA.yz - regionMinA.yz) + axisFirst(s.center.xyz, a).yz) * S));
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
            vec3 right = si.right.xyz, sliceUp = si.up.xyz;
            SliceTerms t = sliceTerms(si, a, origin);
            vAt[i] = vec4(t.atOrigin, t.limit * t.limit, 0.0);
            vSteps[i] = t.steps;
            float halfSide = t.reach <= t.extent
                             ? t.reach * max(length(vec2(right[b], sliceUp[b])), length(vec2(right[c], sliceUp[c])))
                             : t.extent * max(abs(right[b]) + abs(sliceUp[b]), abs(right[c]) + abs(sliceUp[c]));
            vec3 fromRegion = vec3(si.anchor.xyz - uRegionMin) + si.center.xyz;
            vec2 pixel = vec2(fromRegion[b], fromRegion[c]) * S;
            lo = min(lo, pixel - halfSide * S);
            hi = max(hi, pixel + halfSide * S);
        } else {
            vAt[i] = vec4(0.0, 0.0, -1.0, 0.0); // no pixel passes
            vSteps[i] = vec4(0.0);
        }
    }
    gl_Position = vec4((0.5 * (lo + hi) + float(uMargin)) / uViewport * 2.0 - 1.0, 0.0, 1.0);
    gl_PointSize = max(hi.x - lo.x, hi.y - lo.y) + 0.1;
#else
    SliceTerms t = sliceTerms(s, a, origin);
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
