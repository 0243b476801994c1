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

static int parse_outputs(const char *v, unsigned *out) {
  char buf[256];
  snprintf(buf, sizeof buf, "%s", v);
  *out = 0;
  char *save = NULL;
  for (char *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
    if (strcmp(t, "color") == 0 || strcmp(t, "colour") == 0) *out |= JND_RENDER_COLOR;
    else if (strcmp(t, "depth") == 0) *out |= JND_RENDER_DEPTH;
    else if (strcmp(t, "mask") == 0) *out |= JND_RENDER_MASK;
    else if (strcmp(t, "motion") == 0) *out |= JND_RENDER_MOTION;
    else if (strcmp(t, "mip") == 0) *out |= JND_RENDER_MIP;
    else if (strcmp(t, "exr") == 0) *out |= JND_RENDER_EXR;
    else return 0;
  }
  return *out != 0;
}

/* --list-lods and --list-maps: the asset as loaded, nothing written */
static int list(const char *model, const cli_views *vo, int strict, int lod, int lods, const cli_common *common) {
  jnd_scene *scene = NULL;
  if (jnd_scene_open(model, vo->map_size, &scene) != JND_OK) return cli_lib_error();
  int rc = EXIT_OK;
  for (int i = 0; i < jnd_scene_warning_count(scene) && rc == EXIT_OK; i++) {
    if (strict) rc = cli_bad("%s", jnd_scene_warning(scene, i));
    else cli_info(common, "jnd: warning: %s\n", jnd_scene_warning(scene, i));
  }
  if (rc == EXIT_OK && lods) {
    for (int k = 0; k < jnd_scene_lod_count(scene); k++) {
      jnd_lod_level_info li;
      jnd_scene_lod_info(scene, k, &li);
      printf("level %-3d %10zu triangles %10zu vertices%s%s\n", k, li.triangles, li.vertices, li.source[0] ? "  " : "",
             li.source);
    }
  } else if (rc == EXIT_OK && jnd_scene_lod_select(scene, lod) != JND_OK) {
    rc = cli_lib_error();
  } else if (rc == EXIT_OK) {
    for (int i = 0; i < jnd_scene_map_count(scene); i++) {
      jnd_map_info mi;
      jnd_scene_map_info(scene, i, &mi);
      const float *t = mi.uv_transform;
      int moved = !(t[0] == 1 && t[1] == 0 && t[2] == 0 && t[3] == 0 && t[4] == 1 && t[5] == 0);
      printf("%-48s %5d x %-5d %d channels, uv set %d%s\n", mi.name, mi.orig_width, mi.orig_height, mi.channels,
             mi.uv_set, moved ? ", texture transform" : "");
    }
  }
  jnd_scene_free(scene);
  return rc;
}

static int run(int argc, char **argv) {
  const char *model = NULL, *dir = NULL, *v;
  cli_common common = {0};
  cli_views vo;
  cli_views_init(&vo, 512, 512);
  jnd_render_params p;
  jnd_render_defaults(&p);
  int list_maps = 0, list_lods = 0, nlights_fixed = 0;
  jnd_light fixed[JND_MAX_LIGHTS];
  jnd_map_edit edits[MAX_EDITS];
  int nedits = 0;
  cli_args args = cli_args_start(argc, argv, "render"), *ap = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    const char *a = argv[args.i];
    if (cli_help(ap)) {
      help();
      return EXIT_OK;
    } else if (cli_opt(ap, "-o", &v) || cli_opt(ap, "--output", &v)) {
      dir = v;
    } else if (cli_views_opt(ap, &vo) || cli_common_opt(ap, &common)) {
    } else if (cli_opt(ap, "--motion-orbit", &v)) {
      p.motion_orbit_deg = cli_double(ap, "--motion-orbit", v, -180, 180);
    } else if (cli_opt(ap, "--env-intensity", &v)) {
      p.env_intensity = cli_double(ap, "--env-intensity", v, 0, 1e6);
    } else if (cli_opt(ap, "--env-rotation", &v)) {
      p.env_rotation_deg = cli_double(ap, "--env-rotation", v, -3600, 3600);
    } else if (cli_opt(ap, "--background", &v)) {
      if (strcmp(v, "env") == 0) p.background_env = 1;
      else if (strcmp(v, "black") == 0) p.background_env = 0;
      else return cli_bad("render: --background: '%s' is not black or env", v);
    } else if (cli_opt(ap, "--light", &v)) {
      if (nlights_fixed >= JND_MAX_LIGHTS) return cli_bad("render: --light: more than 8 lights");
      if (!parse_light(v, &fixed[nlights_fixed]))
        return cli_bad("render: --light: '%s' is not dir:DX,DY,DZ[:I[:R,G,B]], point:X,Y,Z[:I[:R,G,B]] "
                   "or spot:X,Y,Z:DX,DY,DZ[:I[:OUTER_DEG]]",
                   v);
      nlights_fixed++;
    } else if (cli_opt(ap, "--exposure", &v)) {
      p.exposure = cli_double(ap, "--exposure", v, 0, 1e9);
    } else if (cli_opt(ap, "--scale", &v) || cli_opt(ap, "--replace", &v)) {
      int replace = strncmp(a, "--replace", 9) == 0;
      const char *eq = strrchr(v, '=');
      if (!eq || eq == v || !eq[1] || nedits >= MAX_EDITS)
        return cli_bad("render: '%s' is not MAP=VALUE (at most 64 edits)", v);
      jnd_map_edit *e = &edits[nedits++];
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
      p.lod = cli_int(ap, "--lod", v, 0, 63);
    } else if (cli_flag(ap, "--list-lods")) {
      list_lods = 1;
    } else if (cli_flag(ap, "--strict")) {
      p.strict = 1;
    } else if (cli_opt(ap, "--outputs", &v)) {
      if (!parse_outputs(v, &p.outputs))
        return cli_bad("render: --outputs: '%s' is not a list of color,depth,mask,motion,mip,exr", v);
    } else if (!cli_operand(ap, &model, NULL, 1)) {
      return EXIT_BAD;
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
  int rc;
  if (list_maps || list_lods) {
    rc = list(model, &vo, p.strict, p.lod, list_lods, &common);
  } else {
    p.views = vo.set;
    p.lights = fixed;
    p.nlights = nlights_fixed;
    p.edits = edits;
    p.nedits = nedits;
    cli_run_options(&p.run, &common, vo.map_size);
    cli_progress prog;
    cli_progress_start(&prog, &common, "render", 1);
    p.progress = cli_progress_callback;
    p.progress_user = &prog;
    jnd_render_result *R = NULL;
    jnd_status st = jnd_render_run(model, &p, dir, &R);
    cli_progress_end(&prog);
    if (st != JND_OK) {
      rc = cli_lib_error();
    } else {
      rc = cli_report_print(R->report, common.json_path);
      cli_info(&common, "jnd render: %d views of %s (%zu triangles) at %dx%d on %s; load %.2f s, %.1f frames/s\n",
               R->views, model, R->triangles, p.views.render.width, p.views.render.height, R->renderer, R->load_s,
               R->render_s > 0 ? R->views / R->render_s : 0);
    }
    jnd_render_result_free(R);
  }
  for (int e = 0; e < nedits; e++) free((char *)edits[e].map);
  return rc;
}

const jnd_command jnd_cmd_render = {"render", "frames of an asset under deterministic views (headless PBR)", run};
