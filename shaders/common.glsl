// Shared by every yarnvox shader: buffer layouts and the sampling rule's
// helpers. src/gpu/gpu_layout.h holds the C++ side of each layout.

// Fixed-point scale of volume fractions (src/core/sampling.h: kFixedScale).
const float kFixedScale = 16777216.0;
const int kBrickVoxels = 512;
// Smallest share of a voxel a sample gives it (src/core/sampling.h: kMinVoxelShare).
const float kMinVoxelShare = 1.0 / 65536.0;

// One curve segment (96 bytes): control points in voxel units relative to
// the segment's anchor, an integer voxel (p[1].w, p[2].w, p[3].w), so that
// floats keep their precision anywhere in the grid; p[0].w = twist rate
// (radians per voxel unit of length);
// up.w = twist phase at the segment's start; info = first slice within the
// draw's list, slice count, float bits of the segment length, yarn.
struct GpuSegment {
    vec4 p[4];
    vec4 up;
    uvec4 info;
};

// One voxel fragment (16 bytes): region-local key (brick << 9 | voxel in
// brick), fixed-point volume fraction, axis code, float bits of the density.
struct Fragment {
    uint key;
    uint weight;
    uint axis;
    uint density;
};

// One slice placed from its segment (slice_setup.comp), 96 bytes: what the
// sprite's vertex shader and the sampling pass read of it.
struct SliceRecord {
    vec4 center;    // xyz: voxel units from `anchor`; w: projection axis (int bits)
    ivec4 anchor;   // xyz: the integer voxel the slice's coordinates are relative to
    vec4 right;     // xyz: the cross-section's right; w: thickness, voxel units
    vec4 up;        // xyz: the cross-section's up (tangent x right); w: radians it turns by at the next slice
    vec4 tangent;   // xyz; w: slab depth along the projection axis before the bend's scale, voxel units
    vec4 curvature; // xyz: curvature vector, 1 / voxel units; w: unused
};

// Slices one point sprite draws at most (SLICE_POINTS: a run of consecutive
// slices, slice_runs.comp; SLICE_RUN, chooseSlicePrimitive in
// src/gpu/gl_voxelizer.cpp: 1, or gpu_layout.h's kSliceRunMax where the yarn
// is thin on the face); a triangle draws one.
#if SLICE_POINTS
const int kRunSlices = SLICE_RUN;
#else
const int kRunSlices = 1;
#endif

vec3 catmullRom(vec3 p0, vec3 p1, vec3 p2, vec3 p3, float t) {
    float t2 = t * t, t3 = t2 * t;
    return 0.5 * ((-t + 2.0 * t2 - t3) * p0 + (2.0 - 5.0 * t2 + 3.0 * t3) * p1 +
                  (t + 4.0 * t2 - 3.0 * t3) * p2 + (-t2 + t3) * p3);
}

vec3 catmullRomDerivative(vec3 p0, vec3 p1, vec3 p2, vec3 p3, float t) {
    float t2 = t * t;
    return 0.5 * ((-1.0 + 4.0 * t - 3.0 * t2) * p0 + (-10.0 * t + 9.0 * t2) * p1 +
                  (1.0 + 8.0 * t - 9.0 * t2) * p2 + (-2.0 * t + 3.0 * t2) * p3);
}

// Arc length for t in [t0, t1]: three-point Gauss-Legendre quadrature of the
// speed (src/garment/catmull_rom.h: catmullRomArcLength).
float catmullRomArcLength(vec3 p0, vec3 p1, vec3 p2, vec3 p3, float t0, float t1) {
    float mid = 0.5 * (t0 + t1), halfWidth = 0.5 * (t1 - t0), node = 0.7745966692414834 * halfWidth;
    return halfWidth * (5.0 / 9.0 * length(catmullRomDerivative(p0, p1, p2, p3, mid - node)) +
                   8.0 / 9.0 * length(catmullRomDerivative(p0, p1, p2, p3, mid)) +
                   5.0 / 9.0 * length(catmullRomDerivative(p0, p1, p2, p3, mid + node)));
}

