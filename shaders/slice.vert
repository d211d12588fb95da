// Places slice gl_InstanceID of the draw's segment list from curve data (no
// per-slice matrices) and projects it along the dominant axis of its normal
// onto the region's face, one pixel per (supersampled) voxel column. Each
// slice is drawn as one point sprite around its projection (SLICE_POINTS,
// src/gpu/gl_voxelizer.h: SlicePrimitive), or as one triangle around the part
// of the slice that can hold fibre, or as its square where the fibre may fill
// the square (a strip of kSliceVertices, src/gpu/gpu_layout.h, with repeated
// corners). Any of them covers
// every pixel whose sample can hold fibre; the fragment shader decides from
// the pixel alone, so what is written never depends on the shape drawn or on
// the region.
layout(std430, binding = 0) readonly buffer Segments { GpuSegment segments[]; };
// Segments this draw covers (indices into `segments`), and the first
// instance of each, for the search from instance to segment.
layout(std430, binding = 1) readonly buffer DrawList { uvec2 drawList[]; }; // x: segment, y: first instance

uniform int uDrawCount;        // entries in drawList
uniform uint uUniformSlices;   // slices of every segment when all have the same count, else 0
uniform float uRadius;         // yarn radius, voxel units
uniform float uSupport;        // textureSupport(), units of the radius (1 for the disk)
uniform int uSupersample;
uniform ivec3 uRegionMin;      // region box in voxels
uniform vec2 uViewport;        // viewport size in pixels (covers every axis' face)
uniform int uMargin;           // pixels around the region's face (SLICE_POINTS: sprites whose centre lies outside it)

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

vec3 rotateMinimal(vec3 v, vec3 from, vec3 to) {
    float c = dot(from, to);
    vec3 k = cross(from, to);
    if (c < -0.999999) {
        vec3 a = abs(from);
        vec3 e = (a.x <= a.y && a.x <= a.z) ? vec3(1, 0, 0) : (a.y <= a.z ? vec3(0, 1, 0) : vec3(0, 0, 1));
        vec3 axis = normalize(cross(from, e));
        return 2.0 * dot(axis, v) * axis - v;
    }
    return v + cross(k, v) + cross(k, cross(k, v)) / (1.0 + c);
}

void main() {
    // Last list entry whose first instance is <= gl_InstanceID: a division
    // when every segment has the same slice count, else a binary search.
    uint instance = uint(gl_InstanceID);
    int lo = uUniformSlices != 0u ? int(instance / uUniformSlices) : 0;
    int hi = uUniformSlices != 0u ? lo : uDrawCount - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) >> 1;
        if (drawList[mid].y <= instance) lo = mid; else hi = mid - 1;
    }
    GpuSegment seg = segments[drawList[lo].x];
    uint k = instance - drawList[lo].y;
    float K = float(seg.info.y);
    vec3 p0 = seg.p[0].xyz, p1 = seg.p[1].xyz, p2 = seg.p[2].xyz, p3 = seg.p[3].xyz;

    float t = (float(k) + 0.5) / K;
    vec3 center = catmullRom(p0, p1, p2, p3, t);
    vec3 d1 = catmullRomDerivative(p0, p1, p2, p3, t);
    vec3 d2 = catmullRomSecondDerivative(p0, p1, p2, p3, t);
    vec3 tangent = normalize(d1);
    float thickness = catmullRomArcLength(p0, p1, p2, p3, float(k) / K, float(k + 1u) / K);

    vec3 t0 = normalize(catmullRomDerivative(p0, p1, p2, p3, 0.0));
    vec3 up = rotateMinimal(seg.up.xyz, t0, tangent);
    up = normalize(up - dot(up, tangent) * tangent);
    float twistRate = seg.p[0].w;
    float phase = seg.up.w + twistRate * t * uintBitsToFloat(seg.info.z);
    vec3 right = cos(phase) * up + sin(phase) * cross(tangent, up);
    vec3 sliceUp = cross(tangent, right);

    int a = dominantAxis(tangent);
    int b = (a + 1) % 3, c = (a + 2) % 3;

    // The slice's square grown by two pixels of margin in the plane: those
    // are at least one pixel on the face, since the face foreshortens the
    // plane by |tangent[a]| >= 1/sqrt(3), so every pixel whose square meets
    // the slice square has its centre in it.
    float S = float(uSupersample);
    float extent = uRadius + 2.0 / S;
    // A sample can hold fibre only where its footprint's centre lies within
    // the support plus half the footprint's edges (the fragment shader's
    // skip, footprintCells): a disk of radius `reach` in the plane (the
    // margin covers float rounding and the rasterizer's snapping).
    float footprintEdges = 0.5 * (length(vec2(sliceUp[c], right[c])) + length(vec2(sliceUp[b], right[b]))) / (abs(tangent[a]) * S);
    float reach = (uSupport * uRadius + footprintEdges) * 1.001 + 0.05 / S;
    ivec3 anchor = ivec3(seg.p[1].w, seg.p[2].w, seg.p[3].w);
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
    gl_PointSize = 2.0 * (halfSide * S + 0.05);
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

    vAxis = a;
    vAnchor = anchor;
    vCenter = center;
    vRight = right;
    vUp = sliceUp;
    vTangent = tangent;
    vCurvature = (d2 - dot(d2, tangent) * tangent) / dot(d1, d1);
    vThickness = thickness;
    vTwistStep = twistRate * thickness;
    vDepthScale = thickness / abs(tangent[a]);
}
