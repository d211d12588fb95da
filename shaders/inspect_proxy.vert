// Empty-space skipping, pass 1 (object order): the faces of occupied bricks
// that border empty ones, in voxel coordinates.
layout(location = 0) in vec3 position;
uniform mat4 viewProjection;
out vec3 worldPosition;

void main() {
    worldPosition = position;
    gl_Position = viewProjection * vec4(position, 1.0);
}
