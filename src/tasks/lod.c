/* jnd lod as one call (jnd_lod_analyse; jnd_lod_run writes its outputs):
 *  1. the asset and its chain of levels (jnd_scene_open, jnd_scene_lod_chain:
 *     made, imported or the given files);
 *  2. 003's analysis per screen (jnd_poi_analyse, lod_poi.c);
 *  3. the perceptual choice and switch distances per screen, the screens in
 *     parallel (jnd_lod_switch_analyse, lod_switch.c; judge_screens below);
 *  4. the switch coverages written into the model (MSFT_screencoverage):
 *     the perceptual switch distances of the first screen, or
 *     meshoptimizer's error-to-pixels rule without them.
 * The Pareto plot of 003's curves is here too (jnd_poi_pareto_plot). */
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "io/draw.h"
#include "jnd.h"
#include "scene/scene.h"
#include "tasks/tasks.h"
#include "vision/vision.h"


/* MSFT_screencoverage from the perceptual switch distances of one screen:
 * level k is shown while the sphere fills more of the screen than where
 * level k + 1 may take over (its switch coverage, a fraction of the
 * height), written as Babylon.js's screen coverage like coverage_rule(). */
static void coverage_switch(const jnd_lod_switch_result *w, int nscreens, double *cov, char *rule, size_t nrule) {
  const jnd_poi_screen *ref = &w->screen;
  double prev = 1;
  for (int k = 0; k < w->nlevels; k++) {
    double h = k + 1 < w->nlevels ? fmin(w->switch_coverage[k + 1], 1.0) : 0;
    double c = M_PI * h * h * ref->height_px / (4.0 * ref->width_px);
    if (c > prev) c = prev;
    cov[k] = c;
    prev = c;
  }
  snprintf(rule, nrule, "perceptual switch distances on %s (%dx%d), the first of %d screen%s (a model holds one "
           "screen's coverages), as projected sphere area over screen area", ref->name, ref->width_px, ref->height_px,
           nscreens, nscreens == 1 ? "" : "s");
}

void jnd_model_stem(const char *model_path, char *out, size_t n) {
  const char *base = strrchr(model_path, '/');
  snprintf(out, n, "%s", base ? base + 1 : model_path);
  char *dot = strrchr(out, '.');
  if (dot && dot != out) *dot = 0;
  for (char *q = out; *q; q++)
    if (*q == ':' || *q == ',' || *q == '=') *q = '_';
}

/* ---- jnd lod as one call ---- */

void jnd_lod_run_defaults(jnd_lod_run_params *p) {
  memset(p, 0, sizeof *p);
  jnd_lod_defaults(&p->chain);
  jnd_poi_defaults(&p->poi);
  p->analyse = 1;
  p->perceptual = 1;
  jnd_lod_switch_defaults(&p->sw);
  jnd_run_options_defaults(&p->run);
  p->run.map_size = 512;
}

void jnd_lod_result_clear(jnd_lod_result *r) {
  if (!r) return;
  jnd_scene_free(r->scene);
  jnd_poi_result_free(&r->poi);
  for (int i = 0; i < r->nsw && r->sw; i++) jnd_lod_switch_result_free(&r->sw[i]);
  free(r->sw);
  free(r->report);
  memset(r, 0, sizeof *r);
}

void jnd_lod_result_free(jnd_lod_result *r) {
  jnd_lod_result_clear(r);
  free(r);
}

/* MSFT_screencoverage until the perceptual switch distances exist:
 * meshoptimizer's error-to-pixels rule on the reference screen. Level k may
 * be shown once its error covers at most `px` pixels, i.e. while the
 * bounding sphere's diameter spans at most c_k = 2R·px / (e_k·H) of the
 * screen's height; level k − 1 gives way to level k there. Written as
 * Babylon.js's screen coverage: the sphere's projected area over the
 * screen's, π c² H / (4 W). */
