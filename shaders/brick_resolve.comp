// Resolve: accumulated brick slots -> final density and axis per voxel, as
// resolveBrick (src/core/bricks.cpp) does on the CPU, in double. Two passes:
//   COUNT_ONLY: each slot's active voxels, as (kept, count), for
//     brick_resolve_scan.comp to turn into (header index, first voxel);
//   else: each kept brick's header and its active voxels' values, written at
//     those places (layout: src/core/packed_bricks.h). Slots with no active
//     voxel write nothing: they are dropped here, not on the host.
// REDUCE_MAX: max words (density bits, axis code); else mean words (fixed-point
// fraction, structure tensor). OVERLAP_SUM: mean densities are not clamped.
// ALBEDO (mean only): three more words per voxel, and each active voxel's
// colour (R G B floats) written from uAlbedoBase, in the voxels' order.

#include "layout.glsl"

layout(local_size_x = 128) in;
// NVIDIA's compiler unrolls the Jacobi sweeps below in full: 213 and 278 ms
// to link this program on the H200 with no shader cache, 157 and 200 ms with
// loops kept (the same resolve time and the same bytes; a first run waits on
// it: bench/shader_variants.sh). Other drivers ignore the pragma.
#pragma optionNV(unroll none)

const uint kGroup = 128u;
const uint kPerThread = 4u; // voxel lid + k * kGroup, k < kPerThread
#ifdef REDUCE_MAX
const uint kWords = 2u;
#elif defined(ALBEDO)
const uint kWords = 10u;
#else
const uint kWords = 7u;
#endif

struct PackedBrickHeader {
    uvec2 key;
    uint activeMask[16];
    uint firstVoxel;
    uint activeCount;
    uint voxelsOverOne;
    uint unused;
    double densitySum;
    double rawDensitySum;
    double excessOverOne;
};

layout(std430, binding = kBrickWordsBinding) readonly buffer BrickWords { uint words[]; };
layout(std430, binding = kResolvePlacesBinding) buffer Places { uvec2 places[]; };
#ifndef COUNT_ONLY
// Region mode: slot -> region brick index (brick_scan.comp's slotBrick);
// else two words of brickKey per slot.
layout(std430, binding = kResolveKeysBinding) readonly buffer Keys { uint keyWords[]; };
// One buffer bound twice: headers from its start, voxels from uVoxelBase.
layout(std430, binding = kPackedHeadersBinding) writeonly buffer Headers { PackedBrickHeader headers[]; };
layout(std430, binding = kPackedVoxelsBinding) writeonly buffer Voxels { vec4 voxels[]; };
uniform bool uKeysFromRegion;
uniform ivec3 uBrickMin;      // the region's first brick
uniform ivec3 uRegionBricks;  // bricks along each axis of the region
uniform uint uVoxelBase;      // in vec4s
#ifdef ALBEDO
layout(std430, binding = kPackedAlbedoBinding) writeonly buffer Albedo { float albedo[]; };
uniform uint uAlbedoBase;     // in floats
#endif
#endif
uniform uint uBrickCount;

const double kScale = 16777216.0LF;                 // src/core/sampling.h: kFixedScale
const double kOverOne = 1.0LF + 1.0LF / 1024.0LF;   // src/core/bricks.h: 1 + kOverOneMargin

shared uint sMask[16];
#ifndef COUNT_ONLY
shared double sDensity[kGroup], sRaw[kGroup], sExcess[kGroup];
shared uint sOverOne[kGroup];
#endif

// Density of a voxel from its first word (resolveBrick's, bit for bit).
float voxelDensity(uint w, out double raw) {
#ifdef REDUCE_MAX
    float d = uintBitsToFloat(w);
    raw = double(d);
    return d;
#else
    raw = double(w) / kScale;
#ifdef OVERLAP_SUM
    return float(raw);
#else
    return float(min(raw, 1.0LF));
#endif
#endif
}

#ifndef COUNT_ONLY
// glm::normalize in double, in glm's order of operations.
dvec3 normalizeD(dvec3 v) {
    precise double len2 = (v.x * v.x + v.y * v.y) + v.z * v.z;
    precise double inv = 1.0LF / sqrt(len2);
    return dvec3(v.x * inv, v.y * inv, v.z * inv);
}

