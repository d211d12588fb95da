// Volumetric triangles, stage 2 (the appendix's geometry shader): each
// slice's square is split into two right triangles along its diagonal, and
// for each triangle a screen-space rectangle is emitted that holds every
// view ray passing within kCutoff standard deviations of it. The blurs get
// a floor of a third of a pixel at the slice's distance, as in the appendix.
layout(points) in;
layout(triangle_strip, max_vertices = 8) out;
in vec4 vCentreThickness[];
in vec3 vRight[], vUp[];

uniform mat4 viewProjection;
uniform vec3 eye;                // voxel coordinates
uniform float pixelAngle;        // a pixel's height at unit distance
uniform float blurVoxels;        // in-plane blur (standard deviation), voxels
uniform int maxDivisions;        // sample grid per triangle, at most this a side

flat out vec3 triCorner, triEdgeS, triEdgeT; // p = corner + s edgeS + t edgeT, s, t >= 0, s + t <= 1
flat out vec2 localCorner, localEdgeS, localEdgeT; // the same in slice-local units of the radius
flat out vec3 sliceNormal;
flat out vec3 blurThicknessDivisions; // sigma_b, sigma_t (voxels), divisions a side
flat out float slabThickness;

const float kCutoff = 3.0;

void emitBounds(vec3 a, vec3 b, vec3 c, float reach) {
    vec2 lo = vec2(1e30), hi = vec2(-1e30);
    vec3 corners[3] = vec3[3](a, b, c);
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 8; ++k) {
            vec3 o = vec3((k & 1) != 0 ? reach : -reach, (k & 2) != 0 ? reach : -reach, (k & 4) != 0 ? reach : -reach);
            vec4 clip = viewProjection * vec4(corners[i] + o, 1.0);
            if (clip.w <= 1e-6) { lo = vec2(-1.0); hi = vec2(1.0); i = 3; break; } // reaches behind the eye
            vec2 ndc = clip.xy / clip.w;
            lo = min(lo, ndc);
            hi = max(hi, ndc);
        }
    lo = max(lo, vec2(-1.0));
    hi = min(hi, vec2(1.0));
    if (any(greaterThanEqual(lo, hi))) return;
    gl_Position = vec4(lo.x, lo.y, 0.0, 1.0); EmitVertex();
    gl_Position = vec4(hi.x, lo.y, 0.0, 1.0); EmitVertex();
    gl_Position = vec4(lo.x, hi.y, 0.0, 1.0); EmitVertex();
    gl_Position = vec4(hi.x, hi.y, 0.0, 1.0); EmitVertex();
    EndPrimitive();
}

void main() {
    vec3 c = vCentreThickness[0].xyz, r = vRight[0], u = vUp[0];
    float thickness = vCentreThickness[0].w;
    float minBlur = pixelAngle * distance(eye, c) / 3.0;
    float side = 2.0 * max(length(r), length(u));
    // The sample grid's spacing never exceeds the blur: a coarse grid
    // widens the blur instead of showing its rows.
    float divisions = clamp(ceil(side / max(blurVoxels, minBlur)), 1.0, float(maxDivisions));
    float sigmaB = max(max(blurVoxels, minBlur), side / divisions);
    // A uniform slab of this thickness has standard deviation thickness / sqrt(12) across it.
    float sigmaT = max(thickness * 0.28867513, minBlur);
    float reach = kCutoff * max(sigmaB, sigmaT);
    sliceNormal = normalize(cross(r, u));
    blurThicknessDivisions = vec3(sigmaB, sigmaT, divisions);
    slabThickness = thickness;
    // Right angles at (+1, -1) and (-1, +1); both hypotenuses are the diagonal
    // from (-1, -1) to (+1, +1), whose samples each triangle weighs by half.
    for (int half_ = 0; half_ < 2; ++half_) {
        vec2 l0 = half_ == 0 ? vec2(1.0, -1.0) : vec2(-1.0, 1.0);
        vec2 l1 = vec2(-1.0, -1.0), l2 = vec2(1.0, 1.0);
        vec3 p0 = c + l0.x * r + l0.y * u, p1 = c + l1.x * r + l1.y * u, p2 = c + l2.x * r + l2.y * u;
        triCorner = p0;
        triEdgeS = p1 - p0;
        triEdgeT = p2 - p0;
        localCorner = l0;
        localEdgeS = l1 - l0;
        localEdgeT = l2 - l0;
        emitBounds(p0, p1, p2, reach);
    }
}