static void coverage_rule(const jnd_scene *s, const jnd_poi_screen *ref, int nscreens, double px,
                          const double *err_abs, double *cov, char *rule, size_t nrule) {
  int n = jnd_scene_lod_count(s);
  double centre[3], radius;
  jnd_scene_bounds(s, centre, &radius);
  double prev = 1;
  for (int k = 0; k < n; k++) {
    double c = 0;
    if (k + 1 < n) {
      double e = err_abs[k + 1];
      double h = e > 0 ? 2 * radius * px / (e * ref->height_px) : 1;   /* height fraction */
      if (h > 1) h = 1;
      c = M_PI * h * h * ref->height_px / (4.0 * ref->width_px);
    }
    if (c > prev) c = prev;
    cov[k] = c;
    prev = c;
  }
  snprintf(rule, nrule, "meshoptimizer's error <= %g px on %s (%dx%d), %s, as projected sphere area over screen area",
           px, ref->name, ref->width_px, ref->height_px,
           nscreens > 1 ? "the first of the screens (a model holds one screen's coverages)" : "the screen");
}

/* ---- the perceptual step's screens, in parallel ----
 *
 * The screens are independent, and one screen's judging keeps about one core
 * busy on a CPU rasteriser: a small window's rendering is mostly the
 * triangles' setup on the calling thread, and the model runs one thread
 * beside the rasteriser's. So `threads` workers (0: the cores), each with a
 * twin of the scene (its own level shown; jnd_scene_twin) and a renderer of
 * its own, which every judge of its screens borrows and sizes to its
 * window, take the screens in order as they become free: the screens' costs
 * differ by a third (teapot_100k: 92 to 127 renderings), and handed out w,
 * w + W, ... in advance one worker idled while the other finished its
 * second screen (docs/speed.md, item 4). A screen's result depends on the
 * screen alone, so the report is the same for every thread count and every
 * order of taking; an error is the first failing screen's, in screen
 * order. */
typedef struct {
  jnd_scene *scene;                  /* the run's (worker 0 without the analysis beside) or a twin */
  const jnd_poi_screen *screens;     /* n */
  int n;
  const jnd_lod_switch_params *sp;
  const jnd_lod_run_params *p;
  jnd_lod_result *out;
  int *next;                         /* the next screen to take (under lock) */
  jnd_status *status;                /* per screen */
  char (*error)[512];                /* per screen: its message */
  pthread_mutex_t *lock;             /* next, held, the progress callback and its count */
  int *done;
  int *held;                         /* nonzero while the analysis beside reports its own progress */
} screen_worker;

/* the next screen no worker has taken, or n when none is left */
static int take_screen(screen_worker *w) {
  pthread_mutex_lock(w->lock);
  int i = *w->next < w->n ? (*w->next)++ : w->n;
  pthread_mutex_unlock(w->lock);
  return i;
}

static void *judge_screen_worker(void *arg) {
  screen_worker *w = arg;
  jnd_lod_switch_params sp = *w->sp;
  jnd_renderer *r = NULL;
  jnd_status st = JND_OK;
  if (!sp.judge.renderer) {
    /* each judge sizes it */
    if (!(st = judge_renderer(&sp.judge.views.render, 64, &r))) sp.judge.renderer = r;
  }
  for (int i; (i = take_screen(w)) < w->n;) {
    if (!st) st = jnd_lod_switch_analyse(w->scene, &w->screens[i], &sp, &w->out->sw[i]);
    w->status[i] = st;
    if (st) {
      snprintf(w->error[i], sizeof w->error[i], "%s", jnd_last_error());
      continue;   /* the worker's later screens fail with it */
    }
    pthread_mutex_lock(w->lock);
    ++*w->done;
    if (w->p->progress && !*w->held) w->p->progress(w->p->progress_user, "perceptual choice", *w->done, w->n);
    pthread_mutex_unlock(w->lock);
  }
  jnd_renderer_free(r);
  return NULL;
}

/* The screens judged by the workers. With poi (003's analysis's
 * parameters, poi_check passed), every worker is on a twin and a thread of
 * its own while this thread runs the analysis into out->poi, with its own
 * progress, the screens' held back until it returns; its error, if any, is
 * the one returned (it comes first in the run's order). */
