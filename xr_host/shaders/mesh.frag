#version 450
// Headlight plus a fixed key light; back faces get a distinct tint so
// inside-out or open geometry is visible at a glance. Back faces are told
// by the triangle's winding (gl_FrontFacing), not by the interpolated
// normal: a smooth normal turns away from the eye just inside a
// silhouette, which tinted the rims of closed models.
layout(push_constant) uniform Push {
    mat4 model;
    vec4 color;
} pc;
layout(location = 0) in vec3 v_normal;
layout(location = 1) in vec3 v_to_eye;
layout(location = 0) out vec4 out_color;
void main() {
    vec3 n = normalize(v_normal);
    vec3 e = normalize(v_to_eye);
    float facing = dot(n, e);
    vec3 base = pc.color.rgb;
    if (!gl_FrontFacing) {
        base = vec3(0.8, 0.15, 0.15);
    }
    if (facing < 0.0) {
        n = -n;
    }
    vec3 key = normalize(vec3(0.3, 0.5, 0.8));
    float head = max(dot(n, e), 0.0);
    float keyd = max(dot(n, key), 0.0);
    vec3 h = normalize(e + key);
    float spec = pow(max(dot(n, h), 0.0), 32.0);
    vec3 c = base * (0.12 + 0.55 * head + 0.35 * keyd) + vec3(0.15 * spec);
    out_color = vec4(c, pc.color.a);
}
