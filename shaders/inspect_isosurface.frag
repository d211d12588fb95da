// Pseudo-isosurface ray casting through the brick atlas: each ray stops at
// the first point where the density, interpolated trilinearly between voxel
// centres, reaches the iso value; the surface there is shaded by the density
// gradient (central differences, one level voxel each way) as its normal.
// The march, its sample positions and its empty-space skipping are the ray
// caster's (inspect_raycast.frag); the crossing is refined by bisection
// between the last sample below the iso value and the first one above.
uniform mat4 inverseViewProjection;
uniform vec2 viewport;
uniform bool skipEmpty;          // entry and exit from pass 1, else the box
uniform bool startAtNearPlane;   // the eye may sit inside an occupied brick
layout(binding = kEntryExitUnit) uniform sampler2D entryExitTexture;
layout(binding = kIndirectionUnit) uniform usampler3D indirection;  // level brick -> atlas slot + 1, 0: empty
layout(binding = kDensityAtlasUnit) uniform sampler3D densityAtlas;
uniform ivec3 atlasSlots;        // slots along x, y (z follows)
uniform vec3 originVoxel;        // voxel of the level's corner
uniform float levelScale;        // voxels per level voxel
uniform ivec3 brickDims;         // the indirection grid
uniform vec3 boxMin, boxMax;     // voxel box of the level's bricks
uniform float step;              // in voxels
uniform float isoValue;          // the density the surface lies at
uniform vec3 lightDirection;     // unit, towards the light

layout(location = 0) out vec4 colour;
layout(location = 1) out float samples;

const vec3 kSurfaceColour = vec3(0.93, 0.84, 0.70);
const float kAmbient = 0.15;

// The density of level voxel v (0 in an empty brick or outside the grid).
float voxel(ivec3 v) {
    ivec3 brick = v >> 3;
    if (any(lessThan(brick, ivec3(0))) || any(greaterThanEqual(brick, brickDims))) return 0.0;
    uint slot = texelFetch(indirection, brick, 0).r;
    if (slot == 0u) return 0.0;
    int s = int(slot - 1u);
    ivec3 base = ivec3(s % atlasSlots.x, (s / atlasSlots.x) % atlasSlots.y, s / (atlasSlots.x * atlasSlots.y));
    return texelFetch(densityAtlas, base * 8 + (v & 7), 0).r;
}

// Whether the level brick holding voxel position p is occupied (and which it is).
bool occupied(vec3 p, out ivec3 brick) {
    brick = ivec3(floor((p - originVoxel) / levelScale)) >> 3;
    if (any(lessThan(brick, ivec3(0))) || any(greaterThanEqual(brick, brickDims))) return false;
    return texelFetch(indirection, brick, 0).r != 0u;
}

// Trilinear density at voxel position p, voxel values sitting at voxel centres.
float density(vec3 p) {
    vec3 q = (p - originVoxel) / levelScale - 0.5;
    ivec3 v = ivec3(floor(q));
    vec3 f = q - vec3(v);
    float c00 = mix(voxel(v), voxel(v + ivec3(1, 0, 0)), f.x);
    float c10 = mix(voxel(v + ivec3(0, 1, 0)), voxel(v + ivec3(1, 1, 0)), f.x);
    float c01 = mix(voxel(v + ivec3(0, 0, 1)), voxel(v + ivec3(1, 0, 1)), f.x);
    float c11 = mix(voxel(v + ivec3(0, 1, 1)), voxel(v + ivec3(1, 1, 1)), f.x);
    return mix(mix(c00, c10, f.y), mix(c01, c11, f.y), f.z);
}

