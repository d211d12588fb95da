// Empty-space skipping, pass 1: each proxy face writes its distance along
// the pixel's ray as (t, -t); blending with GL_MIN keeps the nearest entry
// and the farthest exit (the dual-depth trick of the reference).
in vec3 worldPosition;
uniform mat4 inverseViewProjection;
uniform vec2 viewport;
layout(location = 0) out vec2 entryExit;

void main() {
    vec2 ndc = 2.0 * gl_FragCoord.xy / viewport - 1.0;
    vec4 a = inverseViewProjection * vec4(ndc, -1.0, 1.0);
    vec4 b = inverseViewProjection * vec4(ndc, 1.0, 1.0);
    vec3 origin = a.xyz / a.w;
    vec3 dir = normalize(b.xyz / b.w - origin);
    float t = dot(worldPosition - origin, dir);
    entryExit = vec2(t, -t);
}
