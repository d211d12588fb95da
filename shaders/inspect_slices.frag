// `inspect --render slices`: the fragment cuts its ray with the slab's
// piece of yarn (a disk of the yarn's radius swept along the thickness) and
// blends, premultiplied, with opacity from the length of yarn the ray
// crosses. Drawn as a box, the fragment lies on one of the box's faces and
// the ray runs from the eye through it; fragments of back faces are
// dropped, so each slab counts once a pixel. Drawn as a point
// (SLAB_POINTS), the ray is the pixel's, from the inverse of the camera's
// matrix; pixels whose ray misses the slab are dropped.
#ifdef SLAB_POINTS
flat in mat3 slabFrame; // columns: right, up, tangent
uniform mat4 inverseViewProjection;
uniform vec2 viewportPixels;
#else
in vec3 localPosition;
#endif
flat in vec3 localEye;
flat in vec3 halfSize;
flat in vec3 localLight;
uniform float opacityPerVoxel; // extinction along the ray, per voxel of yarn crossed
uniform float twist;           // radians per voxel of yarn the fibres turn by
uniform vec3 albedo;
layout(location = 0) out vec4 colour;

void main() {
#ifdef SLAB_POINTS
    vec2 ndc = gl_FragCoord.xy / viewportPixels * 2.0 - 1.0;
    vec4 near = inverseViewProjection * vec4(ndc, -1.0, 1.0), far = inverseViewProjection * vec4(ndc, 1.0, 1.0);
    vec3 d = normalize(transpose(slabFrame) * (far.xyz / far.w - near.xyz / near.w));
#else
    vec3 toFragment = localPosition - localEye;
    float tFragment = length(toFragment);
    vec3 d = toFragment / tFragment;
#endif
    // The ray's interval in the box (slab method; IEEE infinities where d has a zero).
    vec3 inv = 1.0 / d;
    vec3 t1 = (-halfSize - localEye) * inv, t2 = (halfSize - localEye) * inv;
    vec3 lo = min(t1, t2), hi = max(t1, t2);
    float enter = max(max(lo.x, lo.y), lo.z), leave = min(min(hi.x, hi.y), hi.z);
#ifdef SLAB_POINTS
    if (!(enter < leave)) discard; // the pixel's ray misses the box
#else
    if (tFragment - enter > leave - tFragment) discard; // a back face
#endif
    // ... cut with the infinite cylinder x^2 + y^2 < radius^2.
    float a = dot(d.xy, d.xy), b = dot(localEye.xy, d.xy);
    float c = dot(localEye.xy, localEye.xy) - halfSize.x * halfSize.x;
    if (a > 1e-12) {
        float disc = b * b - a * c;
        if (disc <= 0.0) discard;
        float s = sqrt(disc);
        enter = max(enter, (-b - s) / a);
        leave = min(leave, (-b + s) / a);
    } else if (c >= 0.0) {
        discard;
    }
    float crossed = leave - enter;
    if (crossed <= 0.0) discard;
    float alpha = 1.0 - exp(-opacityPerVoxel * crossed);
    // The fibre where the ray is halfway through the yarn: a helix about the
    // axis, so at (x, y) it leans by the twist along the circle through it
    // (Eq. 1's step between slices, taken per unit length); untwisted, it
    // runs along the yarn. Lambertian shading of a thin cylinder under
    // parallel light: the sine of the angle between fibre and light.
    vec2 p = (localEye + 0.5 * (enter + leave) * d).xy;
    vec3 fibre = normalize(vec3(-twist * p.y, twist * p.x, 1.0));
    float cosine = dot(fibre, localLight);
    vec3 shade = albedo * (0.25 + 0.75 * sqrt(max(0.0, 1.0 - cosine * cosine)));
    colour = vec4(shade * alpha, alpha);
}