static jnd_status judge_screens(jnd_scene *s, const jnd_poi_screen *screens, int n, const jnd_lod_switch_params *sp,
                                const jnd_lod_run_params *p, jnd_lod_result *out, const jnd_poi_params *poi) {
  int nw = jnd_threads(p->threads);
  if (nw > n) nw = n;
  if (nw > LOD_MAX_SCREENS) nw = LOD_MAX_SCREENS;
  /* a lent renderer is one GL context: one thread */
  if (sp->judge.renderer || nw < 1) nw = 1;
  jnd_status status[LOD_MAX_SCREENS];
  char error[LOD_MAX_SCREENS][512];
  screen_worker w[LOD_MAX_SCREENS];
  pthread_t tid[LOD_MAX_SCREENS];
  int started[LOD_MAX_SCREENS] = {0}, done = 0, next = 0, held = poi != NULL;
  pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
  if (n > LOD_MAX_SCREENS) return jnd_fail(JND_ERR_ARG, "lod: %d screens (at most %d)", n, LOD_MAX_SCREENS);
  for (int i = 0; i < n; i++) status[i] = JND_OK, error[i][0] = 0;
  if (p->progress && !held) p->progress(p->progress_user, "perceptual choice", 0, n);
  jnd_status st = JND_OK;
  memset(w, 0, sizeof w);
  /* without the analysis, worker 0 is this thread, on the run's scene */
  const int first = poi ? 0 : 1;
  for (int k = 0; k < nw; k++) {
    w[k] = (screen_worker){k < first ? s : jnd_scene_twin(s), screens, n, sp, p, out, &next, status, error, &lock,
                           &done, &held};
    if (!w[k].scene) {
      st = jnd_fail(JND_ERR_NOMEM, "lod: out of memory");
      break;
    }
    if (k >= first && pthread_create(&tid[k], NULL, judge_screen_worker, &w[k]) == 0) started[k] = 1;
  }
  jnd_status bst = JND_OK;
  char berr[512] = "";
  if (poi) {
    if ((bst = jnd_poi_analyse(s, poi, &out->poi))) snprintf(berr, sizeof berr, "%s", jnd_last_error());
    pthread_mutex_lock(&lock);
    held = 0;
    if (p->progress && !bst) p->progress(p->progress_user, "perceptual choice", done, n);
    pthread_mutex_unlock(&lock);
  } else if (!st) {
    judge_screen_worker(&w[0]);
  }
  for (int k = first; k < nw; k++) {
    if (started[k]) pthread_join(tid[k], NULL);
    else if (!st && w[k].scene) judge_screen_worker(&w[k]);   /* no thread: on this one */
    if (w[k].scene) jnd_scene_free(w[k].scene);
  }
  jnd_scene_lod_select(s, 0);
  if (bst) return jnd_fail(bst, "%s", berr);
  if (st) return st;
  for (int i = 0; i < n; i++)
    if (status[i]) return jnd_fail(status[i], "%s", error[i]);
  return JND_OK;
}

