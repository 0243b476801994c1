/* Option parsing shared by the subcommands: one parser per option group
 * (common, display, views, criterion, calibration), the same limits and
 * messages in every command, and no exit(): errors are printed once and
 * returned. */
#include <errno.h>
#include <math.h>
#include <omp.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"

__attribute__((format(printf, 1, 0))) static void verror(const char *fmt, va_list ap) {
  fputs("jnd: ", stderr);
  vfprintf(stderr, fmt, ap);
  fputc('\n', stderr);
}

void cli_error(const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  verror(fmt, ap);
  va_end(ap);
}

int cli_bad(const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  verror(fmt, ap);
  va_end(ap);
  return EXIT_BAD;
}

int cli_lib_error(void) { return cli_bad("%s", jnd_last_error()); }

void cli_info(const cli_common *c, const char *fmt, ...) {
  if (c && c->quiet) return;
  va_list ap;
  va_start(ap, fmt);
  vfprintf(stderr, fmt, ap);
  va_end(ap);
}

cli_args cli_args_start(int argc, char **argv, const char *cmd) {
  cli_args a = {argc, argv, 1, cmd, 0};
  return a;
}

int cli_unknown(cli_args *a) {
  const char *arg = a->argv[a->i];
  a->bad = 1;
  if (arg[0] == '-')
    return cli_bad("%s: unknown option '%s' (jnd %s --help lists the options)", a->cmd, arg, a->cmd);
  return cli_bad("%s: unexpected argument '%s' (jnd %s --help)", a->cmd, arg, a->cmd);
}

int cli_help(const cli_args *a) { return cli_flag(a, "--help") || cli_flag(a, "-h"); }

int cli_operand(cli_args *a, const char **ops, int *n, int max) {
  const char *arg = a->argv[a->i];
  int one = 0, *count = n ? n : &one;
  if (!n && ops[0]) one = 1;
  if ((arg[0] == '-' && arg[1]) || *count >= max) {
    if (*count >= max && max > 1 && arg[0] != '-') {
      a->bad = 1;
      cli_error("%s: at most %d arguments ('%s' is one too many; jnd %s --help)", a->cmd, max, arg, a->cmd);
      return 0;
    }
    cli_unknown(a);
    return 0;
  }
  ops[(*count)++] = arg;
  return 1;
}

/* an error in the value of an option: printed once, parsing stops */
__attribute__((format(printf, 2, 3))) static void fail(cli_args *a, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  if (!a->bad) verror(fmt, ap);
  va_end(ap);
  a->bad = 1;
}

int cli_flag(const cli_args *a, const char *name) { return strcmp(a->argv[a->i], name) == 0; }

int cli_opt(cli_args *a, const char *name, const char **val) {
  const char *s = a->argv[a->i];
  size_t n = strlen(name);
  if (strncmp(s, name, n) != 0) return 0;
  if (s[n] == '=') {
    *val = s + n + 1;
    return 1;
  }
  if (s[n] != 0) return 0;
  if (a->i + 1 >= a->argc) {
    fail(a, "%s needs a value", name);
    *val = "";
    return 1;
  }
  *val = a->argv[++a->i];
  return 1;
}

double cli_double(cli_args *a, const char *opt, const char *v, double lo, double hi) {
  char *end;
  errno = 0;
  double d = strtod(v, &end);
  if (end == v || *end || errno || !isfinite(d)) {
    fail(a, "%s: '%s' is not a number", opt, v);
    return lo;
  }
  if (d < lo || d > hi) {
    fail(a, "%s: %g is outside [%g, %g]", opt, d, lo, hi);
    return lo;
  }
  return d;
}

int cli_int(cli_args *a, const char *opt, const char *v, int lo, int hi) {
  char *end;
  errno = 0;
  long d = strtol(v, &end, 10);
  if (end == v || *end || errno) {
    fail(a, "%s: '%s' is not an integer", opt, v);
    return lo;
  }
  if (d < lo || d > hi) {
    fail(a, "%s: %ld is outside [%d, %d]", opt, d, lo, hi);
    return lo;
  }
  return (int)d;
}

