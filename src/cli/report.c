/* The JSON report every subcommand writes, and the progress bar. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli.h"

cJSON *cli_report_new(const char *command) {
  cJSON *r = cJSON_CreateObject();
  cJSON_AddStringToObject(r, "jnd_version", jnd_version());
  cJSON_AddStringToObject(r, "command", command);
  cJSON_AddObjectToObject(r, "inputs");
  cJSON_AddObjectToObject(r, "parameters");
  cJSON_AddObjectToObject(r, "result");
  return r;
}

cJSON *cli_report_section(cJSON *report, const char *name) {
  return cJSON_GetObjectItemCaseSensitive(report, name);
}

cJSON *cli_display_json(const jnd_display *d) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "name", d->name);
  cJSON_AddNumberToObject(o, "ppd", d->ppd);
  cJSON_AddNumberToObject(o, "peak_cdm2", d->peak_cdm2);
  cJSON_AddNumberToObject(o, "black_cdm2", d->black_cdm2);
  cJSON_AddNumberToObject(o, "ambient_lux", d->ambient_lux);
  cJSON_AddNumberToObject(o, "reflectivity", d->reflectivity);
  cJSON_AddNumberToObject(o, "exr_scale", d->exr_scale);
  cJSON_AddStringToObject(o, "task", jnd_viewing_task_name(d->task));
  if (d->diagonal_in > 0) {
    cJSON_AddNumberToObject(o, "diagonal_in", d->diagonal_in);
    cJSON_AddNumberToObject(o, "width_px", d->width_px);
    cJSON_AddNumberToObject(o, "height_px", d->height_px);
    cJSON_AddNumberToObject(o, "distance_m", d->distance_m);
  }
  return o;
}

int cli_report_write(cJSON *report, const char *path) {
  char *text = cJSON_Print(report);
  if (!text) {
    cli_error("out of memory writing the JSON report");
    return EXIT_BAD;
  }
  size_t n = strlen(text);
  int rc = EXIT_OK;
  if (strcmp(path, "-") == 0) {
    fwrite(text, 1, n, stdout);
    fputc('\n', stdout);
    fflush(stdout);
  } else {
    char *t2 = malloc(n + 2);
    if (!t2) {
      free(text);
      cli_error("out of memory");
      return EXIT_BAD;
    }
    memcpy(t2, text, n);
    t2[n] = '\n';
    if (jnd_write_file_atomic(path, t2, n + 1) != JND_OK) {
      cli_error("%s", jnd_last_error());
      rc = EXIT_BAD;
    }
    free(t2);
  }
  free(text);
  return rc;
}

int cli_report_print(const char *text, const char *path) {
  if (!path || strcmp(path, "-") != 0) return EXIT_OK;
  fputs(text, stdout);
  fflush(stdout);
  return ferror(stdout) ? cli_bad("standard output: cannot write the report") : EXIT_OK;
}

static void run_warning(void *user, const char *line) { cli_info(user, "jnd: warning: %s\n", line); }

void cli_run_options(jnd_run_options *o, const cli_common *c, int map_size) {
  o->map_size = map_size;
  o->report_path = c->json_path;
  o->timings = c->timings;
  o->warning = run_warning;
  o->warning_user = (void *)c;
}

int cli_out_open(jnd_output **w) {
  return jnd_output_open(w) == JND_OK ? EXIT_OK : cli_lib_error();
}

int cli_out_inputs(jnd_output *w, const char *const *paths, int n) {
  for (int k = 0; k < n; k++) {
    if (!paths[k]) continue;
    char **files = NULL;
    int count = 0;
    if (jnd_asset_files(paths[k], &files, &count) != JND_OK) return cli_lib_error();
    jnd_status s = JND_OK;
    for (int f = 0; f < count && s == JND_OK; f++) s = jnd_output_add_input(w, files[f]);
    jnd_asset_files_free(files, count);
    if (s != JND_OK) return cli_lib_error();
  }
  return EXIT_OK;
}

int cli_out_file(jnd_output *w, const char *path, const char **staged) {
  *staged = NULL;
  if (!path) return EXIT_OK;
  return jnd_output_add_file(w, path, staged) == JND_OK ? EXIT_OK : cli_lib_error();
}

int cli_out_dir(jnd_output *w, const char *path, const char **staged) {
  *staged = NULL;
  if (!path) return EXIT_OK;
  return jnd_output_add_dir(w, path, staged) == JND_OK ? EXIT_OK : cli_lib_error();
}

int cli_out_end(jnd_output *w, int rc) {
  if (w && (rc == EXIT_OK || rc == EXIT_ABOVE) && jnd_output_commit(w) != JND_OK) rc = cli_lib_error();
  jnd_output_free(w);
  return rc;
}

void cli_progress_start(cli_progress *p, const cli_common *c, const char *label, int total) {
  p->enabled = !(c && c->quiet);
  p->tty = isatty(2);
  p->total = total > 0 ? total : 1;
  p->done = 0;
  p->label = label;
  p->t0 = jnd_seconds();
}

double cli_progress_eta(const cli_progress *p) {
  return p->done > 0 ? (jnd_seconds() - p->t0) * (p->total - p->done) / p->done : 0;
}

void cli_progress_count(cli_progress *p, int done) {
  p->done = done;
  if (!p->enabled) return;
  double el = jnd_seconds() - p->t0;
  if (done >= p->total)
    fprintf(stderr, "jnd %s: %d/%d done in %.0f s\n", p->label, done, p->total, el);
  else if (done == 0)
    fprintf(stderr, "jnd %s: 0/%d done\n", p->label, p->total);
  else
    fprintf(stderr, "jnd %s: %d/%d done in %.0f s, about %.0f s left\n", p->label, done, p->total, el,
            cli_progress_eta(p));
  fflush(stderr);
}

/* a bar on a terminal only: a log gets the stage lines instead */
void cli_progress_step(cli_progress *p, int done) {
  p->done = done;
  if (!p->enabled || !p->tty) return;
  if (done > p->total) p->total = done;
  int width = 30, filled = (int)((double)width * done / p->total);
  double el = jnd_seconds() - p->t0, eta = cli_progress_eta(p);
  fprintf(stderr, "\r%-12s [", p->label);
  for (int k = 0; k < width; k++) fputc(k < filled ? '#' : '.', stderr);
  fprintf(stderr, "] %d/%d  %.0fs, ~%.0fs left ", done, p->total, el, eta);
  fflush(stderr);
}

void cli_progress_line(cli_progress *p, const char *line) {
  if (!p->enabled) return;
  if (p->tty) fprintf(stderr, "\r%*s\r", 80, "");
  fprintf(stderr, "jnd %s: %s (%.1f s)\n", p->label, line, jnd_seconds() - p->t0);
  fflush(stderr);
  if (p->tty) cli_progress_step(p, p->done);
}

void cli_progress_end(cli_progress *p) {
  if (p->enabled && p->tty) fprintf(stderr, "\r%*s\r", 80, "");
}

void cli_progress_callback(void *user, const char *line, int done, int total) {
  cli_progress *p = user;
  if (total > p->total) p->total = total;
  if (line) {
    p->done = done;
    cli_progress_line(p, line);
  } else {
    cli_progress_step(p, done);
  }
}
