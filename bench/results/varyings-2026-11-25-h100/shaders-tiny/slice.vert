// Places one slice (its record from slice_setup.comp) and
// projects it along the dominant axis of its normal onto the region's face,
// one pixel per (supersampled) voxel column. Each slice is drawn as one point
// sprite around its projection (SLICE_POINTS, src/gpu/gl_voxelizer.h:
// SlicePrimitive), or as one triangle around the part of the slice that can
// hold fibre, or as its square where the fibre may fill the square (a strip
// of kSliceVertices, src/gpu/gpu_layout.h, with repeated corners). Any of
// them covers every pixel whose sample can hold fibre; what is sampled there
// depends on the pixel alone, so what is written never depends on the shape
// drawn or on the region.
layout(std430, binding = 5) readonly buffer Slices { SliceRecord slices[]; };

uniform float uRadius;         // yarn radius, voxel units
uniform float uSupport;        // textureSupport(), units of the radius (1 for the disk)
uniform int uSupersample;
uniform ivec3 uRegionMin;      // region box in voxels
uniform ivec3 uRegionBricks;   // region size in bricks
uniform vec2 uViewport;        // viewport size in pixels (covers every axis' face)
uniform int uMargin;           // pixels around the region's face (SLICE_POINTS: sprites whose centre lies outside it)

flat out int vInstance;    // the slice's record
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

// What append.frag's test needs, worked out once a slice rather than once a
// pixel (the raster's fragment shaders run on few units of an H100, where
// they are most of its time; dense.frag reads the slice's vectors above):
// where the column through a pixel meets the slice is affine in the pixel.
flat out ivec4 vFace;    // xy: the face pixel (region-local) the test is expanded about; zw: the face's size in pixels
flat out vec2 vAtOrigin; // slice-local (x, y), units of the radius, where the column through vFace.xy's centre meets the slice
flat out vec4 vSteps;    // xy: (x, y) a pixel along the face's axis b (footprintEdgeB); zw: along c (footprintEdgeC)
flat out float vLimit;   // farthest |(x, y)| a kept sample can have: the support, its slack and the footprint's reach

// Relative slack of append.frag's support test (the exact test is
// sample.comp's): float rounding here must never drop a sample it keeps.
const float kSupportSlack = 1e-3;

void main() {
#if SLICE_POINTS
    // Points: one vertex a slice (an instance a slice ran no faster).
    int slice = gl_VertexID;
#else
    int slice = gl_InstanceID;
#endif
    SliceRecord s = slices[slice];
    vec3 center = s.center.xyz, right = s.right.xyz, sliceUp = s.up.xyz, tangent = s.tangent.xyz;
    int a = floatBitsToInt(s.center.w);
    int b = (a + 1) % 3, c = (a + 2) % 3;

    // The slice's square grown by two pixels of margin in the plane: those
    // are at least one pixel on the face, since the face foreshortens the
    // plane by |tangent[a]| >= 1/sqrt(3), so every pixel whose square meets
    // the slice square has its centre in it.
    float S = float(uSupersample);
    float extent = uRadius + 2.0 / S;
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
    float reach = (uSupport + footprintReach) * uRadius * 1.001 + 0.05 / S;
    ivec3 anchor = s.anchor.xyz;
#if SLICE_POINTS
    // One point sprite a slice: an axis-aligned square on the face around the
    // projection of the disk of radius `reach` (or of the square's corners),
    // widened by the same 0.05 pixel as the triangle (SlicePrimitive); the
    // viewport's margin keeps the sprite's centre in it.
    float halfSide = reach <= extent
                     ? reach * max(length(vec2(right[b], sliceUp[b])), length(vec2(right[c], sliceUp[c])))
                     : extent * max(abs(right[b]) + abs(sliceUp[b]), abs(right[c]) + abs(sliceUp[c]));
    vec3 fromRegion = vec3(anchor - uRegionMin) + center;
    vec2 pixel = vec2(fromRegion[b], fromRegion[c]) * S + float(uMargin);
    gl_Position = vec4(pixel / uViewport * 2.0 - 1.0, 0.0, 1.0);
    gl_PointSize = 1.0; // variant: one-pixel sprites
#else
    // Why one triangle: fragments run in 2x2 quads, and a quad that an edge
    // between two triangles cuts runs in both, the sampling code twice over.
    // The square's diagonal runs through the middle of the fibre; the
    // triangle's edges lie outside the disk, where samples end at the skip.
    // On the real sweater this took 16 to 31 % off the raster's time (H100),
    // though the triangle covers more pixels than the disk needs.
    vec2 local;
    int vertex = gl_VertexID;
    if (reach <= extent) {
        // Equilateral, with inradius `reach`: corners at 2 reach; the strip's
        // fourth vertex repeats the third (a zero-area triangle draws nothing).
        float angle = float(min(vertex, 2)) * 2.0943951023931953 + 1.5707963267948966;
        local = 2.0 * reach * vec2(cos(angle), sin(angle));
    } else {
        // Strip order of the square's corners: (-1,-1), (1,-1), (-1,1), (1,1).
        local = extent * vec2((vertex & 1) != 0 ? 1.0 : -1.0, (vertex & 2) != 0 ? 1.0 : -1.0);
    }
    vec3 p = center + local.x * right + local.y * sliceUp;
    vec3 fromRegion = vec3(anchor - uRegionMin) + p;
    vec2 pixel = vec2(fromRegion[b], fromRegion[c]) * S;
    gl_Position = vec4(pixel / uViewport * 2.0 - 1.0, 0.0, 1.0);
#endif

    // The face pixel holding the slice's centre, and the test's terms there.
    ivec3 anchorA = axisFirst(anchor, a), regionMinA = axisFirst(uRegionMin, a);
    ivec2 origin = ivec2(floor((vec2(anchorA.yz - regionMinA.yz) + centerA.yz) * S));
    vFace = ivec4(origin, axisFirst(uRegionBricks * 8, a).yz * uSupersample);
    vAtOrigin = columnCrossing(origin + regionMinA.yz * uSupersample, uSupersample, anchorA, centerA, rightA, upA, det) / uRadius;
    vSteps = vec4(edgeB, edgeC);
    vLimit = uSupport * (1.0 + kSupportSlack) + kSupportSlack + footprintReach;

    vInstance = slice;
    vAxis = a;
    vAnchor = s.anchor.xyz;
    vCenter = center;
    vRight = right;
    vUp = sliceUp;
    vTangent = tangent;
    vCurvature = s.curvature.xyz;
    vThickness = s.right.w;
    vTwistStep = s.up.w;
    vDepthScale = s.tangent.w;
}
