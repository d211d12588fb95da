// Places one slice (its record from slice_setup.comp) and
// projects it along the dominant axis of its normal onto the region's face,
// one pixel per (supersampled) voxel column. Each slice is drawn as one point
// sprite around its projection (SLICE_POINTS, src/gpu/gl_voxelizer.h:
// SlicePrimitive; the sprite worked out by slice_setup.comp), or as one
// triangle around the part of the slice that can hold fibre, or as its square
// where the fibre may fill the square (a strip of kSliceVertices,
// src/gpu/gpu_layout.h, with repeated corners). Any of them covers every
// pixel whose sample can hold fibre; what is sampled there depends on the
// pixel alone, so what is written never depends on the shape drawn or on the
// region.
layout(std430, binding = 5) readonly buffer Slices { SliceRecord slices[]; };
#if SLICE_POINTS
layout(std430, binding = 4) readonly buffer Sprites { SpriteRecord sprites[]; };
#endif

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

// What append.frag's test needs (SliceTest), worked out once a slice rather
// than once a pixel: the raster's fragment shaders run on few units of an
// H100, where they are most of its time (dense.frag reads the slice's
// vectors above).
flat out ivec4 vFace;
flat out vec2 vAtOrigin;
flat out vec4 vSteps;
flat out float vLimit;

void main() {
#if SLICE_POINTS
    // One vertex a slice (an instance a slice ran no faster). The sprite and
    // the test's terms come from the slices' placement, on every compute
    // unit: an H100 runs vertex shaders on few.
    SpriteRecord sprite = sprites[gl_VertexID];
    gl_Position = vec4(sprite.position.xy, 0.0, 1.0);
    gl_PointSize = sprite.position.z;
    vInstance = gl_VertexID;
    vFace = sprite.face;
    vAtOrigin = sprite.atOrigin.xy;
    vSteps = sprite.steps;
    vLimit = sprite.position.w;
#else
    int slice = gl_InstanceID;
    SliceRecord s = slices[slice];
    vec3 center = s.center.xyz, right = s.right.xyz, sliceUp = s.up.xyz, tangent = s.tangent.xyz;
    int a = floatBitsToInt(s.center.w);
    int b = (a + 1) % 3, c = (a + 2) % 3;
    float S = float(uSupersample);
    // The slice's square grown by two pixels of margin in the plane: those
    // are at least one pixel on the face, since the face foreshortens the
    // plane by |tangent[a]| >= 1/sqrt(3), so every pixel whose square meets
    // the slice square has its centre in it.
    float extent = uRadius + 2.0 / S;
    SliceTest test = sliceTest(s, uRadius, uSupport, uSupersample, uRegionMin, uRegionBricks);
    float reach = test.reach;
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
    vec3 fromRegion = vec3(s.anchor.xyz - uRegionMin) + p;
    vec2 pixel = vec2(fromRegion[b], fromRegion[c]) * S;
    gl_Position = vec4(pixel / uViewport * 2.0 - 1.0, 0.0, 1.0);

    vFace = test.face;
    vAtOrigin = test.atOrigin;
    vSteps = test.steps;
    vLimit = test.limit;
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
#endif
}
