// Ray marching through the brick atlas: front-to-back compositing with a 1D
// transfer function (RAYCAST), maximum intensity projection (MIP), or
// orientation as colour (ORIENTATION: |axis| as RGB, opacity from the
// transfer function). Voxels are sampled nearest, as stored: the picture
// shows the voxels there are. Samples lie at t = (k + 1/2) * step along each
// ray whatever the ray's entry, so skipping empty space changes which samples
// are taken but not their values. Skipping is both object order (the
// proxy's entry and exit) and image order (a jump over each empty brick the
// ray crosses between them); a sample is one step of the march.
uniform mat4 inverseViewProjection;
uniform vec2 viewport;
uniform bool skipEmpty;          // entry and exit from pass 1, else the box
uniform bool startAtNearPlane;   // the eye may sit inside an occupied brick
layout(binding = kEntryExitUnit) uniform sampler2D entryExitTexture;
layout(binding = kIndirectionUnit) uniform usampler3D indirection;  // level brick -> atlas slot + 1, 0: empty
layout(binding = kDensityAtlasUnit) uniform sampler3D densityAtlas;
layout(binding = kOrientationAtlasUnit) uniform sampler3D orientationAtlas;
layout(binding = kTransferFunctionUnit) uniform sampler1D transferFunction;
uniform ivec3 atlasSlots;        // slots along x, y (z follows)
uniform vec3 originVoxel;        // voxel of the level's corner
uniform float levelScale;        // voxels per level voxel
uniform ivec3 brickDims;         // the indirection grid
uniform vec3 boxMin, boxMax;     // voxel box of the level's bricks
uniform float step;              // in voxels
uniform float densityScale;      // density to transfer function coordinate

layout(location = 0) out vec4 colour;
layout(location = 1) out float samples;

// The atlas texel of a voxel position; false when its brick is empty (then
// `brick` is the level brick the position lies in).
bool lookup(vec3 p, out ivec3 texel, out ivec3 brick) {
    vec3 q = (p - originVoxel) / levelScale;
    ivec3 v = ivec3(floor(q));
    brick = v >> 3;
    if (any(lessThan(brick, ivec3(0))) || any(greaterThanEqual(brick, brickDims))) return false;
    uint slot = texelFetch(indirection, brick, 0).r;
    if (slot == 0u) return false;
    int s = int(slot - 1u);
    ivec3 base = ivec3(s % atlasSlots.x, (s / atlasSlots.x) % atlasSlots.y, s / (atlasSlots.x * atlasSlots.y));
    texel = base * 8 + (v & 7);
    return true;
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
    t0 = max(t0, 0.0);
    t1 = min(t1, farT);

    vec3 rgb = vec3(0.0);
    float alpha = 0.0, highest = 0.0;
    float count = 0.0;
    for (float k = max(ceil(t0 / step - 0.5), 0.0);; k += 1.0) {
        float t = (k + 0.5) * step;
        if (t > t1) break;
        count += 1.0;
        ivec3 texel, brick;
        if (!lookup(origin + t * dir, texel, brick)) {
            // Image-order skipping inside the proxy's span: the next sample
            // is the first one past this empty brick.
            if (skipEmpty) {
                vec3 lo = originVoxel + vec3(brick * 8) * levelScale, hi = lo + 8.0 * levelScale;
                vec3 d = mix(dir, vec3(1e-20), equal(dir, vec3(0.0))); // no 0/0
                vec3 exits = (mix(lo, hi, greaterThan(d, vec3(0.0))) - origin) / d;
                float tExit = min(min(exits.x, exits.y), exits.z);
                k = max(k, ceil(tExit / step - 0.5) - 1.0);
            }
            continue;
        }
        float d = texelFetch(densityAtlas, texel, 0).r;
#if defined(MIP)
        highest = max(highest, d);
#else
        if (d <= 0.0) continue;
        vec4 c = texture(transferFunction, clamp(d * densityScale, 0.0, 1.0));
        // Opacity is given per voxel of length: correct it for the step.
        float a = 1.0 - pow(1.0 - min(c.a, 0.9999), step);
#if defined(ORIENTATION)
        c.rgb = texelFetch(orientationAtlas, texel, 0).rgb;
#endif
        rgb += (1.0 - alpha) * a * c.rgb;
        alpha += (1.0 - alpha) * a;
        if (alpha > 0.995) break; // early ray termination
#endif
    }
#if defined(MIP)
    colour = vec4(vec3(clamp(highest * densityScale, 0.0, 1.0)), 1.0);
#else
    colour = vec4(rgb, alpha);
#endif
    samples = count;
}
