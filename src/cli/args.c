/* Argument parsing helpers and messages shared by the subcommands. */
#include <errno.h>
#include <math.h>
#include <omp.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

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

void cli_info(const cli_common *c, const char *fmt, ...) {
  if (c && c->quiet) return;
  va_list ap;
  va_start(ap, fmt);
  vfprintf(stderr, fmt, ap);
  va_end(ap);
}

int cli_unknown(const char *cmd, const char *arg) {
  if (arg[0] == '-')
    cli_error("%s: unknown option '%s' (jnd %s --help lists the options)", cmd, arg, cmd);
  else
    cli_error("%s: unexpected argument '%s' (jnd %s --help)", cmd, arg, cmd);
  return EXIT_BAD;
}

int cli_flag(char **argv, int i, const char *name) { return strcmp(argv[i], name) == 0; }

int cli_opt(int argc, char **argv, int *i, const char *name, const char **val) {
  const char *a = argv[*i];
  size_t n = strlen(name);
  if (strncmp(a, name, n) != 0) return 0;
  if (a[n] == '=') {
    *val = a + n + 1;
    return 1;
  }
  if (a[n] != 0) return 0;
  if (*i + 1 >= argc) {
    cli_error("%s needs a value", name);
    exit(EXIT_BAD);
  }
  *val = argv[++*i];
  return 1;
}

double cli_double(const char *cmd, const char *opt, const char *v, double lo, double hi) {
  char *end;
  errno = 0;
  double d = strtod(v, &end);
  if (end == v || *end || errno || !isfinite(d)) {
    cli_error("%s: %s: '%s' is not a number", cmd, opt, v);
    exit(EXIT_BAD);
  }
  if (d < lo || d > hi) {
    cli_error("%s: %s: %g is outside [%g, %g]", cmd, opt, d, lo, hi);
    exit(EXIT_BAD);
  }
  return d;
}

int cli_threads(const char *cmd, const char *v) {
  int n = cli_int(cmd, "--threads", v, 1, 1024);
  /* every parallel region of the run, the library's included, uses n */
  omp_set_num_threads(n);
  return n;
}

int cli_int(const char *cmd, const char *opt, const char *v, int lo, int hi) {
  char *end;
  errno = 0;
  long d = strtol(v, &end, 10);
  if (end == v || *end || errno) {
    cli_error("%s: %s: '%s' is not an integer", cmd, opt, v);
    exit(EXIT_BAD);
  }
  if (d < lo || d > hi) {
    cli_error("%s: %s: %ld is outside [%d, %d]", cmd, opt, d, lo, hi);
    exit(EXIT_BAD);
  }
  return (int)d;
}

void cli_pair(const char *cmd, const char *opt, const char *v, double *a, double *b) {
  char *end;
  errno = 0;
  *a = strtod(v, &end);
  if (end == v || (*end != ',' && *end != 'x') || errno) goto bad;
  const char *s = end + 1;
  *b = strtod(s, &end);
  if (end == s || *end || errno || !isfinite(*a) || !isfinite(*b)) goto bad;
  return;
bad:
  cli_error("%s: %s: '%s' is not a pair of numbers like 10,20", cmd, opt, v);
  exit(EXIT_BAD);
}

double cli_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

const char *const cli_display_help =
    "display (how the viewer sees the image):\n"
    "  --display NAME      standard-fhd (default: 24\" 1920x1080 at 60 cm, 200 cd/m2),\n"
    "                      standard-4k, phone, laptop, vr\n"
    "  --ppd N             pixels per degree of visual angle (overrides the preset's)\n"
    "  --peak CDM2         luminance of white, cd/m2\n"
    "  --black CDM2        luminance of black, cd/m2 (default peak/1000)\n"
    "  --ambient LUX       room illuminance on the screen (default 0: dark room)\n"
    "  --reflectivity K    fraction of ambient light reflected (default 0.005)\n"
    "  --exr-scale S       cd/m2 per unit of EXR/HDR input values (default 1)\n";

int cli_common_opt(int argc, char **argv, int *i, cli_common *c) {
  const char *v;
  if (cli_opt(argc, argv, i, "--json", &v)) {
    c->json_path = v;
    return 1;
  }
  if (cli_flag(argv, *i, "--quiet") || cli_flag(argv, *i, "-q")) {
    c->quiet = 1;
    return 1;
  }
  return 0;
}

int cli_display_opt(const char *cmd, int argc, char **argv, int *i, jnd_display *d) {
  const char *v;
  if (cli_opt(argc, argv, i, "--display", &v)) {
    double ppd = d->ppd;
    (void)ppd;
    if (jnd_display_preset(v, d) != JND_OK) {
      cli_error("%s: --display: %s", cmd, jnd_last_error());
      exit(EXIT_BAD);
    }
    return 1;
  }
  if (cli_opt(argc, argv, i, "--ppd", &v)) {
    d->ppd = cli_double(cmd, "--ppd", v, 1, 1000);
    d->diagonal_in = d->distance_m = 0;
    return 1;
  }
  if (cli_opt(argc, argv, i, "--peak", &v)) {
    double old = d->peak_cdm2;
    d->peak_cdm2 = cli_double(cmd, "--peak", v, 0.01, 100000);
    if (fabs(d->black_cdm2 - old / 1000) < 1e-12) d->black_cdm2 = d->peak_cdm2 / 1000;
    return 1;
  }
  if (cli_opt(argc, argv, i, "--black", &v)) {
    d->black_cdm2 = cli_double(cmd, "--black", v, 0, 10000);
    return 1;
  }
  if (cli_opt(argc, argv, i, "--ambient", &v)) {
    d->ambient_lux = cli_double(cmd, "--ambient", v, 0, 200000);
    return 1;
  }
  if (cli_opt(argc, argv, i, "--reflectivity", &v)) {
    d->reflectivity = cli_double(cmd, "--reflectivity", v, 0, 1);
    return 1;
  }
  if (cli_opt(argc, argv, i, "--exr-scale", &v)) {
    d->exr_scale = cli_double(cmd, "--exr-scale", v, 1e-9, 1e9);
    return 1;
  }
  return 0;
}

int cli_mkdir_p(const char *dir) {
  char buf[4096];
  snprintf(buf, sizeof buf, "%s", dir);
  for (char *p = buf + 1; *p; p++)
    if (*p == '/') {
      *p = 0;
      if (mkdir(buf, 0777) != 0 && errno != EEXIST) return 0;
      *p = '/';
    }
  if (mkdir(buf, 0777) != 0 && errno != EEXIST) return 0;
  struct stat st;
  return stat(buf, &st) == 0 && S_ISDIR(st.st_mode);
}
