#version 450 core
// Vertex stage of the PBR pass: world-space position, normal and tangent,
// and the clip positions of this and the previous pose (motion vectors).
// Shading reads the position, normal and tangent placed by u_shade_model
// (u_model, or the previous pose's model when shading with its setup).
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_tangent;
layout(location = 3) in vec2 a_uv0;
layout(location = 4) in vec2 a_uv1;
layout(location = 5) in vec4 a_color;

uniform mat4 u_model;
uniform mat4 u_view;
uniform mat4 u_viewproj;
uniform mat4 u_prev_mvp;
uniform mat3 u_normal_mat;   // of u_shade_model
uniform mat4 u_shade_model;

out vec3 v_world;
out vec3 v_normal;
out vec4 v_tangent;
out vec2 v_uv0;
out vec2 v_uv1;
out vec4 v_color;
out vec4 v_clip;
out vec4 v_prev_clip;
out float v_depth;

void main() {
  vec4 w = u_model * vec4(a_pos, 1.0);
  v_world = (u_shade_model * vec4(a_pos, 1.0)).xyz;
  v_normal = u_normal_mat * a_normal;
  v_tangent = vec4(mat3(u_shade_model) * a_tangent.xyz, a_tangent.w);
  v_uv0 = a_uv0;
  v_uv1 = a_uv1;
  v_color = a_color;
  v_clip = u_viewproj * w;
  v_prev_clip = u_prev_mvp * vec4(a_pos, 1.0);
  v_depth = -(u_view * w).z;
  gl_Position = v_clip;
}
