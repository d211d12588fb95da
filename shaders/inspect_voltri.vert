// Volumetric triangles, stage 1: one point per slice, in voxel coordinates.
// The slice is the square centre +- right +- up (right and up already
// scaled by the yarn radius); it stands for a slab `thickness` long.
layout(location = 0) in vec4 centreThickness;
layout(location = 1) in vec3 right;
layout(location = 2) in vec3 up;
out vec4 vCentreThickness;
out vec3 vRight, vUp;

void main() {
    vCentreThickness = centreThickness;
    vRight = right;
    vUp = up;
}
