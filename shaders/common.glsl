// Shared by every yarnvox shader: buffer layouts and the sampling rule's
// helpers. src/gpu/gpu_layout.h holds the C++ side of each layout.

// Fixed-point scale of volume fractions (src/core/sampling.h: kFixedScale).
const float kFixedScale = 16777216.0;
const int kBrickVoxels = 512;

// One curve segment (96 bytes): control points in voxel units relative to
// the grid origin; p[0].w = twist rate (radians per voxel unit of length);
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

vec3 catmullRomSecondDerivative(vec3 p0, vec3 p1, vec3 p2, vec3 p3, float t) {
    return 0.5 * ((4.0 - 6.0 * t) * p0 + (-10.0 + 18.0 * t) * p1 + (8.0 - 18.0 * t) * p2 + (-2.0 + 6.0 * t) * p3);
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
