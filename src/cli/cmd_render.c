/* jnd render MODEL -o DIR — frames of an asset under deterministic views. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli/cli.h"

#define MAX_EDITS 64

static void help(void) {
  printf(
      "usage: jnd render MODEL -o DIR [options]\n"
      "\n"
      "Renders MODEL (glTF 2.0 .gltf/.glb, or OBJ + MTL) headlessly with OpenGL 4.5\n"
      "(a GPU through EGL when there is one, else Mesa llvmpipe on the CPU) from N\n"
      "deterministic views around it, with physically based shading and image-based\n"
      "lighting, and writes the images and DIR/views.json. MODEL may be the word\n"
      "`builtin` (a rounded box with a procedural 2048^2 PBR material, no files\n"
      "needed) or `builtin:sphere`. See docs/render.md.\n"
      "\n"
      "%s"
      "  --motion-orbit DEG  the previous pose for motion vectors: the camera orbited by DEG\n"
      "                      degrees about the vertical axis through the centre (0.5)\n"
      "\n"
      "lighting:\n"
      "  --env-intensity K   multiplier on the environment (1; 0 turns IBL off)\n"
      "  --env-rotation DEG  rotation of the environment about +Y (0)\n"
      "  --background MODE   black (default) or env (the environment behind the object)\n"
      "  --light SPEC        a fixed light instead of the sampled ones (repeatable, <= 8):\n"
      "                        dir:DX,DY,DZ[:INTENSITY[:R,G,B]]      (direction of travel)\n"
      "                        point:X,Y,Z[:INTENSITY[:R,G,B]]\n"
      "                        spot:X,Y,Z:DX,DY,DZ[:INTENSITY[:OUTER_DEG]]\n"
      "  --exposure E        multiplier on linear radiance before the display transform (1)\n"
      "\n"
      "texture maps (named MATERIAL/SLOT, SLOT one of baseColor, metallicRoughness,\n"
      "normal, occlusion, emissive; * matches every material, a bare * every map):\n"
      "  --list-maps         print the maps and exit\n"
      "  --scale MAP=F       resample the map by factor F with Lanczos-3 (000 §4)\n"
      "  --scale MAP=WxH     resample the map to W x H pixels\n"
      "  --replace MAP=FILE  use an image file instead (PNG/JPEG in the slot's encoding)\n"
      "  --strict            a texture that cannot be loaded is an error (default: the slot\n"
      "                      falls back to its factor with a warning, as engines do)\n"
      "\n"
      "levels of detail (a glTF with MSFT_lod, e.g. what jnd lod writes):\n"
      "  --lod K             render level K (0: the finest, the default)\n"
      "  --list-lods         print the levels and their triangles and exit\n"
      "\n"
      "outputs (written to DIR, listed in DIR/views.json):\n"
      "  -o, --output DIR    the folder (created)\n"
      "  --outputs LIST      any of color,depth,mask,motion,mip,exr (default color,mask):\n"
      "                        color  view_NNN.png, 8-bit sRGB\n"
      "                        exr    also view_NNN.exr (linear) and float depth/motion/mip\n"
      "                        depth  view_NNN_depth.png, 16-bit, depth / depth_scale\n"
      "                        mask   view_NNN_mask.png, 8-bit coverage\n"
      "                        motion view_NNN_motion.png, 16-bit RGB, 0.5 + d / (2 motion_scale)\n"
      "                        mip    view_NNN_mip.png, 16-bit RGBA, (level + 1) / 64 for\n"
      "                               baseColor, metallicRoughness, normal, occlusion\n"
      "%s"
      "\n"
      "The same command on the same machine writes identical images.\n"
      "Paper numbers: 000 is Wolski et al. 2019 (texture resolution); include/jnd.h\n"
      "lists them all.\n"
      "Exit status: 0, 2 for bad input (one line: jnd: FILE: problem).\n",
      cli_views_help, cli_common_help);
}

typedef struct {
  const char *map;   /* pattern */
  const char *file;  /* --replace */
  double factor;     /* --scale F */
  int w, h;          /* --scale WxH */
} map_edit;