vec3 catmullRomSecondDerivative(vec3 p0, vec3 p1, vec3 p2, vec3 p3, float t) {
    return 0.5 * ((4.0 - 6.0 * t) * p0 + (-10.0 + 18.0 * t) * p1 + (8.0 - 18.0 * t) * p2 + (-2.0 + 6.0 * t) * p3);
}

// The tangent a segment leaves its first knot by (src/garment/catmull_rom.h:
// knotDirection): the derivative at t = 0; at a cusp, where the knot's
// neighbours coincide (equal numbers, so the derivative is exactly zero),
// the second derivative, or where that is zero too, the third.
vec3 knotTangent(vec3 p0, vec3 p1, vec3 p2, vec3 p3) {
    vec3 d = catmullRomDerivative(p0, p1, p2, p3, 0.0);
    if (d == vec3(0.0)) d = catmullRomSecondDerivative(p0, p1, p2, p3, 0.0);
    if (d == vec3(0.0)) d = 3.0 * (-p0 + 3.0 * p1 - 3.0 * p2 + p3);
    return normalize(d);
}

// Projection axis: the dominant component of the slice normal; components
// within a relative 2^-10 of the largest go to the lowest index, so that
// float here and double on the CPU agree at exact 45-degree ties
// (src/core/sampling.h: dominantAxis).
int dominantAxis(vec3 n) {
    vec3 a = abs(n);
    float floorValue = max(a.x, max(a.y, a.z)) * (1.0 - 1.0 / 1024.0);
    return a.x >= floorValue ? 0 : (a.y >= floorValue ? 1 : 2);
}

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

// Slice k of segment `seg` (src/garment/slices.h: the same frame, twist and
// slab as the CPU reference places it).
SliceRecord placeSlice(GpuSegment seg, uint k) {
    float K = float(seg.info.y);
    vec3 p0 = seg.p[0].xyz, p1 = seg.p[1].xyz, p2 = seg.p[2].xyz, p3 = seg.p[3].xyz;

    float t = (float(k) + 0.5) / K;
    vec3 center = catmullRom(p0, p1, p2, p3, t);
    vec3 d1 = catmullRomDerivative(p0, p1, p2, p3, t);
    vec3 d2 = catmullRomSecondDerivative(p0, p1, p2, p3, t);
    vec3 tangent = normalize(d1);
    float thickness = catmullRomArcLength(p0, p1, p2, p3, float(k) / K, float(k + 1u) / K);

    vec3 t0 = knotTangent(p0, p1, p2, p3);
    vec3 up = rotateMinimal(seg.up.xyz, t0, tangent);
    up = normalize(up - dot(up, tangent) * tangent);
    float twistRate = seg.p[0].w;
    float phase = seg.up.w + twistRate * t * uintBitsToFloat(seg.info.z);
    vec3 right = cos(phase) * up + sin(phase) * cross(tangent, up);
    vec3 sliceUp = cross(tangent, right);
    int a = dominantAxis(tangent);

    SliceRecord s;
    s.center = vec4(center, intBitsToFloat(a));
    s.anchor = ivec4(int(seg.p[1].w), int(seg.p[2].w), int(seg.p[3].w), 0);
    s.right = vec4(right, thickness);
    s.up = vec4(sliceUp, twistRate * thickness);
    s.tangent = vec4(tangent, thickness / abs(tangent[a]));
    s.curvature = vec4((d2 - dot(d2, tangent) * tangent) / dot(d1, d1), 0.0);
    return s;
}

// Axis folded onto the upper hemisphere (v and -v are the same fibre).
vec3 canonicalAxis(vec3 v) {
    if (v.z < 0.0 || (v.z == 0.0 && (v.y < 0.0 || (v.y == 0.0 && v.x < 0.0)))) v = -v;
    return v;
}

// 16+16-bit octahedral code of an axis (src/core/sampling.h: encodeAxis).
uint encodeAxis(vec3 axis) {
    vec3 v = canonicalAxis(axis);
    float s = abs(v.x) + abs(v.y) + abs(v.z);
    vec2 uw = clamp(v.xy / s, -1.0, 1.0) * 0.5 + 0.5;
    uvec2 q = uvec2(round(uw * 65535.0));
    return (q.x << 16) | q.y;
}

