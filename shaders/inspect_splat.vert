// One voxel of the brick atlas as a point sprite. Vertex i is voxel i % 512
// of the (i / 512)-th brick in back-to-front order; within a brick, voxels
// run plane by plane from the side away from the eye. Empty voxels are
// moved outside the clip volume.
layout(std430, binding = kBrickOrderBinding) readonly buffer BrickOrder {
    ivec4 bricks[]; // level brick (xyz) and atlas slot (w), farthest first
};
layout(binding = kDensityAtlasUnit) uniform sampler3D densityAtlas;
layout(binding = kTransferFunctionUnit) uniform sampler1D transferFunction;
uniform mat4 viewProjection;
uniform vec3 eye;
uniform ivec3 atlasSlots;
uniform vec3 originVoxel;
uniform float levelScale;
uniform ivec3 planeAxes;     // outermost (nearest the view direction) to innermost
uniform float sigma;         // kernel, in level voxels
uniform float pixelsPerUnit; // at clip w = 1
uniform float maxPointSize;

out vec4 splatColour;    // premultiplied, at the kernel's peak
out float edgeSigmas;    // sigmas from the centre to the sprite's edge

void main() {
    ivec4 b = bricks[gl_VertexID >> 9];
    int i = gl_VertexID & 511;
    ivec3 step3 = ivec3(i >> 6, (i >> 3) & 7, i & 7); // outer, middle, inner
    ivec3 local;
    local[planeAxes.x] = step3.x;
    local[planeAxes.y] = step3.y;
    local[planeAxes.z] = step3.z;
    vec3 brickCentre = originVoxel + (vec3(b.xyz) + 0.5) * 8.0 * levelScale;
    // Far side first: where the eye lies above the brick's centre on an axis, low indices are far.
    local = mix(7 - local, local, greaterThan(eye, brickCentre));
    ivec3 base = ivec3(b.w % atlasSlots.x, (b.w / atlasSlots.x) % atlasSlots.y, b.w / (atlasSlots.x * atlasSlots.y));
    float d = texelFetch(densityAtlas, base * 8 + local, 0).r;
    if (d <= 0.0) {
        gl_Position = vec4(0.0, 0.0, 2.0, 1.0); // beyond the far plane: clipped
        gl_PointSize = 1.0;
        splatColour = vec4(0.0);
        edgeSigmas = 3.0;
        return;
    }
    vec3 centre = originVoxel + (vec3(b.xyz * 8 + local) + 0.5) * levelScale;
    gl_Position = viewProjection * vec4(centre, 1.0);
    vec4 c = texture(transferFunction, clamp(d, 0.0, 1.0));
    // The voxel's opacity over its own length (opacity is given per voxel).
    float a = 1.0 - pow(1.0 - min(c.a, 0.9999), levelScale);
    splatColour = vec4(c.rgb * a, a);
    // The sprite spans three sigmas either side of the centre.
    float diameter = 6.0 * sigma * levelScale * pixelsPerUnit / max(gl_Position.w, 1e-6);
    gl_PointSize = clamp(diameter, 1.0, maxPointSize);
    edgeSigmas = 3.0 * gl_PointSize / diameter; // clamped sprites show more or less of the kernel
}
