// Append microbenchmark (bench/append_micro.cpp): instance i is a square of
// uSide x uSide pixels at a position spread over the viewport, so that
// neighbouring instances overlap as slices of a yarn do.
uniform float uSide;     // pixels
uniform vec2 uViewport;  // pixels
uniform int uPerRow;     // instances per row

void main() {
    vec2 corner = vec2((gl_VertexID & 1) != 0 ? 1.0 : 0.0, (gl_VertexID & 2) != 0 ? 1.0 : 0.0);
    vec2 origin = vec2(float(gl_InstanceID % uPerRow), float((gl_InstanceID / uPerRow) % uPerRow)) *
                  ((uViewport - uSide) / float(uPerRow));
    gl_Position = vec4((origin + corner * uSide) / uViewport * 2.0 - 1.0, 0.0, 1.0);
}