/* MAP matches "MAT/SLOT" with "*" for the material, or a bare "*". */
static int map_matches(const char *pattern, const char *name) {
  if (strcmp(pattern, "*") == 0) return 1;
  if (strncmp(pattern, "*/", 2) == 0) {
    const char *slash = strrchr(name, '/');
    return slash && strcmp(slash + 1, pattern + 2) == 0;
  }
  return strcmp(pattern, name) == 0;
}

static int parse_vec3(const char *s, double v[3], const char **end) {
  char *e;
  for (int k = 0; k < 3; k++) {
    errno = 0;
    v[k] = strtod(s, &e);
    if (e == s || errno || !isfinite(v[k])) return 0;
    s = e;
    if (k < 2) {
      if (*s != ',') return 0;
      s++;
    }
  }
  *end = s;
  return 1;
}

static int parse_light(const char *spec, jnd_light *L) {
  memset(L, 0, sizeof *L);
  L->color[0] = L->color[1] = L->color[2] = 1;
  L->intensity = 2;
  const char *s;
  if (strncmp(spec, "dir:", 4) == 0) {
    L->type = JND_LIGHT_DIRECTIONAL;
    if (!parse_vec3(spec + 4, L->direction, &s)) return 0;
  } else if (strncmp(spec, "point:", 6) == 0) {
    L->type = JND_LIGHT_POINT;
    L->intensity = 10;
    if (!parse_vec3(spec + 6, L->position, &s)) return 0;
  } else if (strncmp(spec, "spot:", 5) == 0) {
    L->type = JND_LIGHT_SPOT;
    L->intensity = 10;
    L->outer_deg = 30;
    L->inner_deg = 20;
    if (!parse_vec3(spec + 5, L->position, &s) || *s != ':' || !parse_vec3(s + 1, L->direction, &s)) return 0;
  } else {
    return 0;
  }
  if (*s == 0) return 1;
  if (*s != ':') return 0;
  char *e;
  L->intensity = strtod(s + 1, &e);
  if (e == s + 1 || !isfinite(L->intensity) || L->intensity < 0) return 0;
  s = e;
  if (*s == 0) return 1;
  if (*s != ':') return 0;
  if (L->type == JND_LIGHT_SPOT) {
    L->outer_deg = strtod(s + 1, &e);
    if (e == s + 1 || !(L->outer_deg > 0 && L->outer_deg < 90)) return 0;
    L->inner_deg = 0.8 * L->outer_deg;
    return *e == 0;
  }
  return parse_vec3(s + 1, L->color, &s) && *s == 0;
}

static cJSON *vec3_json(const double v[3]) {
  cJSON *a = cJSON_CreateArray();
  for (int k = 0; k < 3; k++) cJSON_AddItemToArray(a, cJSON_CreateNumber(v[k]));
  return a;
}

static cJSON *camera_json(const jnd_camera *c) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddItemToObject(o, "eye", vec3_json(c->eye));
  cJSON_AddItemToObject(o, "target", vec3_json(c->target));
  cJSON_AddItemToObject(o, "up", vec3_json(c->up));
  cJSON_AddNumberToObject(o, "fov_y_deg", c->fov_y_deg);
  cJSON_AddNumberToObject(o, "znear", c->znear);
  cJSON_AddNumberToObject(o, "zfar", c->zfar);
  return o;
}

static cJSON *light_json(const jnd_light *L) {
  static const char *const types[3] = {"directional", "point", "spot"};
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "type", types[L->type]);
  if (L->type != JND_LIGHT_DIRECTIONAL) cJSON_AddItemToObject(o, "position", vec3_json(L->position));
  if (L->type != JND_LIGHT_POINT) cJSON_AddItemToObject(o, "direction", vec3_json(L->direction));
  cJSON_AddItemToObject(o, "color", vec3_json(L->color));
  cJSON_AddNumberToObject(o, "intensity", L->intensity);
  if (L->range > 0) cJSON_AddNumberToObject(o, "range", L->range);
  if (L->type == JND_LIGHT_SPOT) {
    cJSON_AddNumberToObject(o, "inner_deg", L->inner_deg);
    cJSON_AddNumberToObject(o, "outer_deg", L->outer_deg);
  }
  return o;
}

