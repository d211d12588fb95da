// Slice polygons in voxel coordinates, seen by the eye or by the light.
layout(location = 0) in vec3 position;
uniform mat4 viewProjection;
out vec3 voxelPosition;

void main() {
    voxelPosition = position;
    gl_Position = viewProjection * vec4(position, 1.0);
}
