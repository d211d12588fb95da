// A slice placed on its curve segment: Catmull-Rom positions and frames
// (src/garment/catmull_rom.h, src/garment/slices.cpp), as slice_setup.comp
// runs it for every slice of a draw.

#include "layout.glsl"

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
