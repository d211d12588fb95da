// The slices render's slabs (inspect_slices.vert and .frag,
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