vec3 decodeAxis(uint code) {
    vec2 uw = vec2(float(code >> 16), float(code & 0xffffu)) / 65535.0 * 2.0 - 1.0;
    return normalize(vec3(uw, max(0.0, 1.0 - abs(uw.x) - abs(uw.y))));
}

// Area of (disk of radius r about the origin) ∩ (parallelogram centred at c
// with edges u, v) over the parallelogram's area (src/core/footprint.h:
// diskCoverage): shoelace about c, plus a circular cap for every arc.
float diskCoverage(vec2 c, vec2 u, vec2 v, float r) {
    float area = abs(u.x * v.y - u.y * v.x);
    if (!(area > 0.0)) return 0.0;
    float reach = 0.5 * (length(u) + length(v)), dist = length(c);
    if (dist - reach >= r) return 0.0;
    if (dist + reach <= r) return 1.0;
    if (u.x * v.y - u.y * v.x < 0.0) { vec2 t = u; u = v; v = t; }
    vec2 corner[4] = vec2[4](c - 0.5 * u - 0.5 * v, c + 0.5 * u - 0.5 * v, c + 0.5 * u + 0.5 * v, c - 0.5 * u + 0.5 * v);
    float r2 = r * r;
    float tIn[4], tOut[4];
    bool inside[4];
    for (int i = 0; i < 4; ++i) {
        vec2 a = corner[i], d = corner[(i + 1) & 3] - a;
        float qa = dot(d, d), qb = dot(a, d), qc = dot(a, a) - r2;
        float disc = qb * qb - qa * qc;
        float s = sqrt(max(disc, 0.0));
        tIn[i] = max(0.0, (-qb - s) / qa);
        tOut[i] = min(1.0, (-qb + s) / qa);
        inside[i] = disc > 0.0 && tOut[i] > tIn[i];
    }
    // Edge by edge with fixed indices, as src/core/footprint.h explains: a
    // list of boundary points indexed at run time went to scratch memory and
    // made the disk program 8 to 13 times slower than the texture's.
    float twice = 0.0, caps = 0.0;
    bool any = false;
    for (int i = 0; i < 4; ++i) {
        if (!inside[i]) continue;
        any = true;
        int next = (i + 1) & 3;
        vec2 a = corner[i], d = corner[next] - a;
        vec2 entry = a + tIn[i] * d;
        vec2 nextEntry = entry;
        for (int step = 1; step < 4; ++step) {
            int k = (i + step) & 3;
            if (inside[k]) {
                nextEntry = corner[k] + tIn[k] * (corner[(k + 1) & 3] - corner[k]);
                break;
            }
        }
        bool exits = tOut[i] < 1.0 || !inside[next] || tIn[next] > 0.0;
        vec2 exitPoint = exits ? a + tOut[i] * d : nextEntry;
        vec2 p = entry - c, q = exitPoint - c, o = nextEntry - c;
        twice += (p.x * q.y - p.y * q.x) + (q.x * o.y - q.y * o.x);
        if (exits) {
            float theta = atan(exitPoint.x * nextEntry.y - exitPoint.y * nextEntry.x, dot(exitPoint, nextEntry));
            if (theta < 0.0) theta = theta > -1e-4 ? 0.0 : theta + 6.28318530717959;
            float t2 = theta * theta;
            float excess = theta < 1e-2 ? theta * t2 / 6.0 * (1.0 - t2 / 20.0) : theta - sin(theta);
            caps += 0.5 * r2 * excess;
        }
    }
    if (!any) {
        for (int i = 0; i < 4; ++i) {
            vec2 e = corner[(i + 1) & 3] - corner[i];
            if (e.x * -corner[i].y - e.y * -corner[i].x < 0.0) return 0.0;
        }
        return min(1.0, 3.14159265358979 * r2 / area);
    }
    return clamp((0.5 * twice + caps) / area, 0.0, 1.0);
}

