#version 450 core
// Fragment stage of the PBR pass: glTF 2.0 metallic-roughness shading with
// Cook–Torrance (GGX distribution, separable Smith masking-shadowing, Schlick
// Fresnel), normal / occlusion / emissive maps, image-based lighting (SH
// irradiance + prefiltered specular with the split-sum table) and punctual
// lights. Also writes depth, motion and the mip level sampled per map.
in vec3 v_world;
in vec3 v_normal;
in vec4 v_tangent;
in vec2 v_uv0;
in vec2 v_uv1;
in vec4 v_color;
in vec4 v_clip;
in vec4 v_prev_clip;
in float v_depth;

layout(location = 0) out vec4 o_color;  // linear RGB × exposure, coverage
layout(location = 1) out vec4 o_aux;    // depth, motion x, motion y (pixels), 1
layout(location = 2) out vec4 o_mip0;   // mip level: baseColor, metallicRoughness, normal, occlusion
layout(location = 3) out vec4 o_mip1;   // mip level: emissive; material index

const float PI = 3.14159265358979;

// slots: 0 baseColor, 1 metallicRoughness, 2 normal, 3 occlusion, 4 emissive
uniform sampler2D u_map0;
uniform sampler2D u_map1;
uniform sampler2D u_map2;
uniform sampler2D u_map3;
uniform sampler2D u_map4;
uniform int u_has[5];
uniform int u_uvset[5];
uniform vec3 u_uvxf[10];  // per map, KHR_texture_transform: u' = dot(row 0, (u, v, 1)), v' = dot(row 1, ...)
uniform vec2 u_size[5];
uniform float u_levels[5];
uniform float u_max_aniso;
uniform float u_material;

uniform vec4 u_base_color;
uniform float u_metallic;
uniform float u_roughness;
uniform float u_normal_scale;
uniform float u_occlusion_strength;
uniform vec3 u_emissive;
uniform int u_alpha_mode;  // 0 opaque, 1 mask, 2 blend
uniform float u_alpha_cutoff;

uniform vec3 u_eye;
uniform vec2 u_viewport;
uniform float u_exposure;

uniform int u_nlights;
uniform int u_ltype[8];     // 0 directional, 1 point, 2 spot
uniform vec3 u_lpos[8];
uniform vec3 u_ldir[8];     // direction the light travels
uniform vec3 u_lcolor[8];   // colour × intensity
uniform float u_lrange[8];
uniform vec2 u_lcone[8];    // cos(inner), cos(outer)

uniform sampler2D u_env;    // equirectangular, mip level L = roughness L / (levels − 1)
uniform float u_env_levels;
uniform sampler2D u_brdf;   // split-sum scale, bias over (N·V, roughness)
uniform vec3 u_sh[9];
uniform float u_env_intensity;
uniform mat3 u_env_rot;

vec2 equirect_uv(vec3 d) {
  return vec2(atan(d.x, -d.z) / (2.0 * PI) + 0.5, acos(clamp(d.y, -1.0, 1.0)) / PI);
}

vec3 sh_irradiance(vec3 d) {
  return max(u_sh[0] * 0.282095 + u_sh[1] * (0.488603 * d.y) + u_sh[2] * (0.488603 * d.z) +
             u_sh[3] * (0.488603 * d.x) + u_sh[4] * (1.092548 * d.x * d.y) +
             u_sh[5] * (1.092548 * d.y * d.z) + u_sh[6] * (0.315392 * (3.0 * d.z * d.z - 1.0)) +
             u_sh[7] * (1.092548 * d.x * d.z) + u_sh[8] * (0.546274 * (d.x * d.x - d.y * d.y)),
             vec3(0.0));
}

// The mip level anisotropic filtering samples (EXT_texture_filter_anisotropic's
// reference): the footprint's longer axis divided by the number of probes.
float mip_level(vec2 uv, vec2 size, float levels) {
  vec2 dx = dFdx(uv) * size, dy = dFdy(uv) * size;
  float px = length(dx), py = length(dy);
  float pmax = max(px, py), pmin = max(min(px, py), 1e-8);
  float n = min(ceil(pmax / pmin), u_max_aniso);
  return clamp(log2(max(pmax / n, 1e-8)), 0.0, levels - 1.0);
}