// src/core/sampling.h: canonicalAxis.
dvec3 canonicalAxisD(dvec3 v) {
    if (v.z < 0.0LF || (v.z == 0.0LF && (v.y < 0.0LF || (v.y == 0.0LF && v.x < 0.0LF)))) v = -v;
    return v;
}

#ifdef REDUCE_MAX
// src/core/sampling.h: decodeAxis.
dvec3 decodeAxisD(uint code) {
    precise double u = (double(code >> 16) / 65535.0LF) * 2.0LF - 1.0LF;
    precise double w = (double(code & 0xffffu) / 65535.0LF) * 2.0LF - 1.0LF;
    return normalizeD(dvec3(u, w, max(0.0LF, 1.0LF - abs(u) - abs(w))));
}
#else
// One Jacobi rotation zeroing a[p][q] (src/core/bricks.cpp: principalAxis's
// inner step).
void jacobiRotate(inout double a[3][3], inout double v[3][3], int p, int q) {
    if (a[p][q] == 0.0LF) return;
    precise double theta = (a[q][q] - a[p][p]) / (2.0LF * a[p][q]);
    precise double tt = (theta >= 0.0LF ? 1.0LF : -1.0LF) / (abs(theta) + sqrt(theta * theta + 1.0LF));
    precise double c = 1.0LF / sqrt(tt * tt + 1.0LF);
    precise double s = tt * c;
    for (int k = 0; k < 3; ++k) { // A <- A J
        precise double akp = a[k][p], akq = a[k][q];
        a[k][p] = c * akp - s * akq;
        a[k][q] = s * akp + c * akq;
    }
    for (int k = 0; k < 3; ++k) { // A <- J^T A
        precise double apk = a[p][k], aqk = a[q][k];
        a[p][k] = c * apk - s * aqk;
        a[q][k] = s * apk + c * aqk;
    }
    for (int k = 0; k < 3; ++k) { // V <- V J
        precise double vkp = v[k][p], vkq = v[k][q];
        v[k][p] = c * vkp - s * vkq;
        v[k][q] = s * vkp + c * vkq;
    }
}

// Principal eigenvector of the symmetric tensor (xx yy zz xy xz yz): the
// CPU's cyclic Jacobi sweeps (src/core/bricks.cpp: principalAxis), operation
// for operation; `precise` keeps multiply-adds unfused, as the CPU computes them.
dvec3 principalAxis(double t[6]) {
    precise double a[3][3] = double[3][3](double[3](t[0], t[3], t[4]), double[3](t[3], t[1], t[5]),
                                          double[3](t[4], t[5], t[2]));
    precise double v[3][3] = double[3][3](double[3](1.0LF, 0.0LF, 0.0LF), double[3](0.0LF, 1.0LF, 0.0LF),
                                          double[3](0.0LF, 0.0LF, 1.0LF));
    for (int sweep = 0; sweep < 12; ++sweep) {
        precise double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        precise double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if (off <= 1e-30LF * diag || off == 0.0LF) break;
        // The pivots (0,1), (0,2), (1,2) in a loop that stays one: a single
        // copy of the rotation's double divisions and square roots to
        // compile (an H100 with no shader cache links this program 20 to
        // 40 ms sooner; the resolve takes as long: bench/results/README.md).
        for (int r = 0; r < 3; ++r) jacobiRotate(a, v, r == 2 ? 1 : 0, r == 0 ? 1 : 2);
    }
    int best = 0;
    if (a[1][1] > a[best][best]) best = 1;
    if (a[2][2] > a[best][best]) best = 2;
    return normalizeD(dvec3(v[0][best], v[1][best], v[2][best]));
}
#endif

// Axis of an active voxel (zero where the voxel has no samples).
vec3 voxelAxis(uint base, uint voxel, uint w) {
    if (w == 0u) return vec3(0.0);
#ifdef REDUCE_MAX
    return vec3(decodeAxisD(words[base + uint(kBrickVoxels) + voxel]));
#else
    double t[6];
    for (uint i = 0u; i < 6u; ++i) t[i] = double(int(words[base + (1u + i) * uint(kBrickVoxels) + voxel]));
    return vec3(canonicalAxisD(principalAxis(t)));
#endif
}

