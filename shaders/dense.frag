// The paper's dense method (Appendix A): every sample on fibre is written
// straight into dense 3D textures, density as a max and the fibre direction as
// two 8-bit angles. The sample itself, and the voxels its slab column crosses,
// are computed exactly as append.frag does (global pixel index, slice plane,
// half-open square, level-0 texel, box filter in depth), so the baseline
// differs from the sparse backend only in how samples are stored.
//
// The imageLoad / imageStore pairs below are a read-modify-write without
// atomics, as in the paper: two fragments of the same voxel may interleave, a
// smaller density can overwrite a larger one, and theta/phi may come from a
// different sample than the density. That race is the baseline's nature (r8
// images have no atomics); it is measured, not fixed.

#include "common.glsl"

layout(binding = kCrossSectionUnit) uniform usampler2D uCrossSection; // R8UI, texel 255 = solid fibre
layout(binding = kDenseDensityImage, r8) uniform image3D uDensity;
layout(binding = kDenseThetaImage, r8) uniform writeonly image3D uTheta;
layout(binding = kDensePhiImage, r8) uniform writeonly image3D uPhi;

uniform float uRadius;        // yarn radius, voxel units
// CROSS_SECTION_DISK (a #define, 1 or 0): the uniform disk, coverage computed
// exactly; a program of its own, so that each keeps only the code it runs.
const bool kDisk = CROSS_SECTION_DISK != 0;
uniform float uSupport;       // textureSupport(): beyond it the texture reads 0
uniform int uSupersample;
uniform ivec3 uDims;          // grid size in voxels (the textures' size)

flat in int vAxis;
flat in ivec3 vAnchor;
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
    int a = vAxis;
    float S = float(uSupersample);
    // Axis first (axisFirst): x is the depth axis a, y and z the face's.
    vec3 center = axisFirst(vCenter, a), right = axisFirst(vRight, a), up = axisFirst(vUp, a);
    vec3 tangent = axisFirst(vTangent, a), curvature = axisFirst(vCurvature, a);
    ivec3 anchor = axisFirst(vAnchor, a), dims = axisFirst(uDims, a);
    // The viewport covers the whole grid from its origin: the pixel is global.
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    ivec2 fromAnchor = pixel - anchor.yz * uSupersample;
    float db = (float(fromAnchor.x) + 0.5) / S - center.y;
    float dc = (float(fromAnchor.y) + 0.5) / S - center.z;
    float det = tangent.x;
    float x = (db * up.z - dc * up.y) / det;
    float y = (right.y * dc - right.z * db) / det;

    ivec2 face = ivec2(pixel.x / uSupersample, pixel.y / uSupersample);
    if (face.x >= dims.y || face.y >= dims.z) return;

    float cellDensity[kCells], cellZ0[kCells], cellZ1[kCells], zMin, zMax;
    float cellSum = footprintCells(uCrossSection, kDisk, uSupport, S, uRadius, center, right, up, tangent, curvature,
                                   vDepthScale, x, y, cellDensity, cellZ0, cellZ1, zMin, zMax);
    if (!(cellSum > 0.0)) return;
    float density = cellSum / float(kCells);

    // Eq. 1 of the paper: where the fibre at (x, y) sits on the next slice.
    float cs = cos(vTwistStep), sn = sin(vTwistStep);
    vec3 dir = normalize((x * cs - y * sn - x) * vRight + (x * sn + y * cs - y) * vUp + vThickness * vTangent);

    float theta = acos(clamp(dir.z, -1.0, 1.0)) / kPi;
    float phi = (atan(dir.y, dir.x) + kPi) / (2.0 * kPi);

    // Racy max, as the paper (see the top of the file). Unlike the paper, the
    // angles are written only by a sample that is not below the stored
    // density, so where no race hits, orientation follows the densest sample
    // as the max reduction of the other backends does.
    for (float v = floor(zMin); v < zMax; v += 1.0) {
        if (!(layerShare(v, cellDensity, cellZ0, cellZ1) / (S * S * float(kCells)) >= kMinVoxelShare)) continue;
        int depth = int(v) + anchor.x;
        if (depth < 0 || depth >= dims.x) continue;
        ivec3 voxel = axisBack(ivec3(depth, face), a);
        float stored = imageLoad(uDensity, voxel).x;
        if (density < stored) continue;
        imageStore(uDensity, voxel, vec4(density));
        imageStore(uTheta, voxel, vec4(theta));
        imageStore(uPhi, voxel, vec4(phi));
    }
}
