// The sampling rule's helpers: a slice's footprint on its projection face,
// the disk and texture cross-sections, and the cells a sample's volume is
// measured in (src/core/footprint.h, src/core/sampling.h).

#include "layout.glsl"

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