/* The camera orbited by deg about the vertical axis through the target. */
static void orbit(const jnd_camera *c, double deg, jnd_camera *out) {
  *out = *c;
  double a = deg * M_PI / 180, cs = cos(a), sn = sin(a);
  double dx = c->eye[0] - c->target[0], dz = c->eye[2] - c->target[2];
  out->eye[0] = c->target[0] + cs * dx + sn * dz;
  out->eye[2] = c->target[2] - sn * dx + cs * dz;
}

static int write_png(const char *dir, const char *name, const jnd_image *img, int bits, cJSON *view,
                     const char *key) {
  char path[4200];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  if (jnd_image_write_png(path, img, bits) != JND_OK) {
    cli_error("%s", jnd_last_error());
    return 0;
  }
  cJSON_AddStringToObject(view, key, name);
  return 1;
}

static int write_exr(const char *dir, const char *name, const jnd_image *img, const char *const *names,
                     cJSON *view, const char *key) {
  char path[4200];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  if (jnd_image_write_exr(path, img, names, 0) != JND_OK) {
    cli_error("%s", jnd_last_error());
    return 0;
  }
  cJSON_AddStringToObject(view, key, name);
  return 1;
}

enum { O_COLOR = 1, O_DEPTH = 2, O_MASK = 4, O_MOTION = 8, O_MIP = 16, O_EXR = 32 };

static int parse_outputs(const char *v, unsigned *out) {
  char buf[256];
  snprintf(buf, sizeof buf, "%s", v);
  *out = 0;
  char *save = NULL;
  for (char *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
    if (strcmp(t, "color") == 0 || strcmp(t, "colour") == 0) *out |= O_COLOR;
    else if (strcmp(t, "depth") == 0) *out |= O_DEPTH;
    else if (strcmp(t, "mask") == 0) *out |= O_MASK;
    else if (strcmp(t, "motion") == 0) *out |= O_MOTION;
    else if (strcmp(t, "mip") == 0) *out |= O_MIP;
    else if (strcmp(t, "exr") == 0) *out |= O_EXR;
    else return 0;
  }
  return *out != 0;
}

static int apply_edits(jnd_scene *scene, const map_edit *edits, int nedits) {
  for (int e = 0; e < nedits; e++) {
    int hits = 0;
    jnd_image img = {0};
    jnd_image_info info;
    if (edits[e].file && jnd_image_read(edits[e].file, &img, &info) != JND_OK) {
      cli_error("%s", jnd_last_error());
      return 0;
    }
    for (int i = 0; i < jnd_scene_map_count(scene); i++) {
      jnd_map_info mi;
      jnd_scene_map_info(scene, i, &mi);
      if (!map_matches(edits[e].map, mi.name)) continue;
      hits++;
      jnd_status st;
      if (edits[e].file) {
        if (info.encoding == JND_ENCODING_LINEAR && mi.kind == JND_MAP_KIND_COLOR) {
          cli_error("%s: a linear image cannot replace the colour map %s (give PNG/JPEG)", edits[e].file,
                    mi.name);
          jnd_image_free(&img);
          return 0;
        }
        st = jnd_scene_map_set(scene, i, &img);
      } else if (edits[e].w > 0) {
        st = jnd_scene_map_resize(scene, i, edits[e].w, edits[e].h);
      } else {
        int w = (int)lround(mi.orig_width * edits[e].factor), h = (int)lround(mi.orig_height * edits[e].factor);
        st = jnd_scene_map_resize(scene, i, w < 1 ? 1 : w, h < 1 ? 1 : h);
      }
      if (st != JND_OK) {
        cli_error("%s: %s", mi.name, jnd_last_error());
        jnd_image_free(&img);
        return 0;
      }
    }
    jnd_image_free(&img);
    if (!hits) {
      cli_error("%s: no such map in %s (jnd render %s --list-maps)", edits[e].map, jnd_scene_path(scene),
                jnd_scene_path(scene));
      return 0;
    }
  }
  return 1;
}

