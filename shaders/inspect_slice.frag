// One slice of texture slicing or half-angle slicing: the atlas's voxel under
// the fragment, sampled nearest through the indirection texture as the ray
// caster samples it, coloured by the transfer function. Its opacity is given
// per voxel of length, so it is corrected for the path between two slices
// along the ray (from the eye, or along the light for LIGHT_PASS). Colour is
// premultiplied by opacity for the blending the renderer sets.
//  HALF_ANGLE: the light reaching the voxel is what the light buffer (opacity
//  between the light and this slice) lets through, plus an ambient share.
//  LIGHT_PASS: only the opacity, for the light buffer.
in vec3 voxelPosition;
layout(binding = kIndirectionUnit) uniform usampler3D indirection;  // level brick -> atlas slot + 1, 0: empty
layout(binding = kDensityAtlasUnit) uniform sampler3D densityAtlas;
layout(binding = kTransferFunctionUnit) uniform sampler1D transferFunction;
layout(binding = kLightBufferUnit) uniform sampler2D lightBuffer;
uniform ivec3 atlasSlots;        // slots along x, y (z follows)
uniform vec3 originVoxel;        // voxel of the level's corner
uniform float levelScale;        // voxels per level voxel
uniform ivec3 brickDims;         // the indirection grid
uniform vec3 sliceNormal;        // unit, perpendicular to every slice
uniform float spacing;           // between slices, in voxels
uniform bool rayFromEye;         // the path runs from `eye`, else along `lightTravel`
uniform vec3 eye;
uniform vec3 lightTravel;        // unit, the direction the light travels
uniform mat4 lightViewProjection;
uniform float ambient;

layout(location = 0) out vec4 colour;

// The density at a voxel position; false where its brick is empty (as
// inspect_raycast.frag's lookup).
bool density(vec3 p, out float d) {
    ivec3 v = ivec3(floor((p - originVoxel) / levelScale));
    ivec3 brick = v >> 3;
    if (any(lessThan(brick, ivec3(0))) || any(greaterThanEqual(brick, brickDims))) return false;
    uint slot = texelFetch(indirection, brick, 0).r;
    if (slot == 0u) return false;
    int s = int(slot - 1u);
    ivec3 base = ivec3(s % atlasSlots.x, (s / atlasSlots.x) % atlasSlots.y, s / (atlasSlots.x * atlasSlots.y));
    d = texelFetch(densityAtlas, base * 8 + (v & 7), 0).r;
    return true;
}

void main() {
    float d;
    if (!density(voxelPosition, d) || d <= 0.0) discard;
    vec4 c = texture(transferFunction, clamp(d, 0.0, 1.0));
    vec3 ray = rayFromEye ? normalize(voxelPosition - eye) : lightTravel;
    // Grazing rays see at most a few slices' worth of path per slice.
    float path = spacing / max(abs(dot(ray, sliceNormal)), 0.25);
    float a = 1.0 - pow(1.0 - min(c.a, 0.9999), path);
#if defined(LIGHT_PASS)
    colour = vec4(0.0, 0.0, 0.0, a);
#else
#if defined(HALF_ANGLE)
    vec4 l = lightViewProjection * vec4(voxelPosition, 1.0);
    float shadow = texture(lightBuffer, 0.5 * l.xy / l.w + 0.5).a;
    c.rgb *= ambient + (1.0 - ambient) * (1.0 - clamp(shadow, 0.0, 1.0));
#endif
    colour = vec4(c.rgb * a, a);
#endif
}