// Mean density over a footprint cell, slice-local units of the radius
// (src/garment/cross_section.h: CrossSection::footprintDensity): exact
// coverage for the disk, else the texture, bilinear, at the cell's centre (0
// outside the slice square). The four texels come from four texelFetch;
// with CROSS_SECTION_GATHER from one textureGather at the corner they share
// (the texture clamps to its edge, as the CPU clamps); with
// CROSS_SECTION_QUAD (the default) from one texelFetch of a texture that
// holds each lookup's four. The same texels; the quad is the fastest on
// NVIDIA's driver and on llvmpipe (cross_section_texture.h: TexelReads).
// `size`: the cross-section's width in texels, asked once a sample
// (textureSize in the cell loop was a tenth of the raster's time on NVIDIA's
// driver).
float footprintDensity(usampler2D crossSection, int size, bool disk, vec2 c, vec2 e0, vec2 e1) {
    if (disk) return diskCoverage(c, e0, e1, 1.0);
    if (!(c.x >= -1.0 && c.x < 1.0 && c.y >= -1.0 && c.y < 1.0)) return 0.0;
    // Bilinear between texel centres (CrossSection::bilinear).
    vec2 f = (c + 1.0) * 0.5 * float(size) - 0.5;
    vec2 f0 = floor(f), t = f - f0;
#if CROSS_SECTION_QUAD
    // One texel holds the four (uploadCrossSectionTexture): the one at
    // floor(f) + 1, which the lookup's range keeps within [0, size].
    uvec4 texel = texelFetch(crossSection, clamp(ivec2(f0) + 1, ivec2(0), ivec2(size)), 0);
    float top = float(texel.x) * (1.0 - t.x) + float(texel.y) * t.x;
    float bottom = float(texel.z) * (1.0 - t.x) + float(texel.w) * t.x;
#elif CROSS_SECTION_GATHER
    // x: (i0, j1), y: (i1, j1), z: (i1, j0), w: (i0, j0).
    vec4 texel = vec4(textureGather(crossSection, (f0 + 1.0) / float(size)));
    float top = texel.w * (1.0 - t.x) + texel.z * t.x;
    float bottom = texel.x * (1.0 - t.x) + texel.y * t.x;
#else
    ivec2 i0 = clamp(ivec2(f0), ivec2(0), ivec2(size - 1)), i1 = clamp(ivec2(f0) + 1, ivec2(0), ivec2(size - 1));
    float top = float(texelFetch(crossSection, ivec2(i0.x, i0.y), 0).r) * (1.0 - t.x) +
                float(texelFetch(crossSection, ivec2(i1.x, i0.y), 0).r) * t.x;
    float bottom = float(texelFetch(crossSection, ivec2(i0.x, i1.y), 0).r) * (1.0 - t.x) +
                   float(texelFetch(crossSection, ivec2(i1.x, i1.y), 0).r) * t.x;
#endif
    return (top * (1.0 - t.y) + bottom * t.y) / 255.0;
}

// Cells per side of a sample's footprint (CrossSection::kFootprintCells).
const int kFootprintCells = 4;
const int kCells = kFootprintCells * kFootprintCells;

// A vector's components with the projection axis a first, then b = a + 1,
// then c = a + 2 (mod 3). The sampling code below takes its vectors this way
// and indexes them with constants: a component index known only at run time
// made NVIDIA's compiler keep the vectors in memory instead of registers, a
// sixth of the raster's time.
vec3 axisFirst(vec3 v, int a) { return a == 0 ? v : (a == 1 ? v.yzx : v.zxy); }
ivec3 axisFirst(ivec3 v, int a) { return a == 0 ? v : (a == 1 ? v.yzx : v.zxy); }
// The inverse: (a, b, c) components back to (x, y, z).
ivec3 axisBack(ivec3 v, int a) { return a == 0 ? v : (a == 1 ? v.zxy : v.yzx); }

// Where the column through the centre of `pixel` (global, on the face's
// axes b and c, supersampled by S) meets the slice: slice-local (x, y) in
// voxel units along right and up. Vectors axis first (axisFirst); right x up
// = tangent, so the 2x2 system has determinant det = tangent[a]. Integers
// first (exact), then small floats.
vec2 columnCrossing(ivec2 pixel, int S, ivec3 anchor, vec3 center, vec3 right, vec3 up, float det) {
    ivec2 fromAnchor = pixel - anchor.yz * S;
    float db = (float(fromAnchor.x) + 0.5) / float(S) - center.y;
    float dc = (float(fromAnchor.y) + 0.5) / float(S) - center.z;
    return vec2((db * up.z - dc * up.y) / det, (right.y * dc - right.z * db) / det);
}

