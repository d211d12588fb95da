// A Gaussian footprint: the voxel's premultiplied colour weighted by
// exp(-r^2 / 2 sigma^2), cut at three sigmas, blended "over".
in vec4 splatColour;
in float edgeSigmas;
layout(location = 0) out vec4 colour;

void main() {
    float r = length(2.0 * gl_PointCoord - 1.0) * edgeSigmas; // in sigmas
    if (r > 3.0) discard;
    colour = splatColour * exp(-0.5 * r * r);
}
