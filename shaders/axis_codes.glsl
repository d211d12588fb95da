// A fibre axis as a 32-bit code, both ways (src/core/sampling.h).

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