// The edges of a sample's footprint (its pixel seen on the slice plane), in
// units of the radius: one pixel along the face's axis b, and along c.
// Vectors axis first; det = tangent[a].
vec2 footprintEdgeB(vec3 right, vec3 up, float det, float S, float radius) {
    return vec2(up.z, -right.z) / (det * S * radius);
}
vec2 footprintEdgeC(vec3 right, vec3 up, float det, float S, float radius) {
    return vec2(-up.y, right.y) / (det * S * radius);
}

// The least distance from the slice's centre, units of the radius, that the
// footprint about (x, y) (voxel units) can reach: its centre's distance less
// half its edges.
float footprintNearest(vec2 xy, vec2 edgeB, vec2 edgeC, float radius) {
    return length(xy / radius) - 0.5 * (length(edgeB) + length(edgeC));
}

// Relative slack of the item test's support bound (the exact test is
// sample.comp's): float rounding there must never drop a sample it keeps.
const float kSupportSlack = 1e-3;

// One slice on the face of its projection axis `a`: what the sample items'
// test needs of it (append.frag, with the terms slice.vert works out once a
// slice; slice_items.comp). `radius`: the yarn's, voxel units; `support`:
// textureSupport(), units of the radius; `S`: the supersampling;
// `regionMin`: the region's first voxel.
struct SliceTerms {
    float reach;    // voxel units in the slice plane: the disk holding every footprint centre whose sample can read fibre
    float extent;   // voxel units: half the side of the slice's square grown by two pixels
    vec2 atOrigin;  // slice-local (x, y), units of the radius, where the column through face pixel `origin` meets the slice
    vec4 steps;     // xy: (x, y) a pixel along the face's axis b (footprintEdgeB); zw: along c (footprintEdgeC)
    float limit;    // the farthest |(x, y)| a kept sample can have: the support, its slack and the footprint's reach
};

SliceTerms sliceTerms(SliceRecord s, int a, ivec2 origin, float radius, float support, int supersample, ivec3 regionMin) {
    vec3 center = s.center.xyz, right = s.right.xyz, sliceUp = s.up.xyz, tangent = s.tangent.xyz;
    SliceTerms t;
    // The slice's square grown by two pixels of margin in the plane: those
    // are at least one pixel on the face, since the face foreshortens the
    // plane by |tangent[a]| >= 1/sqrt(3), so every pixel whose square meets
    // the slice square has its centre in it.
    float S = float(supersample);
    t.extent = radius + 2.0 / S;
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
    vec2 edgeB = footprintEdgeB(rightA, upA, det, S, radius), edgeC = footprintEdgeC(rightA, upA, det, S, radius);
    float footprintReach = kFootprintReach * max(length(edgeB + edgeC), length(edgeB - edgeC)); // units of the radius
    t.reach = (support + footprintReach) * radius * 1.001 + 0.05 / S;

    ivec3 anchorA = axisFirst(s.anchor.xyz, a), regionMinA = axisFirst(regionMin, a);
    t.atOrigin = columnCrossing(origin + regionMinA.yz * supersample, supersample, anchorA, centerA, rightA, upA, det) / radius;
    t.steps = vec4(edgeB, edgeC);
    t.limit = support * (1.0 + kSupportSlack) + kSupportSlack + footprintReach;
    return t;
}

// The face pixel (region-local) holding the slice's centre, on the face of
// its projection axis `a`: the item test's terms are expanded about it.
ivec2 sliceFacePixel(SliceRecord s, int a, ivec3 regionMin, int supersample) {
    ivec3 anchorA = axisFirst(s.anchor.xyz, a), regionMinA = axisFirst(regionMin, a);
    return ivec2(floor((vec2(anchorA.yz - regionMinA.yz) + axisFirst(s.center.xyz, a).yz) * float(supersample)));
}