void cli_pair(cli_args *a, const char *opt, const char *v, double *x, double *y) {
  char *end;
  errno = 0;
  *x = strtod(v, &end);
  if (end != v && *end == ',' && !errno) {
    const char *s = end + 1;
    *y = strtod(s, &end);
    if (end != s && !*end && !errno && isfinite(*x) && isfinite(*y)) return;
  }
  fail(a, "%s: '%s' is not a pair of numbers like 10,20", opt, v);
  *x = *y = 0;
}

void cli_size(cli_args *a, const char *opt, const char *v, int lo, int hi, int *w, int *h) {
  char *end;
  errno = 0;
  long x = strtol(v, &end, 10), y = 0;
  int ok = end != v && (*end == 'x' || *end == 'X') && !errno;
  if (ok) {
    const char *s = end + 1;
    y = strtol(s, &end, 10);
    ok = end != s && !*end && !errno && *s != '-' && *s != '+';
  }
  if (!ok || x < lo || x > hi || y < lo || y > hi) {
    fail(a, "%s: '%s' is not WxH with W and H in %d..%d pixels", opt, v, lo, hi);
    return;
  }
  *w = (int)x;
  *h = (int)y;
}

int cli_int_list(cli_args *a, const char *opt, const char *v, int lo, int hi, int *out, int max) {
  int n = 0;
  const char *s = v;
  while (*s) {
    char *e;
    errno = 0;
    long x = strtol(s, &e, 10);
    if (e == s || errno || x < lo || x > hi || (*e && *e != ',') || n >= max) {
      fail(a, "%s: '%s' is not a list of at most %d integers in %d..%d like 1024,512,256", opt, v, max, lo, hi);
      return 0;
    }
    out[n++] = (int)x;
    if (!*e) break;
    s = e + 1;
  }
  if (n == 0) fail(a, "%s: an empty list", opt);
  return n;
}

int cli_double_list(cli_args *a, const char *opt, const char *v, double lo, double hi, double *out, int max) {
  int n = 0;
  const char *s = v;
  while (*s) {
    char *e;
    errno = 0;
    double x = strtod(s, &e);
    if (e == s || errno || !isfinite(x) || x < lo || x > hi || (*e && *e != ',') || n >= max) {
      fail(a, "%s: '%s' is not a list of at most %d numbers in %g..%g like 1,2.5,10", opt, v, max, lo, hi);
      return 0;
    }
    out[n++] = x;
    if (!*e) break;
    s = e + 1;
  }
  if (n == 0) fail(a, "%s: an empty list", opt);
  return n;
}

/* ---- a chain's error targets ---- */

/* a number or a fraction of two ("0.001", "1/1024"); the end in *end */
static int number_or_fraction(const char *s, char **end, double *x) {
  errno = 0;
  *x = strtod(s, end);
  if (*end == s || errno || !isfinite(*x)) return 0;
  if (**end != '/') return 1;
  const char *d = *end + 1;
  double den = strtod(d, end);
  if (*end == d || errno || !isfinite(den) || !(den > 0)) return 0;
  *x /= den;
  return isfinite(*x);
}

int cli_errors(cli_args *a, const char *v, double *out, int max) {
  int n = 0;
  const char *s = v;
  while (*s) {
    char *e;
    double x;
    if (!number_or_fraction(s, &e, &x) || (*e && *e != ',')) {
      fail(a, "--errors: '%s' is not a list of numbers or fractions like 1/1024,1/256", v);
      return 0;
    }
    if (n >= max) {
      fail(a, "--errors: more than %d targets", max);
      return 0;
    }
    if (!(x >= CLI_ERRORS_MIN && x <= 1)) {
      fail(a, "--errors: %g is outside [%g, 1] (a fraction of the model's extent)", x, CLI_ERRORS_MIN);
      return 0;
    }
    if (n && !(x > out[n - 1])) {
      fail(a, "--errors: the targets must rise (%g after %g)", x, out[n - 1]);
      return 0;
    }
    out[n++] = x;
    if (!*e) break;
    s = e + 1;
  }
  if (n == 0) fail(a, "--errors: an empty list");
  return n;
}

/* ---- common ---- */

const char *const cli_common_help =
    "  --json FILE|-       also write the JSON report there (- for stdout)\n"
    "  --timings           add wall-clock times to the report (they vary run to run)\n"
    "  --threads N         worker threads (results do not depend on it)\n"
    "  --quiet, -q         nothing on stderr but errors\n";

