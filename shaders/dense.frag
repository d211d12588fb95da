// The paper's dense method (Appendix A): every sample on fibre is written
// straight into dense 3D textures, into the one voxel that holds it (no split
// of the slab in depth: the paper's rule, kept as the baseline), density as a max and the fibre direction as
// two 8-bit angles. The sample itself is computed exactly as append.frag does
// (global pixel index, slice plane, half-open square, level-0 texel), so the
// baseline differs from the sparse backend only in how samples are stored.
//
// The imageLoad / imageStore pairs below are a read-modify-write without
// atomics, as in the paper: two fragments of the same voxel may interleave, a
// smaller density can overwrite a larger one, and theta/phi may come from a
// different sample than the density. That race is the baseline's nature (r8
// images have no atomics); it is measured, not fixed.

layout(binding = 0) uniform usampler2D uCrossSection; // R8UI, texel 255 = solid fibre
layout(binding = 0, r8) uniform image3D uDensity;
layout(binding = 1, r8) uniform writeonly image3D uTheta;
layout(binding = 2, r8) uniform writeonly image3D uPhi;

uniform float uRadius;        // yarn radius, voxel units
uniform int uSupersample;
uniform ivec3 uDims;          // grid size in voxels (the textures' size)

flat in int vAxis;
flat in vec3 vCenter;
flat in vec3 vRight;
flat in vec3 vUp;
flat in vec3 vTangent;
flat in vec3 vCurvature;
flat in float vThickness;
flat in float vTwistStep;
flat in float vDepthScale;

const float kPi = 3.14159265358979323846;

void main() {
    int a = vAxis, b = (a + 1) % 3, c = (a + 2) % 3;
    float S = float(uSupersample);
    // The viewport covers the whole grid from its origin: the pixel is global.
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    float db = (float(pixel.x) + 0.5) / S - vCenter[b];
    float dc = (float(pixel.y) + 0.5) / S - vCenter[c];
    float det = vTangent[a];
    float x = (db * vUp[c] - dc * vUp[b]) / det;
    float y = (vRight[b] * dc - vRight[c] * db) / det;
    if (x < -uRadius || x >= uRadius || y < -uRadius || y >= uRadius) return;

    ivec3 voxel;
    voxel[a] = int(floor(vCenter[a] + x * vRight[a] + y * vUp[a]));
    voxel[b] = pixel.x / uSupersample;
    voxel[c] = pixel.y / uSupersample;
    if (any(lessThan(voxel, ivec3(0))) || any(greaterThanEqual(voxel, uDims))) return;

    int size = textureSize(uCrossSection, 0).x;
    ivec2 texel = clamp(ivec2(floor((vec2(x, y) / uRadius + 1.0) * 0.5 * float(size))), ivec2(0), ivec2(size - 1));
    uint value = texelFetch(uCrossSection, texel, 0).r;
    if (value == 0u) return;
    // value / 255 stored as unorm8 gives back exactly `value`.
    float density = float(value) / 255.0;

    // Eq. 1 of the paper: where the fibre at (x, y) sits on the next slice.
    float cs = cos(vTwistStep), sn = sin(vTwistStep);
    vec3 dir = normalize((x * cs - y * sn - x) * vRight + (x * sn + y * cs - y) * vUp + vThickness * vTangent);

    // Racy max, as the paper (see the top of the file). Unlike the paper, the
    // angles are written only by a sample that is not below the stored
    // density, so where no race hits, orientation follows the densest sample
    // as the max reduction of the other backends does.
    float stored = imageLoad(uDensity, voxel).x;
    if (density < stored) return;
    imageStore(uDensity, voxel, vec4(density));
    float theta = acos(clamp(dir.z, -1.0, 1.0)) / kPi;
    float phi = (atan(dir.y, dir.x) + kPi) / (2.0 * kPi);
    imageStore(uTheta, voxel, vec4(theta));
    imageStore(uPhi, voxel, vec4(phi));
}