jnd_status jnd_lod_analyse(const char *model_path, const jnd_lod_run_params *p, jnd_lod_result *out) {
  jnd_lod_run_params d;
  if (!p) {
    jnd_lod_run_defaults(&d);
    p = &d;
  }
  memset(out, 0, sizeof *out);
  jnd_status st;
  /* 003's parameters and screens refused before the asset is loaded and
   * its chain built (a chain of a large mesh takes seconds) */
  if (p->analyse) {
    jnd_poi_screen scr[LOD_MAX_SCREENS];
    int nscr = 0;
    if ((st = poi_params_check(&p->poi, scr, &nscr))) return st;
  }
  double t0 = jnd_seconds(), c0 = jnd_cpu_seconds();
  /* the asset and its chain */
  st = jnd_scene_open(model_path, p->run.map_size > 0 ? p->run.map_size : 512, &out->scene);
  if (st) return st;
  for (int i = 0; p->run.warning && i < jnd_scene_warning_count(out->scene); i++)
    p->run.warning(p->run.warning_user, jnd_scene_warning(out->scene, i));
  jnd_scene *s = out->scene;
  out->load_s = jnd_seconds() - t0;
  out->load_cpu_s = jnd_cpu_seconds() - c0;
  t0 = jnd_seconds();
  c0 = jnd_cpu_seconds();
  jnd_lod_chain_params cp = {&p->chain, p->rebuild, p->level_paths, p->nlevel_paths};
  if ((st = jnd_scene_lod_chain(s, model_path, &cp, &out->chain_source))) {
    jnd_lod_result_clear(out);
    return st;
  }
  int n = jnd_scene_lod_count(s);
  out->chain_s = jnd_seconds() - t0;
  out->chain_cpu_s = jnd_cpu_seconds() - c0;
  /* 003's analysis */
  double t1 = jnd_seconds(), c1 = jnd_cpu_seconds();
  if (p->analyse) {
    jnd_poi_params pp = p->poi;
    if (!pp.progress) {
      pp.progress = p->progress;
      pp.progress_user = p->progress_user;
    }
    jnd_poi_screen scr[LOD_MAX_SCREENS];
    int nscr = 0;
    if ((st = poi_check(s, &pp, scr, &nscr))) {
      jnd_lod_result_clear(out);
      return st;
    }
    /* the perceptual choice and switch distances, per screen: with two
     * threads or more, judged beside 003's analysis, which keeps two cores
     * only about 85 % busy (its renderings and its sums take turns), as
     * the screens' judges keep them about 75 % (docs/speed.md, item 4);
     * one thread does one, then the other */
    if (p->perceptual) {
      if (!(out->sw = jnd_calloc((size_t)nscr, sizeof *out->sw))) {
        jnd_lod_result_clear(out);
        return jnd_fail(JND_ERR_NOMEM, "%s: out of memory", model_path);
      }
      jnd_lod_switch_params sp = p->sw;
      sp.coverage = p->poi.coverage;
      jnd_view_sampling *vs = &sp.judge.views.sampling;
      vs->seed = p->poi.seed;
      if (p->poi.fov_y_deg > 0) vs->fov_y_deg = p->poi.fov_y_deg;
      vs->lights = p->poi.lights;
      sp.judge.views.render.env_path = p->poi.env_path;
      sp.judge.views.render.platform = p->poi.platform;
      out->nsw = nscr;
      if (jnd_threads(p->threads) >= 2 && !sp.judge.renderer) {
        st = judge_screens(s, scr, nscr, &sp, p, out, &pp);
      } else {
        st = jnd_poi_analyse(s, &pp, &out->poi);
        if (!st) st = judge_screens(s, scr, nscr, &sp, p, out, NULL);
      }
    } else {
      st = jnd_poi_analyse(s, &pp, &out->poi);
    }
    if (st) {
      jnd_lod_result_clear(out);
      return st;
    }
    out->analysed = 1;
  }
  out->analysis_s = jnd_seconds() - t1;
  out->analysis_cpu_s = jnd_cpu_seconds() - c1;
  /* the switch coverages of the model: each level's error in object units
   * (measured where meshoptimizer gives none) */
  double t2 = jnd_seconds();
  jnd_poi_screen ref;
  if (p->poi.screens && p->poi.nscreens > 0) ref = p->poi.screens[0];
  else jnd_poi_screen_parse("standard-fhd", &ref);
  double err[64];
  for (int k = 0; k < n && k < 64 && !st; k++) {
    jnd_lod_level_info li;
    if ((st = jnd_scene_lod_info(s, k, &li))) break;
    err[k] = li.error_abs;
    if (!isfinite(err[k])) {
      jnd_surface_distance dist;
      if (out->analysed) dist = out->poi.distance[k];
      else st = jnd_scene_lod_distance(s, k, 16384, 1, &dist);
      err[k] = dist.max;
    }
  }
  if (!st && out->nsw > 0)
    coverage_switch(&out->sw[0], out->nsw, out->coverage, out->coverage_rule, sizeof out->coverage_rule);
  else if (!st)
    coverage_rule(s, &ref, p->poi.screens ? p->poi.nscreens : 1, p->poi.meshopt_pixels > 0 ? p->poi.meshopt_pixels : 1,
                  err, out->coverage, out->coverage_rule, sizeof out->coverage_rule);
  out->write_s = jnd_seconds() - t2;   /* jnd_lod_run adds the writing */
  if (st) {
    jnd_lod_result_clear(out);
    return st;
  }
  return JND_OK;
}