int cli_common_opt(cli_args *a, cli_common *c) {
  const char *v;
  if (cli_opt(a, "--json", &v)) {
    c->json_path = v;
  } else if (cli_flag(a, "--quiet") || cli_flag(a, "-q")) {
    c->quiet = 1;
  } else if (cli_flag(a, "--timings")) {
    c->timings = 1;
  } else if (cli_opt(a, "--threads", &v)) {
    c->threads = cli_int(a, "--threads", v, 1, 1024);
    /* every parallel region of the run, the library's included, uses n */
    if (!a->bad) omp_set_num_threads(c->threads);
  } else {
    return 0;
  }
  return 1;
}

/* ---- display ---- */

const char *const cli_display_help =
    "display (how the viewer sees the image; an explicit quantity wins over the preset's):\n"
    "  --display NAME      standard-fhd (default: 24\" 1920x1080 at 60 cm, 200 cd/m2),\n"
    "                      standard-4k, phone, laptop, vr\n"
    "  --ppd N             pixels per degree of visual angle\n"
    "  --peak CDM2         luminance of white, cd/m2\n"
    "  --black CDM2        luminance of black, cd/m2 (default peak/1000)\n"
    "  --ambient LUX       room illuminance on the screen (default 0: dark room)\n"
    "  --reflectivity K    fraction of ambient light reflected (default 0.005)\n"
    "  --exr-scale S       cd/m2 per unit of EXR/HDR input values (default 1)\n"
    CLI_TASK_HELP;

/* --task: its own parser, for the commands that judge without the display
 * options (lod, whose displays are its --screens) */
int cli_task_opt(cli_args *a, jnd_viewing_task *t) {
  const char *v;
  if (!cli_opt(a, "--task", &v)) return 0;
  if (!a->bad && jnd_viewing_task_parse(v, t) != JND_OK) fail(a, "--task: %s", jnd_last_error());
  return 1;
}

enum { D_PPD, D_PEAK, D_BLACK, D_AMBIENT, D_REFL, D_EXR, D_N };

void cli_display_init(cli_display *d) {
  memset(d, 0, sizeof *d);
  jnd_display_defaults(&d->preset);
}

int cli_display_opt(cli_args *a, cli_display *d) {
  static const struct {
    const char *name;
    double lo, hi;
  } q[D_N] = {{"--ppd", 1, 1000},         {"--peak", 0.01, 100000},   {"--black", 0, 10000},
              {"--ambient", 0, 200000},   {"--reflectivity", 0, 1},   {"--exr-scale", 1e-9, 1e9}};
  const char *v;
  if (cli_opt(a, "--display", &v)) {
    if (!a->bad && jnd_display_preset(v, &d->preset) != JND_OK) fail(a, "--display: %s", jnd_last_error());
    return 1;
  }
  if (cli_task_opt(a, &d->task)) {
    d->task_given = 1;
    return 1;
  }
  for (int k = 0; k < D_N; k++)
    if (cli_opt(a, q[k].name, &v)) {
      d->value[k] = cli_double(a, q[k].name, v, q[k].lo, q[k].hi);
      d->given |= 1u << k;
      return 1;
    }
  return 0;
}

jnd_display cli_display_get(const cli_display *d) {
  jnd_display r = d->preset;
  if (d->given & (1u << D_PPD)) {
    r.ppd = d->value[D_PPD];
    r.diagonal_in = r.distance_m = 0;   /* the geometry no longer gives the ppd */
    r.width_px = r.height_px = 0;
  }
  if (d->given & (1u << D_PEAK)) {
    /* a black level that was the preset's peak/1000 follows the new peak */
    if (!(d->given & (1u << D_BLACK)) && fabs(r.black_cdm2 - r.peak_cdm2 / 1000) < 1e-12)
      r.black_cdm2 = d->value[D_PEAK] / 1000;
    r.peak_cdm2 = d->value[D_PEAK];
  }
  if (d->given & (1u << D_BLACK)) r.black_cdm2 = d->value[D_BLACK];
  if (d->given & (1u << D_AMBIENT)) r.ambient_lux = d->value[D_AMBIENT];
  if (d->given & (1u << D_REFL)) r.reflectivity = d->value[D_REFL];
  if (d->given & (1u << D_EXR)) r.exr_scale = d->value[D_EXR];
  if (d->task_given) r.task = d->task;
  return r;
}