void main() {
    vec2 ndc = 2.0 * gl_FragCoord.xy / viewport - 1.0;
    vec4 a = inverseViewProjection * vec4(ndc, -1.0, 1.0);
    vec4 b = inverseViewProjection * vec4(ndc, 1.0, 1.0);
    vec3 origin = a.xyz / a.w;
    vec3 dir = normalize(b.xyz / b.w - origin);
    float farT = length(b.xyz / b.w - origin);

    float t0, t1;
    if (skipEmpty) {
        vec2 e = texelFetch(entryExitTexture, ivec2(gl_FragCoord.xy), 0).rg;
        t0 = e.x;
        t1 = -e.y;
        if (t0 > t1) { colour = vec4(0.0); samples = 0.0; return; } // no proxy face here
        if (startAtNearPlane) t0 = 0.0;
    } else {
        vec3 inv = 1.0 / dir;
        vec3 ta = (boxMin - origin) * inv, tb = (boxMax - origin) * inv;
        vec3 lo = min(ta, tb), hi = max(ta, tb);
        t0 = max(max(lo.x, lo.y), lo.z);
        t1 = min(min(hi.x, hi.y), hi.z);
    }
    // Trilinear values reach half a level voxel beyond an occupied brick: the
    // span grows by that much so a surface at a brick's face is not cut off.
    t0 = max(t0 - levelScale, 0.0);
    t1 = min(t1 + levelScale, farT);

    float count = 0.0, previousT = -1.0;
    bool hit = false;
    float tHit = 0.0;
    for (float k = max(ceil(t0 / step - 0.5), 0.0);; k += 1.0) {
        float t = (k + 0.5) * step;
        if (t > t1) break;
        count += 1.0;
        vec3 p = origin + t * dir;
        ivec3 brick;
        if (!occupied(p, brick)) {
            // The trilinear density near an empty brick's face still sees its
            // occupied neighbour, so only a brick with no occupied neighbour
            // across any face is jumped over (image-order skipping).
            bool near = false;
            for (int axis = 0; axis < 3 && !near; ++axis)
                for (int side = -1; side <= 1; side += 2) {
                    ivec3 o = ivec3(0);
                    o[axis] = side;
                    ivec3 dummy;
                    if (occupied(p + vec3(o) * levelScale, dummy)) { near = true; break; }
                }
            if (!near) {
                if (skipEmpty) {
                    vec3 lo = originVoxel + vec3(brick * 8) * levelScale, hi = lo + 8.0 * levelScale;
                    vec3 d = mix(dir, vec3(1e-20), equal(dir, vec3(0.0))); // no 0/0
                    vec3 exits = (mix(lo, hi, greaterThan(d, vec3(0.0))) - origin) / d;
                    float tExit = min(min(exits.x, exits.y), exits.z);
                    // Stop a level voxel short of the exit: the next brick's
                    // surface may begin right at its face.
                    k = max(k, ceil((tExit - levelScale) / step - 0.5) - 1.0);
                }
                previousT = -1.0;
                continue;
            }
        }
        if (density(p) >= isoValue) {
            // Bisection between the last sample below and this one.
            float lo = previousT >= 0.0 ? previousT : max(t - step, t0), hi = t;
            for (int i = 0; i < 6; ++i) {
                float mid = 0.5 * (lo + hi);
                if (density(origin + mid * dir) >= isoValue) hi = mid; else lo = mid;
            }
            tHit = hi;
            hit = true;
            break;
        }
        previousT = t;
    }
    samples = count;
    if (!hit) { colour = vec4(0.0); return; }
    vec3 p = origin + tHit * dir;
    float e = levelScale;
    vec3 gradient = vec3(density(p + vec3(e, 0, 0)) - density(p - vec3(e, 0, 0)),
                         density(p + vec3(0, e, 0)) - density(p - vec3(0, e, 0)),
                         density(p + vec3(0, 0, e)) - density(p - vec3(0, 0, e)));
    // Density grows inwards: the outward normal is against the gradient.
    vec3 n = length(gradient) > 0.0 ? -normalize(gradient) : -dir;
    if (dot(n, dir) > 0.0) n = -n; // seen from inside (the eye in the volume): face the eye
    float diffuse = max(dot(n, lightDirection), 0.0);
    colour = vec4(kSurfaceColour * (kAmbient + (1.0 - kAmbient) * diffuse), 1.0);
}