uvec2 brickKeyOf(uint slot) {
    if (!uKeysFromRegion) return uvec2(keyWords[2u * slot], keyWords[2u * slot + 1u]);
    uint b = keyWords[slot];
    uint bx = uint(uRegionBricks.x), by = uint(uRegionBricks.y);
    uvec3 c = uvec3(uBrickMin) + uvec3(b % bx, (b / bx) % by, b / (bx * by));
    // brickKey: x << 42 | y << 21 | z, split into two 32-bit words.
    return uvec2(c.z | (c.y << 21), (c.y >> 11) | (c.x << 10));
}

// Rank of `voxel` among the brick's active voxels (offset order).
uint activeRank(uint voxel) {
    uint rank = bitCount(sMask[voxel >> 5] & ((1u << (voxel & 31u)) - 1u));
    for (uint i = 0u; i < (voxel >> 5); ++i) rank += bitCount(sMask[i]);
    return rank;
}
#endif

void main() {
    uint lid = gl_LocalInvocationID.x;
    // The slot loop is uniform over the work group, so the barriers are too.
    for (uint slot = gl_WorkGroupID.x; slot < uBrickCount; slot += gl_NumWorkGroups.x) {
        uint base = slot * kWords * uint(kBrickVoxels);
        if (lid < 16u) sMask[lid] = 0u;
        barrier();
        float density[kPerThread];
        double densitySum = 0.0LF, rawSum = 0.0LF, excess = 0.0LF;
        uint overOne = 0u;
        for (uint k = 0u; k < kPerThread; ++k) {
            uint voxel = lid + k * kGroup;
            double raw;
            density[k] = voxelDensity(words[base + voxel], raw);
            rawSum += raw;
#ifndef REDUCE_MAX
            if (raw > 1.0LF) {
                excess += raw - 1.0LF;
                if (raw > kOverOne) ++overOne;
            }
#endif
            if (density[k] > 0.0) {
                atomicOr(sMask[voxel >> 5], 1u << (voxel & 31u));
                densitySum += double(density[k]);
            }
        }
        barrier();
        uint count = 0u;
        for (uint i = 0u; i < 16u; ++i) count += bitCount(sMask[i]);
#ifdef COUNT_ONLY
        if (lid == 0u) places[slot] = uvec2(count > 0u ? 1u : 0u, count);
#else
        // Tally partials: a fixed tree, so the same input gives the same bits.
        sDensity[lid] = densitySum;
        sRaw[lid] = rawSum;
        sExcess[lid] = excess;
        sOverOne[lid] = overOne;
        barrier();
        for (uint stride = kGroup / 2u; stride > 0u; stride >>= 1) {
            if (lid < stride) {
                sDensity[lid] += sDensity[lid + stride];
                sRaw[lid] += sRaw[lid + stride];
                sExcess[lid] += sExcess[lid + stride];
                sOverOne[lid] += sOverOne[lid + stride];
            }
            barrier();
        }
        if (count > 0u) {
            uvec2 place = places[slot]; // (header index, first voxel)
            for (uint k = 0u; k < kPerThread; ++k) {
                if (!(density[k] > 0.0)) continue;
                uint voxel = lid + k * kGroup;
                vec3 axis = voxelAxis(base, voxel, words[base + voxel]);
                uint index = place.y + activeRank(voxel);
                voxels[uVoxelBase + index] = vec4(density[k], axis);
#ifdef ALBEDO
                // resolveBrick's colour: summed weighted colour over summed volume fraction.
                double weight = double(words[base + voxel]);
                for (uint i = 0u; i < 3u; ++i)
                    albedo[uAlbedoBase + 3u * index + i] =
                        float(min(1.0LF, double(words[base + (7u + i) * uint(kBrickVoxels) + voxel]) / weight));
#endif
            }
            if (lid < 16u) headers[place.x].activeMask[lid] = sMask[lid];
            if (lid == 0u) {
                headers[place.x].key = brickKeyOf(slot);
                headers[place.x].firstVoxel = place.y;
                headers[place.x].activeCount = count;
                headers[place.x].voxelsOverOne = sOverOne[0];
                headers[place.x].unused = 0u;
                headers[place.x].densitySum = sDensity[0];
                headers[place.x].rawDensitySum = sRaw[0];
                headers[place.x].excessOverOne = sExcess[0];
            }
        }
#endif
        barrier(); // sMask and the sums are reused by the next slot
    }
}