int cli_display_exr_scale_given(const cli_display *d) { return (d->given & (1u << D_EXR)) != 0; }

/* ---- views ---- */

/* The limits every rendering command shares. */
#define VIEWS_MAX JND_VIEWS_MAX   /* jnd.h: the libraries' limit too */
#define VIEW_SIZE_MIN 16      /* the vision model needs a few pyramid levels */
#define VIEW_SIZE_MAX 16384   /* the renderer's limit */

const char *const cli_views_help =
    "views (the same options and limits in every command that renders):\n"
    "  --views N           views on a Fibonacci spiral around the object (1..4096)\n"
    "  --seed S            seed of the spiral's rotation and of the lights (1)\n"
    "  --size WxH          image size in pixels (16..16384)\n"
    "  --coverage F        fraction of the image height the object's bounding sphere\n"
    "                      fills (0.8; 0.01..10)\n"
    "  --distance D        camera distance from the centre in object units (instead)\n"
    "  --fov DEG           vertical field of view (45; 0.1..179)\n"
    "  --elevation A,B     band of camera elevations in degrees (default -60,75; from\n"
    "                      +10 when the asset stands on a ground plane)\n"
    "  --lights N          directional key lights sampled per view (1; 0..8)\n"
    "  --light-intensity E their illuminance (2)\n"
    "  --cameras FILE      explicit cameras from JSON instead (docs/render.md)\n"
    "  --env FILE          equirectangular environment (.hdr/.exr; default: a studio)\n"
    "  --samples N         MSAA samples (4; 1..64)\n"
    "  --anisotropy N      anisotropic filtering (8; 1..16)\n"
    "  --platform P        EGL platform: auto (default), device, surfaceless\n"
    "  --map-size N        side of the builtin asset's maps (2048; 8..8192)\n";

void cli_views_init(cli_views *v, int width, int height) {
  memset(v, 0, sizeof *v);
  jnd_view_set_defaults(&v->set);
  v->set.render.width = width;
  v->set.render.height = height;
  v->map_size = 2048;
}

int cli_views_opt(cli_args *a, cli_views *v) {
  const char *s;
  jnd_view_sampling *vs = &v->set.sampling;
  jnd_renderer_params *rp = &v->set.render;
  if (cli_opt(a, "--views", &s)) {
    v->given |= CLI_VIEWS;
    vs->count = cli_int(a, "--views", s, 1, VIEWS_MAX);
  } else if (cli_opt(a, "--seed", &s)) {
    v->given |= CLI_SEED;
    vs->seed = (uint64_t)cli_double(a, "--seed", s, 0, 9007199254740992.0);
  } else if (cli_opt(a, "--size", &s)) {
    v->given |= CLI_SIZE;
    cli_size(a, "--size", s, VIEW_SIZE_MIN, VIEW_SIZE_MAX, &rp->width, &rp->height);
  } else if (cli_opt(a, "--coverage", &s)) {
    v->given |= CLI_COVERAGE;
    vs->coverage = cli_double(a, "--coverage", s, 0.01, 10);
  } else if (cli_opt(a, "--distance", &s)) {
    v->given |= CLI_DISTANCE;
    vs->distance = cli_double(a, "--distance", s, 1e-9, 1e12);
  } else if (cli_opt(a, "--fov", &s)) {
    v->given |= CLI_FOV;
    vs->fov_y_deg = cli_double(a, "--fov", s, 0.1, 179);
  } else if (cli_opt(a, "--elevation", &s)) {
    v->given |= CLI_ELEVATION;
    cli_pair(a, "--elevation", s, &vs->min_elevation_deg, &vs->max_elevation_deg);
    if (!a->bad && !(vs->min_elevation_deg >= -90 && vs->max_elevation_deg <= 90 &&
                     vs->min_elevation_deg <= vs->max_elevation_deg))
      fail(a, "--elevation: '%s' is not A,B with -90 <= A <= B <= 90 degrees", s);
  } else if (cli_opt(a, "--lights", &s)) {
    v->given |= CLI_LIGHTS;
    vs->lights = cli_int(a, "--lights", s, 0, JND_MAX_LIGHTS);
  } else if (cli_opt(a, "--light-intensity", &s)) {
    v->given |= CLI_LIGHT_INTENSITY;
    vs->light_intensity = cli_double(a, "--light-intensity", s, 0, 1e6);
  } else if (cli_opt(a, "--cameras", &s)) {
    v->given |= CLI_CAMERAS;
    v->cameras = v->set.cameras_path = s;
  } else if (cli_opt(a, "--env", &s)) {
    v->given |= CLI_ENV;
    rp->env_path = s;
  } else if (cli_opt(a, "--samples", &s)) {
    v->given |= CLI_SAMPLES;
    rp->samples = cli_int(a, "--samples", s, 1, 64);
  } else if (cli_opt(a, "--anisotropy", &s)) {
    v->given |= CLI_ANISOTROPY;
    rp->anisotropy = cli_int(a, "--anisotropy", s, 1, 16);
  } else if (cli_opt(a, "--platform", &s)) {
    v->given |= CLI_PLATFORM;
    if (strcmp(s, "auto") && strcmp(s, "device") && strcmp(s, "surfaceless"))
      fail(a, "--platform: '%s' is not auto, device or surfaceless", s);
    rp->platform = s;
  } else if (cli_opt(a, "--map-size", &s)) {
    v->given |= CLI_MAP_SIZE;
    v->map_size = cli_int(a, "--map-size", s, 8, 8192);
  } else {
    return 0;
  }
  return 1;
}

