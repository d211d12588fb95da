// Volumetric triangles, stage 3 (the appendix's fragment shader): the
// absorbance along this pixel's view ray of one blurred triangle. The
// triangle is sampled on a regular grid; each sample carries the fibre mass
// of its cell (density 1 inside the yarn's disk, times the slab's
// thickness, times the cell's area), spread as a Gaussian of deviation
// sigma_b in the slice's plane and sigma_t across it, and the ray's integral
// through that Gaussian is closed form (the appendix's eq. 18). Absorbances
// add up (blending), so triangles are drawn in any order.
uniform mat4 inverseViewProjection;
uniform vec2 viewport;

flat in vec3 triCorner, triEdgeS, triEdgeT;
flat in vec2 localCorner, localEdgeS, localEdgeT;
flat in vec3 sliceNormal;
flat in vec3 blurThicknessDivisions;
flat in float slabThickness;

layout(location = 0) out float absorbance;

const float kPi = 3.14159265;

// x scaled by 1 / sigma_b in the slice's plane and 1 / sigma_t across it.
vec3 scaled(vec3 x, float sigmaB, float sigmaT) {
    float across = dot(x, sliceNormal);
    return (x - across * sliceNormal) / sigmaB + (across / sigmaT) * sliceNormal;
}

void main() {
    vec2 ndc = 2.0 * gl_FragCoord.xy / viewport - 1.0;
    vec4 a = inverseViewProjection * vec4(ndc, -1.0, 1.0);
    vec4 b = inverseViewProjection * vec4(ndc, 1.0, 1.0);
    vec3 origin = a.xyz / a.w;
    vec3 dir = normalize(b.xyz / b.w - origin);

    float sigmaB = blurThicknessDivisions.x, sigmaT = blurThicknessDivisions.y;
    int n = int(blurThicknessDivisions.z);
    vec3 v = scaled(dir, sigmaB, sigmaT);
    float vv = dot(v, v);
    float cellArea = length(cross(triEdgeS, triEdgeT)) / float(n * n); // twice the triangle's area over n^2 cells
    float norm = slabThickness * cellArea / (2.0 * kPi * sigmaB * sigmaB * sigmaT * sqrt(vv));
    float sum = 0.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n - i; ++j) {
            // Cell centres with s + t < 1; those on the hypotenuse count half.
            float s = (float(i) + 0.5) / float(n), t = (float(j) + 0.5) / float(n);
            float weight = i + j == n - 1 ? 0.5 : 1.0;
            vec2 l = localCorner + s * localEdgeS + t * localEdgeT;
            if (dot(l, l) > 1.0) continue; // outside the yarn's disk
            vec3 w = scaled(origin - (triCorner + s * triEdgeS + t * triEdgeT), sigmaB, sigmaT);
            float vw = dot(v, w);
            sum += weight * exp(-0.5 * (dot(w, w) - vw * vw / vv));
        }
    absorbance = sum * norm;
}
