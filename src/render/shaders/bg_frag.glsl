#version 450 core
// The environment seen behind the object: the view ray through each pixel.
in vec2 v_ndc;
layout(location = 0) out vec4 o_color;
uniform mat4 u_inv_viewproj;
uniform vec3 u_eye;
uniform sampler2D u_bg;
uniform mat3 u_env_rot;
uniform float u_env_intensity;
uniform float u_exposure;
const float PI = 3.14159265358979;
void main() {
  vec4 p = u_inv_viewproj * vec4(v_ndc, 1.0, 1.0);
  vec3 d = normalize(u_env_rot * (p.xyz / p.w - u_eye));
  vec2 uv = vec2(atan(d.x, -d.z) / (2.0 * PI) + 0.5, acos(clamp(d.y, -1.0, 1.0)) / PI);
  o_color = vec4(textureLod(u_bg, uv, 0.0).rgb * u_env_intensity * u_exposure, 0.0);
}