static const char *const views_names[] = {"--views", "--seed", "--size", "--coverage", "--distance",
                                           "--fov", "--elevation", "--lights", "--light-intensity", "--cameras",
                                           "--env", "--samples", "--anisotropy", "--platform", "--map-size"};
_Static_assert(sizeof views_names / sizeof *views_names == 15 && CLI_MAP_SIZE == 1u << 14,
               "views_names[k] names the option of bit k of cli_views.given");

int cli_views_only(const cli_views *v, unsigned allowed, const char *cmd, const char *why) {
  for (unsigned k = 0; k < sizeof views_names / sizeof *views_names; k++)
    if ((v->given & ~allowed) & (1u << k)) return cli_bad("%s: %s does not apply (%s)", cmd, views_names[k], why);
  return 0;
}

/* ---- criterion, pooling ---- */

const char *const cli_criterion_help =
    "criterion (000 §9: at most a fraction Q of the views above P):\n"
    "  --p P               a view is above when its pooled probability of detection\n"
    "                      exceeds P (0.2)\n"
    "  --q Q               at most this fraction of the views may be above (0.1)\n"
    "  --pool pNN          pooling percentile of P over the object (p93, 000 §6)\n"
    "  --calibration FILE  a `jnd calibrate` file: pooling and JND transform (000 §7)\n";

int cli_criterion_opt(cli_args *a, jnd_criterion *c) {
  const char *v;
  if (cli_opt(a, "--p", &v)) {
    c->p = cli_double(a, "--p", v, 1e-6, 1 - 1e-6);
  } else if (cli_opt(a, "--q", &v)) {
    c->q = cli_double(a, "--q", v, 0, 0.999);
  } else {
    return 0;
  }
  return 1;
}

int cli_calibration_opt(cli_args *a, cli_calibration *c) {
  const char *v;
  if (cli_opt(a, "--pool", &v)) {
    c->pool = v;
  } else if (cli_opt(a, "--calibration", &v)) {
    c->path = v;
  } else {
    return 0;
  }
  return 1;
}

int cli_calibration_get(const cli_calibration *c, jnd_calibration *out) {
  jnd_calibration_defaults(out);
  if (c->path && jnd_calibration_load(c->path, out) != JND_OK) {
    cli_error("%s", jnd_last_error());
    return 0;
  }
  if (c->pool) {
    jnd_pooling pool;
    if (jnd_pooling_parse(c->pool, &pool) != JND_OK || pool.kind != JND_POOL_PERCENTILE) {
      cli_error("--pool: '%s' is not a percentile like p93", c->pool);
      return 0;
    }
    out->percentile = pool.percentile;
  }
  return 1;
}