// Anisotropic filtering as the reference of EXT_texture_filter_anisotropic
// describes it, done here rather than by the driver: N = ceil(Pmax / Pmin)
// probes (at most the anisotropy), each trilinear at level log2(Pmax / N),
// spread evenly over the footprint's longer axis (at i / (N + 1) − 1/2 of it,
// i = 1..N), averaged. The level is the one mip_level reports. Drivers each
// approximate the reference their own way, and llvmpipe's (an elliptical
// weighted average) costs as much on an isotropic pixel as on a grazing one:
// rendering took 4.5× the time of plain trilinear, three quarters of a texres
// run (docs/render.md). Here every renderer samples alike and an isotropic
// pixel costs one probe. gx, gy: the uv's
// derivatives along x and y, taken where control flow is uniform.
vec4 sample_map(sampler2D s, vec2 uv, vec2 gx, vec2 gy, vec2 size) {
  vec2 dx = gx * size, dy = gy * size;
  float px2 = dot(dx, dx), py2 = dot(dy, dy);
  vec2 major = px2 >= py2 ? gx : gy;
  float pmax = sqrt(max(px2, py2)), pmin = max(sqrt(min(px2, py2)), 1e-8);
  float n = clamp(ceil(pmax / pmin), 1.0, u_max_aniso);
  float lod = log2(max(pmax / n, 1e-8));
  vec4 sum = vec4(0.0);
  for (float i = 1.0; i <= n; i += 1.0) sum += textureLod(s, uv + major * (i / (n + 1.0) - 0.5), lod);
  return sum / n;
}

float d_ggx(float nh, float a2) {
  float d = nh * nh * (a2 - 1.0) + 1.0;
  return a2 / (PI * d * d);
}

float g1_smith(float x, float a2) { return 2.0 * x / (x + sqrt(a2 + (1.0 - a2) * x * x)); }

vec3 f_schlick(vec3 f0, float vh) { return f0 + (1.0 - f0) * pow(1.0 - vh, 5.0); }