static int run(int argc, char **argv) {
  const char *model = NULL, *dir = NULL, *v;
  cli_common common = {0};
  cli_views vo;
  cli_views_init(&vo, 512, 512);
  int list_maps = 0, strict = 0;
  int lod = 0, list_lods = 0;
  int background_env = 0, nlights_fixed = 0;
  double env_intensity = 1, env_rotation = 0, exposure = 1, motion_orbit = 0.5;
  unsigned outputs = O_COLOR | O_MASK;
  jnd_light fixed[JND_MAX_LIGHTS];
  map_edit edits[MAX_EDITS];
  int nedits = 0;
  cli_args args = cli_args_start(argc, argv, "render"), *ap = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    const char *a = argv[args.i];
    if (cli_flag(ap, "--help") || cli_flag(ap, "-h")) {
      help();
      return EXIT_OK;
    } else if (cli_opt(ap, "-o", &v) || cli_opt(ap, "--output", &v)) {
      dir = v;
    } else if (cli_views_opt(ap, &vo) || cli_common_opt(ap, &common)) {
    } else if (cli_opt(ap, "--motion-orbit", &v)) {
      motion_orbit = cli_double(ap, "--motion-orbit", v, -180, 180);
    } else if (cli_opt(ap, "--env-intensity", &v)) {
      env_intensity = cli_double(ap, "--env-intensity", v, 0, 1e6);
    } else if (cli_opt(ap, "--env-rotation", &v)) {
      env_rotation = cli_double(ap, "--env-rotation", v, -3600, 3600);
    } else if (cli_opt(ap, "--background", &v)) {
      if (strcmp(v, "env") == 0) background_env = 1;
      else if (strcmp(v, "black") == 0) background_env = 0;
      else return cli_bad("render: --background: '%s' is not black or env", v);
    } else if (cli_opt(ap, "--light", &v)) {
      if (nlights_fixed >= JND_MAX_LIGHTS) return cli_bad("render: --light: more than 8 lights");
      if (!parse_light(v, &fixed[nlights_fixed]))
        return cli_bad("render: --light: '%s' is not dir:DX,DY,DZ[:I[:R,G,B]], point:X,Y,Z[:I[:R,G,B]] "
                   "or spot:X,Y,Z:DX,DY,DZ[:I[:OUTER_DEG]]",
                   v);
      nlights_fixed++;
    } else if (cli_opt(ap, "--exposure", &v)) {
      exposure = cli_double(ap, "--exposure", v, 0, 1e9);
    } else if (cli_opt(ap, "--scale", &v) || cli_opt(ap, "--replace", &v)) {
      int replace = strncmp(a, "--replace", 9) == 0;
      const char *eq = strrchr(v, '=');
      if (!eq || eq == v || !eq[1] || nedits >= MAX_EDITS)
        return cli_bad("render: '%s' is not MAP=VALUE (at most 64 edits)", v);
      map_edit *e = &edits[nedits++];
      memset(e, 0, sizeof *e);
      e->map = strndup(v, (size_t)(eq - v));   /* freed at exit */
      if (replace) {
        e->file = eq + 1;
      } else if (strchr(eq + 1, 'x')) {
        cli_size(ap, "--scale", eq + 1, 1, 32768, &e->w, &e->h);
      } else {
        e->factor = cli_double(ap, "--scale", eq + 1, 1e-6, 16);
      }
    } else if (cli_flag(ap, "--list-maps")) {
      list_maps = 1;
    } else if (cli_opt(ap, "--lod", &v)) {
      lod = cli_int(ap, "--lod", v, 0, 63);
    } else if (cli_flag(ap, "--list-lods")) {
      list_lods = 1;
    } else if (cli_flag(ap, "--strict")) {
      strict = 1;
    } else if (cli_opt(ap, "--outputs", &v)) {
      if (!parse_outputs(v, &outputs))
        return cli_bad("render: --outputs: '%s' is not a list of color,depth,mask,motion,mip,exr", v);
    } else if (a[0] == '-' && a[1]) {
      return cli_unknown(ap);
    } else if (!model) {
      model = a;
    } else {
      return cli_unknown(ap);
    }
  }
  if (args.bad) {
    for (int e = 0; e < nedits; e++) free((char *)edits[e].map);
    return EXIT_BAD;
  }
  if (!model) {
    cli_error("render: give a MODEL (a .gltf/.glb/.obj file or builtin); jnd render --help");
    return EXIT_BAD;
  }
  if (!dir && !list_maps && !list_lods) {
    cli_error("render: give an output folder with -o DIR; jnd render --help");
    return EXIT_BAD;
  }
  int rc = EXIT_BAD;
  jnd_scene *scene = NULL;
  jnd_renderer *r = NULL;
  jnd_view *views = NULL;
  cJSON *report = NULL;
  double t0 = jnd_seconds();
  jnd_status st;
  /* the outputs checked before any work, written staged, published at the end */
  jnd_output *outw = NULL;
  const char *json_out = common.json_path;
  if (dir && !list_maps && !list_lods) {
    const char *ins[3 + MAX_EDITS] = {model, vo.set.render.env_path, vo.cameras};
    for (int e = 0; e < nedits; e++) ins[3 + e] = edits[e].file;
    if (cli_out_open(&outw) != EXIT_OK || cli_out_inputs(outw, ins, 3 + nedits) != EXIT_OK ||
        cli_out_dir(outw, dir, &dir) != EXIT_OK || cli_out_file(outw, common.json_path, &json_out) != EXIT_OK)
      goto done;
  }
  if ((st = jnd_scene_open(model, vo.map_size, &scene)) != JND_OK) {
    cli_error("%s", jnd_last_error());
    goto done;
  }
  for (int i = 0; i < jnd_scene_warning_count(scene); i++) {
    if (strict) {
      cli_error("%s", jnd_scene_warning(scene, i));
      goto done;
    }
    if (!common.quiet) fprintf(stderr, "jnd: warning: %s\n", jnd_scene_warning(scene, i));
  }
  if (list_lods) {
    for (int k = 0; k < jnd_scene_lod_count(scene); k++) {
      jnd_lod_level_info li;
      jnd_scene_lod_info(scene, k, &li);
      printf("level %-3d %10zu triangles %10zu vertices%s%s\n", k, li.triangles, li.vertices, li.source[0] ? "  " : "",
             li.source);
    }
    rc = EXIT_OK;
    goto done;
  }
  if (jnd_scene_lod_select(scene, lod) != JND_OK) {
    cli_error("%s", jnd_last_error());
    goto done;
  }
  if (list_maps) {
    for (int i = 0; i < jnd_scene_map_count(scene); i++) {
      jnd_map_info mi;
      jnd_scene_map_info(scene, i, &mi);
      const float *t = mi.uv_transform;
      int moved = !(t[0] == 1 && t[1] == 0 && t[2] == 0 && t[3] == 0 && t[4] == 1 && t[5] == 0);
      printf("%-48s %5d x %-5d %d channels, uv set %d%s\n", mi.name, mi.orig_width, mi.orig_height, mi.channels,
             mi.uv_set, moved ? ", texture transform" : "");
    }
    rc = EXIT_OK;
    goto done;
  }
  if (!apply_edits(scene, edits, nedits)) goto done;
  double t_load = jnd_seconds() - t0;
  /* views (read before the output folder exists, so that bad cameras leave nothing behind) */
  int nviews = 0;
  if (nlights_fixed) vo.set.sampling.lights = 0;
  if (cli_views_make(&vo, scene, &views, &nviews) != JND_OK) {
    cli_error("%s", jnd_last_error());
    goto done;
  }
  unsigned gl_outputs = JND_OUT_COLOR | JND_OUT_MASK;
  if (outputs & O_DEPTH) gl_outputs |= JND_OUT_DEPTH;
  if (outputs & O_MOTION) gl_outputs |= JND_OUT_MOTION;
  if (outputs & O_MIP) gl_outputs |= JND_OUT_MIP;
  for (int i = 0; i < nviews; i++) {
    jnd_view *w = &views[i];
    if (nlights_fixed) {
      w->nlights = nlights_fixed;
      memcpy(w->lights, fixed, sizeof fixed);
    }
    w->env_intensity = env_intensity;
    w->env_rotation_deg = env_rotation;
    w->exposure = exposure;
    w->background_env = background_env;
    w->outputs = gl_outputs;
    if (!w->has_prev && (outputs & O_MOTION) && motion_orbit != 0) {
      orbit(&w->camera, motion_orbit, &w->prev_camera);
      w->has_prev = 1;
    }
  }

  double t1 = jnd_seconds();
  int width = vo.set.render.width, height = vo.set.render.height;
  if (jnd_renderer_create(&vo.set.render, &r) != JND_OK) {
    cli_error("%s", jnd_last_error());
    goto done;
  }
  double t_renderer = jnd_seconds() - t1;
  /* the folder only now: a bad environment or no OpenGL leaves nothing behind either */
  if (jnd_make_dirs(dir) != JND_OK) {
    cli_error("%s", jnd_last_error());
    goto done;
  }

  report = cli_report_new("render");
  cJSON *in = cli_report_section(report, "inputs");
  cJSON_AddStringToObject(in, "model", model);
  if (vo.set.render.env_path) cJSON_AddStringToObject(in, "env", vo.set.render.env_path);
  if (vo.cameras) cJSON_AddStringToObject(in, "cameras", vo.cameras);
  cJSON *par = cli_report_section(report, "parameters");
  cJSON_AddNumberToObject(par, "views", nviews);
  cJSON_AddNumberToObject(par, "seed", (double)vo.set.sampling.seed);
  cJSON_AddNumberToObject(par, "width", width);
  cJSON_AddNumberToObject(par, "height", height);
  cJSON_AddNumberToObject(par, "coverage", vo.set.sampling.coverage);
  if (vo.set.sampling.distance > 0) cJSON_AddNumberToObject(par, "distance", vo.set.sampling.distance);
  cJSON_AddNumberToObject(par, "fov_y_deg", vo.set.sampling.fov_y_deg);
  cJSON_AddNumberToObject(par, "env_intensity", env_intensity);
  cJSON_AddNumberToObject(par, "env_rotation_deg", env_rotation);
  cJSON_AddNumberToObject(par, "exposure", exposure);
  cJSON_AddStringToObject(par, "background", background_env ? "env" : "black");
  cJSON_AddNumberToObject(par, "samples", vo.set.render.samples);
  cJSON_AddNumberToObject(par, "anisotropy", vo.set.render.anisotropy);
  cJSON *res = cli_report_section(report, "result");
  cJSON_AddStringToObject(res, "renderer", jnd_renderer_description(r));
  double centre[3], radius;
  jnd_scene_bounds(scene, centre, &radius);
  cJSON_AddItemToObject(res, "centre", vec3_json(centre));
  cJSON_AddNumberToObject(res, "radius", radius);
  cJSON_AddNumberToObject(res, "triangles", (double)jnd_scene_triangle_count(scene));
  cJSON_AddNumberToObject(res, "lod", lod);
  cJSON_AddNumberToObject(res, "lod_levels", jnd_scene_lod_count(scene));
  cJSON_AddNumberToObject(res, "materials", jnd_scene_material_count(scene));
  int nmaps = jnd_scene_map_count(scene);
  cJSON *jmaps = cJSON_AddArrayToObject(report, "maps");
  double *mip_min = calloc((size_t)nmaps + 1, sizeof *mip_min);
  for (int i = 0; i < nmaps; i++) {
    jnd_map_info mi;
    jnd_scene_map_info(scene, i, &mi);
    cJSON *m = cJSON_CreateObject();
    cJSON_AddStringToObject(m, "name", mi.name);
    cJSON_AddNumberToObject(m, "width", mi.width);
    cJSON_AddNumberToObject(m, "height", mi.height);
    cJSON_AddNumberToObject(m, "orig_width", mi.orig_width);
    cJSON_AddNumberToObject(m, "orig_height", mi.orig_height);
    cJSON_AddNumberToObject(m, "uv_set", mi.uv_set);
    cJSON *uvt = cJSON_AddArrayToObject(m, "uv_transform");
    for (int k = 0; k < 6; k++) cJSON_AddItemToArray(uvt, cJSON_CreateNumber(mi.uv_transform[k]));
    cJSON_AddItemToArray(jmaps, m);
    if (mip_min) mip_min[i] = INFINITY;
  }
  cJSON *jviews = cJSON_AddArrayToObject(report, "views");

  cli_progress prog;
  cli_progress_start(&prog, &common, "render", nviews);
  double t_render = 0;
  int ok = 1;
  for (int i = 0; i < nviews && ok; i++) {
    jnd_frame f;
    double tr = jnd_seconds();
    if (jnd_render(r, scene, &views[i], &f) != JND_OK) {
      cli_error("%s: %s", model, jnd_last_error());
      ok = 0;
      break;
    }
    t_render += jnd_seconds() - tr;
    cJSON *jv = cJSON_CreateObject();
    cJSON_AddItemToArray(jviews, jv);
    cJSON_AddNumberToObject(jv, "index", i);
    char name[64];
    jnd_image tmp = {0};
    if (outputs & O_COLOR) {
      snprintf(name, sizeof name, "view_%03d.png", i);
      ok = jnd_render_to_srgb(&f.color, &tmp) == JND_OK && write_png(dir, name, &tmp, 8, jv, "color");
      jnd_image_free(&tmp);
      if (ok && (outputs & O_EXR)) {
        snprintf(name, sizeof name, "view_%03d.exr", i);
        ok = write_exr(dir, name, &f.color, NULL, jv, "color_exr");
      }
    }
    double cover = 0;
    for (size_t k = 0; k < (size_t)width * height; k++) cover += f.mask.data[k];
    cJSON_AddNumberToObject(jv, "coverage", cover / ((double)width * height));
    if (ok && (outputs & O_MASK)) {
      snprintf(name, sizeof name, "view_%03d_mask.png", i);
      ok = write_png(dir, name, &f.mask, 8, jv, "mask");
    }
    if (ok && (outputs & O_DEPTH)) {
      double scale = views[i].camera.zfar > 0 ? views[i].camera.zfar : 1;
      for (size_t k = 0; k < (size_t)width * height; k++)
        if (f.depth.data[k] > scale) scale = f.depth.data[k];
      if (jnd_image_alloc(&tmp, width, height, 1) == JND_OK) {
        for (size_t k = 0; k < (size_t)width * height; k++) tmp.data[k] = (float)(f.depth.data[k] / scale);
        snprintf(name, sizeof name, "view_%03d_depth.png", i);
        ok = write_png(dir, name, &tmp, 16, jv, "depth");
        cJSON_AddNumberToObject(jv, "depth_scale", scale);
        jnd_image_free(&tmp);
      }
      if (ok && (outputs & O_EXR)) {
        snprintf(name, sizeof name, "view_%03d_depth.exr", i);
        ok = write_exr(dir, name, &f.depth, NULL, jv, "depth_exr");
      }
    }
    if (ok && (outputs & O_MOTION)) {
      double mx = 0;
      size_t P = (size_t)width * height;
      for (size_t k = 0; k < 2 * P; k++)
        if (fabs(f.motion.data[k]) > mx) mx = fabs(f.motion.data[k]);
      double scale = mx > 0 ? pow(2, ceil(log2(mx))) : 1;
      if (jnd_image_alloc(&tmp, width, height, 3) == JND_OK) {
        for (size_t k = 0; k < 2 * P; k++) tmp.data[k] = (float)(0.5 + f.motion.data[k] / (2 * scale));
        snprintf(name, sizeof name, "view_%03d_motion.png", i);
        ok = write_png(dir, name, &tmp, 16, jv, "motion");
        cJSON_AddNumberToObject(jv, "motion_scale", scale);
        jnd_image_free(&tmp);
      }
      if (ok && (outputs & O_EXR)) {
        static const char *const xy[2] = {"X", "Y"};
        snprintf(name, sizeof name, "view_%03d_motion.exr", i);
        ok = write_exr(dir, name, &f.motion, xy, jv, "motion_exr");
      }
    }
    if (ok && (outputs & O_MIP)) {
      size_t P = (size_t)width * height;
      if (jnd_image_alloc(&tmp, width, height, 4) == JND_OK) {
        for (size_t k = 0; k < 4 * P; k++) tmp.data[k] = (float)((f.mip.data[k] + 1) / 64.0);
        snprintf(name, sizeof name, "view_%03d_mip.png", i);
        ok = write_png(dir, name, &tmp, 16, jv, "mip");
        jnd_image_free(&tmp);
      }
      if (ok && (outputs & O_EXR)) {
        /* one channel per slot, named for it (readers order EXR channels by name) */
        static const char *const slots[5] = {"baseColor", "metallicRoughness", "normal", "occlusion", "emissive"};
        snprintf(name, sizeof name, "view_%03d_mip.exr", i);
        ok = write_exr(dir, name, &f.mip, slots, jv, "mip_exr");
      }
      /* the finest level each map is sampled at in this view (000 §4: a
       * map never sampled at level 0 can be halved) */
      cJSON *mm = cJSON_AddObjectToObject(jv, "mip_min");
      for (int mi = 0; mi < nmaps; mi++) {
        jnd_map_info info;
        jnd_scene_map_info(scene, mi, &info);
        double lo = INFINITY;
        const float *lv = f.mip.data + (size_t)info.slot * P;
        for (size_t k = 0; k < P; k++)
          if ((int)lroundf(f.material.data[k]) == info.material && lv[k] >= 0 && lv[k] < lo) lo = lv[k];
        if (isfinite(lo)) {
          cJSON_AddNumberToObject(mm, info.name, lo);
          if (mip_min && lo < mip_min[mi]) mip_min[mi] = lo;
        }
      }
    }
    cJSON_AddItemToObject(jv, "camera", camera_json(&views[i].camera));
    if (views[i].has_prev) cJSON_AddItemToObject(jv, "prev_camera", camera_json(&views[i].prev_camera));
    cJSON *jl = cJSON_AddArrayToObject(jv, "lights");
    for (int l = 0; l < views[i].nlights; l++) cJSON_AddItemToArray(jl, light_json(&views[i].lights[l]));
    jnd_frame_free(&f);
    cli_progress_step(&prog, i + 1);
  }
  cli_progress_end(&prog);
  if (ok && (outputs & O_MIP) && mip_min) {
    for (int i = 0; i < nmaps; i++) {
      cJSON *m = cJSON_GetArrayItem(jmaps, i);
      if (isfinite(mip_min[i])) cJSON_AddNumberToObject(m, "mip_min", mip_min[i]);
    }
  }
  free(mip_min);
  if (ok && common.timings) {
    cJSON *t = cJSON_AddObjectToObject(res, "timings");
    cJSON_AddNumberToObject(t, "load_s", t_load);
    cJSON_AddNumberToObject(t, "renderer_s", t_renderer);
    cJSON_AddNumberToObject(t, "render_s", t_render);
    cJSON_AddNumberToObject(t, "fps", t_render > 0 ? nviews / t_render : 0);
  }
  if (!ok) goto done;
  char manifest[4200];
  snprintf(manifest, sizeof manifest, "%s/views.json", dir);
  if (cli_report_write(report, manifest) != EXIT_OK) goto done;
  if (json_out && cli_report_write(report, json_out) != EXIT_OK) goto done;
  cli_info(&common, "jnd render: %d views of %s (%zu triangles) at %dx%d on %s; load %.2f s, %.1f frames/s\n",
           nviews, model, jnd_scene_triangle_count(scene), width, height, jnd_renderer_description(r), t_load,
           t_render > 0 ? nviews / t_render : 0);
  rc = EXIT_OK;
done:
  rc = cli_out_end(outw, rc);
  for (int e = 0; e < nedits; e++) free((char *)edits[e].map);
  cJSON_Delete(report);
  free(views);
  jnd_renderer_free(r);
  jnd_scene_free(scene);
  return rc;
}

const jnd_command jnd_cmd_render = {"render", "frames of an asset under deterministic views (headless PBR)", run};
