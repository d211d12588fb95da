// `inspect --render slices`: the fragment cuts its ray with the slab's
// piece of yarn (a disk of the yarn's radius swept along the thickness) and
// blends, premultiplied, with opacity from the length of yarn the ray
// crosses (slabs.glsl's slabColour). Drawn as a box, the fragment lies on
// one of the box's faces and the ray runs from the eye through it;
// fragments of back faces are dropped, so each slab counts once a pixel.
// Drawn as a point (SLAB_POINTS), the ray is the pixel's, from the inverse
// of the camera's matrix; pixels whose ray misses the slab are dropped.

#include "slabs.glsl"

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
    vec2 interval = slabBoxInterval(localEye, d, halfSize);
#ifdef SLAB_POINTS
    if (!(interval.x < interval.y)) discard; // the pixel's ray misses the box
#else
    if (tFragment - interval.x > interval.y - tFragment) discard; // a back face
#endif
    colour = slabColour(localEye, d, interval, halfSize.x, opacityPerVoxel, twist, albedo, localLight);
    if (colour.a <= 0.0) discard;
}