void main() {
  vec2 uv[5], gx[5], gy[5];
  float mip[5];
  for (int i = 0; i < 5; i++) {
    vec3 t = vec3(u_uvset[i] == 1 ? v_uv1 : v_uv0, 1.0);
    uv[i] = vec2(dot(u_uvxf[2 * i], t), dot(u_uvxf[2 * i + 1], t));
    gx[i] = dFdx(uv[i]);
    gy[i] = dFdy(uv[i]);
#ifdef JND_AUX
    mip[i] = u_has[i] != 0 ? mip_level(uv[i], u_size[i], u_levels[i]) : -1.0;
#endif
  }
  // derivatives are taken above, before any fragment may leave
  vec4 base = u_base_color * v_color;
  if (u_has[0] != 0) base *= sample_map(u_map0, uv[0], gx[0], gy[0], u_size[0]);
#ifdef JND_ALPHA_MASK
  // only this variant may discard: the others keep early depth testing
  if (base.a < u_alpha_cutoff) discard;
#endif
  float alpha = u_alpha_mode == 2 ? base.a : 1.0;
#ifdef JND_AUX
  // the auxiliary pass: one sample per pixel, no shading
  vec2 cur = (v_clip.xy / v_clip.w * 0.5 + 0.5) * u_viewport;
  vec2 prev = (v_prev_clip.xy / v_prev_clip.w * 0.5 + 0.5) * u_viewport;
  o_aux = vec4(v_depth, cur.x - prev.x, -(cur.y - prev.y), 1.0);
  o_mip0 = vec4(mip[0], mip[1], mip[2], mip[3]);
  o_mip1 = vec4(mip[4], u_material, -1.0, -1.0);
  o_color = vec4(0.0);
  return;
#endif
#ifdef JND_UNLIT
  // unlit: the material's colour as it is, no light (003 §4.1's geometry-only view)
  o_color = vec4(base.rgb * u_exposure * alpha, alpha);
  return;
#endif

  float metallic = u_metallic, rough = u_roughness;
  if (u_has[1] != 0) {
    vec4 mr = sample_map(u_map1, uv[1], gx[1], gy[1], u_size[1]);
    rough *= mr.g;
    metallic *= mr.b;
  }
  rough = clamp(rough, 0.03, 1.0);
  metallic = clamp(metallic, 0.0, 1.0);

  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;
  if (u_has[2] != 0) {
    vec3 t = v_tangent.xyz - n * dot(n, v_tangent.xyz);
    if (dot(t, t) > 1e-12) {
      t = normalize(t);
      vec3 b = cross(n, t) * (v_tangent.w < 0.0 ? -1.0 : 1.0);
      vec3 tn = sample_map(u_map2, uv[2], gx[2], gy[2], u_size[2]).xyz * 2.0 - 1.0;
      tn.xy *= u_normal_scale;
      n = normalize(mat3(t, b, n) * tn);
    }
  }
  float ao = 1.0;
  if (u_has[3] != 0) ao = 1.0 + u_occlusion_strength * (sample_map(u_map3, uv[3], gx[3], gy[3], u_size[3]).r - 1.0);
  vec3 emissive = u_emissive;
  if (u_has[4] != 0) emissive *= sample_map(u_map4, uv[4], gx[4], gy[4], u_size[4]).rgb;

  vec3 v = normalize(u_eye - v_world);
  float nv = max(dot(n, v), 1e-4);
  vec3 f0 = mix(vec3(0.04), base.rgb, metallic);
  vec3 diffuse = base.rgb * (1.0 - metallic);
  float a = rough * rough, a2 = a * a;

  vec3 c = vec3(0.0);
  for (int i = 0; i < u_nlights && i < 8; i++) {
    vec3 l;
    vec3 radiance = u_lcolor[i];
    if (u_ltype[i] == 0) {
      l = -normalize(u_ldir[i]);
    } else {
      vec3 d = u_lpos[i] - v_world;
      float d2 = max(dot(d, d), 1e-8);
      l = d * inversesqrt(d2);
      radiance /= d2;
      if (u_lrange[i] > 0.0) {
        float q = d2 / (u_lrange[i] * u_lrange[i]);
        radiance *= clamp(1.0 - q * q, 0.0, 1.0);
      }
      if (u_ltype[i] == 2) {
        float cd = dot(-l, normalize(u_ldir[i]));
        float s = clamp((cd - u_lcone[i].y) / max(u_lcone[i].x - u_lcone[i].y, 1e-4), 0.0, 1.0);
        radiance *= s * s;
      }
    }
    float nl = dot(n, l);
    if (nl <= 0.0) continue;
    vec3 h = normalize(l + v);
    float nh = max(dot(n, h), 0.0), vh = max(dot(v, h), 0.0);
    vec3 f = f_schlick(f0, vh);
    vec3 spec = d_ggx(nh, a2) * g1_smith(nv, a2) * g1_smith(nl, a2) * f / (4.0 * nl * nv);
    c += ((1.0 - f) * diffuse / PI + spec) * radiance * nl;
  }

  if (u_env_intensity > 0.0) {
    vec3 r = reflect(-v, n);
    vec3 pre = textureLod(u_env, equirect_uv(u_env_rot * r), rough * (u_env_levels - 1.0)).rgb;
    vec2 ab = texture(u_brdf, vec2(nv, rough)).rg;
    vec3 spec = pre * (f0 * ab.x + ab.y);
    vec3 diff = sh_irradiance(u_env_rot * n) * diffuse;
    c += (diff + spec) * ao * u_env_intensity;
  }
  c += emissive;

  o_color = vec4(c * u_exposure * alpha, alpha);  // premultiplied
}