// The axis-aligned box on the face (region-local pixels: xy its low
// corner, zw its high one) around the slice's disk of radius t.reach, or
// around its square's corners where that is smaller: every pixel whose
// sample can hold fibre has its centre in it.
vec4 sliceFaceBox(SliceRecord s, int a, SliceTerms t, ivec3 regionMin, float S) {
    int b = (a + 1) % 3, c = (a + 2) % 3;
    vec3 right = s.right.xyz, sliceUp = s.up.xyz;
    float halfSide = t.reach <= t.extent
                     ? t.reach * max(length(vec2(right[b], sliceUp[b])), length(vec2(right[c], sliceUp[c])))
                     : t.extent * max(abs(right[b]) + abs(sliceUp[b]), abs(right[c]) + abs(sliceUp[c]));
    vec3 fromRegion = vec3(s.anchor.xyz - regionMin) + s.center.xyz;
    vec2 pixel = vec2(fromRegion[b], fromRegion[c]) * S;
    return vec4(pixel - halfSide * S, pixel + halfSide * S);
}

// Where the centre of footprint cell (p, q) lies on the slice, in units of
// the radius: first + p stepP + q stepQ (the pixel's sub-squares seen on the
// slice plane, about the column's crossing (x, y), voxel units; det =
// tangent[a]). Vectors axis first (axisFirst).
struct CellGrid {
    vec2 first, stepP, stepQ;
};
CellGrid footprintCellGrid(vec3 right, vec3 up, float det, float S, float radius, float x, float y) {
    float m = float(kFootprintCells);
    float scale = 1.0 / (det * radius * m * S);
    CellGrid g;
    g.stepP = vec2(up.z, -right.z) * scale; // one cell along the face's axis b
    g.stepQ = vec2(-up.y, right.y) * scale; // one cell along c
    g.first = vec2(x, y) / radius - 0.5 * (m - 1.0) * (g.stepP + g.stepQ);
    return g;
}

// A sample's footprint on the slice in kFootprintCells^2 cells, each with
// its fibre density and its column's depth interval [z0, z1) through the
// slab, in voxels along the projection axis (src/cpu/slice_sampler.h:
// sampleSlice). The slice's vectors come axis first (axisFirst).
// `support`: slice-local distance, units of the radius, beyond which the
// texture reads 0 (src/garment/cross_section.h: textureSupport); a footprint
// wholly beyond it is skipped, as on the CPU. Returns the sum of the cells'
// densities (0: no fibre).
float footprintCells(usampler2D crossSection, bool disk, float support, float S, float radius,
                     vec3 center, vec3 right, vec3 up, vec3 tangent, vec3 curvature, float depthScale, float x, float y,
                     out float cellDensity[kCells], out float cellZ0[kCells], out float cellZ1[kCells],
                     out float zMin, out float zMax) {
    float det = tangent.x;
    vec2 edgeB = footprintEdgeB(right, up, det, S, radius), edgeC = footprintEdgeC(right, up, det, S, radius);
    zMin = 1e30;
    zMax = -1e30;
    float coverage = 0.0;
    if (disk) {
        coverage = footprintDensity(crossSection, 0, true, vec2(x, y) / radius, edgeB, edgeC);
        if (!(coverage > 0.0)) return 0.0;
    } else if (footprintNearest(vec2(x, y), edgeB, edgeC, radius) > support) {
        return 0.0;
    }
#if CROSS_SECTION_QUAD
    int size = disk ? 0 : textureSize(crossSection, 0).x - 1; // the quad texture has a texel more a side
#else
    int size = disk ? 0 : textureSize(crossSection, 0).x;
#endif
    // The cells' centres, their lookups and their depths are affine in the
    // cell's (p, q): a start and two steps, worked out once a sample.
    float m = float(kFootprintCells), density = 0.0;
    CellGrid cells = footprintCellGrid(right, up, det, S, radius, x, y);
    float bendR = dot(curvature, right) * radius, bendU = dot(curvature, up) * radius;
    float rightA = right.x * radius, upA = up.x * radius;
    for (int q = 0; q < kFootprintCells; ++q)
        for (int p = 0; p < kFootprintCells; ++p) {
            int k = q * kFootprintCells + p;
            vec2 c = cells.first + float(p) * cells.stepP + float(q) * cells.stepQ;
            float d = disk && coverage >= 1.0 ? 1.0 : footprintDensity(crossSection, size, disk, c, edgeB / m, edgeC / m);
            float depth = max(0.0, 1.0 - (c.x * bendR + c.y * bendU)) * depthScale;
            cellZ0[k] = center.x + c.x * rightA + c.y * upA - 0.5 * depth;
            cellZ1[k] = cellZ0[k] + depth;
            cellDensity[k] = d > 0.0 && depth > 0.0 ? d : 0.0;
            if (cellDensity[k] > 0.0) {
                density += d;
                zMin = min(zMin, cellZ0[k]);
                zMax = max(zMax, cellZ1[k]);
            }
        }
    return density;
}

