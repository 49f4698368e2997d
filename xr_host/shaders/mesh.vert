#version 450
#extension GL_EXT_multiview : require
// Shaded model: one draw serves every view of a multiview render pass;
// gl_ViewIndex picks the eye's matrix.
layout(set = 0, binding = 0) uniform Views {
    mat4 view_proj[2];
    vec4 eye[2];
} views;
layout(push_constant) uniform Push {
    mat4 model;
    vec4 color;
} pc;
layout(location = 0) in vec3 in_pos;
layout(location = 1) in vec3 in_normal;
layout(location = 0) out vec3 v_normal;
layout(location = 1) out vec3 v_to_eye;
void main() {
    vec4 world = pc.model * vec4(in_pos, 1.0);
    // The normal matrix: a drag preview scaled along one axis keeps its
    // shading right (the model matrix is not always a similarity).
    v_normal = transpose(inverse(mat3(pc.model))) * in_normal;
    v_to_eye = views.eye[gl_ViewIndex].xyz - world.xyz;
    gl_Position = views.view_proj[gl_ViewIndex] * world;
}
