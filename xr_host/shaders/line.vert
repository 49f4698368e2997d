#version 450
#extension GL_EXT_multiview : require
// Lines (curves, spines, sections, the ray): world-space positions with a
// per-vertex color.
layout(set = 0, binding = 0) uniform Views {
    mat4 view_proj[2];
    vec4 eye[2];
} views;
layout(push_constant) uniform Push {
    mat4 model;
    vec4 color;
} pc;
layout(location = 0) in vec3 in_pos;
layout(location = 1) in vec3 in_color;
layout(location = 0) out vec3 v_color;
void main() {
    v_color = in_color;
    gl_Position = views.view_proj[gl_ViewIndex] * (pc.model * vec4(in_pos, 1.0));
}
