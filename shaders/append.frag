// Samples the cross-section at level 0 and appends one voxel fragment per
// sample on fibre. The interpolated position, not the window coordinate,
// picks the voxel, so the same pass serves any region.

layout(binding = 0) uniform usampler2D uCrossSection; // R8UI, texel 255 = solid fibre
layout(binding = 0, offset = 0) uniform atomic_uint uFragmentCount;
layout(std430, binding = 2) writeonly buffer Fragments { Fragment fragments[]; };

uniform uint uCapacity;       // fragments the list holds; the counter goes on past it
uniform float uRadius;        // yarn radius, voxel units
uniform ivec3 uRegionMin;
uniform ivec3 uRegionBricks;  // region size in bricks

flat in int vAxis;
flat in vec3 vRight;
flat in vec3 vUp;
flat in vec3 vTangent;
flat in float vThickness;
flat in float vTwistStep;
flat in float vWeightScale;
noperspective in vec2 vLocal;
noperspective in vec3 vVoxel;

void main() {
    ivec3 voxel = ivec3(floor(vVoxel)) - uRegionMin;
    if (any(lessThan(voxel, ivec3(0))) || any(greaterThanEqual(voxel, uRegionBricks * 8))) return;

    int size = textureSize(uCrossSection, 0).x;
    ivec2 texel = clamp(ivec2(floor((vLocal + 1.0) * 0.5 * float(size))), ivec2(0), ivec2(size - 1));
    uint value = texelFetch(uCrossSection, texel, 0).r;
    if (value == 0u) return;
    float density = float(value) / 255.0;

    // Eq. 1 of the paper: where the fibre at this point sits on the next slice.
    float radius = uRadius;
    float x = vLocal.x * radius, y = vLocal.y * radius;
    float cs = cos(vTwistStep), sn = sin(vTwistStep);
    vec3 dir = (x * cs - y * sn - x) * vRight + (x * sn + y * cs - y) * vUp + vThickness * vTangent;

    ivec3 brick = voxel >> 3;
    uint brickIndex = uint(brick.x + uRegionBricks.x * (brick.y + uRegionBricks.y * brick.z));
    ivec3 local = voxel & 7;
    uint key = (brickIndex << 9) | uint((local.x << 6) | (local.y << 3) | local.z);

    uint slot = atomicCounterIncrement(uFragmentCount);
    if (slot < uCapacity)
        fragments[slot] = Fragment(key, uint(round(density * vWeightScale * kFixedScale)), encodeAxis(normalize(dir)),
                                   floatBitsToUint(density));
}