// What the cells put into voxel layer [v, v + 1): density times depth.
float layerShare(float v, float cellDensity[kCells], float cellZ0[kCells], float cellZ1[kCells]) {
    float share = 0.0;
    for (int k = 0; k < kCells; ++k)
        if (cellDensity[k] > 0.0) share += cellDensity[k] * max(0.0, min(cellZ1[k], v + 1.0) - max(cellZ0[k], v));
    return share;
}

// --- The slices render's slabs (inspect_slices.vert and .frag,
// inspect_slices_keys.comp, inspect_slices_composite.comp): a slice of the
// table (per slice: (centre, thickness), (tangent, place in its run)) drawn
// as the slab of yarn it stands for, a box of 2 radius x 2 radius x
// thickness about its centre in the frame (right, up, tangent). At a coarser
// level of detail a slice stands for `span` slices of its run
// (inspect_slices_keys.comp): its slab then reaches from its own centre to
// the last one's, their thicknesses included, along the chord between them.
struct Slab {
    vec3 centre;
    mat3 frame; // columns: right, up, tangent (unit)
    vec3 halfSize;
};

// Slice i's slab where it stands for `span` slices.
Slab slabOf(samplerBuffer slices, uint i, uint span, float radius) {
    vec4 a = texelFetch(slices, int(2u * i));
    vec3 t = texelFetch(slices, int(2u * i + 1u)).xyz;
    vec3 centre = a.xyz;
    float thickness = a.w;
    if (span > 1u) {
        vec4 last = texelFetch(slices, int(2u * (i + span - 1u)));
        vec3 chord = last.xyz - a.xyz;
        float chordLength = length(chord);
        centre = 0.5 * (a.xyz + last.xyz);
        if (chordLength > 1e-6) t = chord / chordLength;
        thickness = chordLength + 0.5 * (a.w + last.w);
    }
    // The disk is round: any frame across the tangent will do.
    vec3 helper = abs(t.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    vec3 r = normalize(cross(t, helper));
    Slab s;
    s.centre = centre;
    s.frame = mat3(r, cross(t, r), t);
    s.halfSize = vec3(radius, radius, 0.5 * thickness);
    return s;
}

// Slice i's slab, with the slices it stands for from `spans`.
Slab sliceSlab(samplerBuffer slices, usamplerBuffer spans, uint i, float radius) {
    return slabOf(slices, i, texelFetch(spans, int(i)).x, radius);
}

// The box of pixels the slab's eight corners project to on a picture of
// `pixels` (lo.xy, hi.xy, pixel units from its lower left corner), so that
// every pixel whose ray meets the slab has its centre inside; false where a
// corner lies on or behind the eye's plane (the box is then unbounded).
bool slabPixelBox(Slab s, mat4 viewProjection, vec2 pixels, out vec4 box) {
    vec2 lo = vec2(1e30), hi = vec2(-1e30);
    for (int k = 0; k < 8; ++k) {
        vec3 corner = vec3((k & 1) != 0, (k & 2) != 0, (k & 4) != 0) * 2.0 - 1.0;
        vec4 clip = viewProjection * vec4(s.centre + s.frame * (corner * s.halfSize), 1.0);
        if (clip.w <= 1e-6) {
            box = vec4(-1e30, -1e30, 1e30, 1e30);
            return false;
        }
        vec2 pixel = (clip.xy / clip.w * 0.5 + 0.5) * pixels;
        lo = min(lo, pixel);
        hi = max(hi, pixel);
    }
    box = vec4(lo, hi);
    return true;
}

// The pixels whose centre lies in a slab's screen box (slabPixelBox, less
// `origin`): (x0, y0, x1, y1) inclusive, none where x0 > x1 or y0 > y1,
// clamped as floats to a pixel beyond [0, last] (an unbounded box's are no
// ints). A ray's cut with the slab is exact, so the box has only to hold
// every pixel whose ray meets it: a 64th of a pixel more each side for the
// corners' rounding.
vec4 slabPixelRange(vec4 box, vec2 origin, vec2 last) {
    const float rounding = 1.0 / 64.0;
    vec4 range = vec4(ceil(box.xy - origin - rounding - 0.5), floor(box.zw - origin + rounding - 0.5));
    return clamp(range, vec4(-1.0), vec4(last, last) + 1.0);
}

// The 16 x 16 tiles of a picture of `pixels` that hold pixels whose centre
// lies in the slab's screen box, inclusive (x0, y0, x1, y1; none where
// x0 > x1 or y0 > y1): every tile where its box is unbounded (the slices
// composited by tiles, render/slice_tiles.h).
ivec4 slabTiles(Slab s, mat4 viewProjection, vec2 pixels) {
    vec4 box;
    slabPixelBox(s, viewProjection, pixels, box);
    vec4 range = slabPixelRange(box, vec2(0.0), pixels - 1.0);
    ivec2 lo = max(ivec2(range.xy), ivec2(0)), hi = min(ivec2(range.zw), ivec2(pixels) - 1);
    return lo.x <= hi.x && lo.y <= hi.y ? ivec4(lo >> 4, hi >> 4) : ivec4(1, 1, 0, 0);
}

// A ray's interval (enter, leave) in the slab's box, from its origin
// `localEye` along the unit `d`, both in the slab's frame from its centre
// (the slab method; IEEE infinities where d has a zero): empty where
// enter >= leave.
vec2 slabBoxInterval(vec3 localEye, vec3 d, vec3 halfSize) {
    vec3 inv = 1.0 / d;
    vec3 t1 = (-halfSize - localEye) * inv, t2 = (halfSize - localEye) * inv;
    vec3 lo = min(t1, t2), hi = max(t1, t2);
    return vec2(max(max(lo.x, lo.y), lo.z), min(min(hi.x, hi.y), hi.z));
}

// What the slab's yarn adds to a ray crossing its box over `interval`:
// premultiplied colour and alpha, zero where the ray misses the yarn (the
// disk of `radius` swept along the tangent). Opacity from the length of
// yarn crossed; Lambertian shading of the fibre where the ray is halfway
// through the yarn: a helix about the axis, so at (x, y) it leans by the
// twist along the circle through it (Eq. 1's step between slices, taken
// per unit length); untwisted, it runs along the yarn. A thin cylinder
// under parallel light `localLight` shades with the sine of the angle
// between fibre and light.
vec4 slabColour(vec3 localEye, vec3 d, vec2 interval, float radius, float opacityPerVoxel, float twist,
                vec3 albedo, vec3 localLight) {
    float enter = interval.x, leave = interval.y;
    // ... cut with the infinite cylinder x^2 + y^2 < radius^2.
    float a = dot(d.xy, d.xy), b = dot(localEye.xy, d.xy);
    float c = dot(localEye.xy, localEye.xy) - radius * radius;
    if (a > 1e-12) {
        float disc = b * b - a * c;
        if (disc <= 0.0) return vec4(0.0);
        float s = sqrt(disc);
        enter = max(enter, (-b - s) / a);
        leave = min(leave, (-b + s) / a);
    } else if (c >= 0.0) {
        return vec4(0.0);
    }
    float crossed = leave - enter;
    if (crossed <= 0.0) return vec4(0.0);
    float alpha = 1.0 - exp(-opacityPerVoxel * crossed);
    vec2 p = (localEye + 0.5 * (enter + leave) * d).xy;
    vec3 fibre = normalize(vec3(-twist * p.y, twist * p.x, 1.0));
    float cosine = dot(fibre, localLight);
    vec3 shade = albedo * (0.25 + 0.75 * sqrt(max(0.0, 1.0 - cosine * cosine)));
    return vec4(shade * alpha, alpha);
}
