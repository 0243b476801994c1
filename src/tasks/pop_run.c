/* `jnd pop` as one call (jnd_pop_run): a pair of frames, a sequence of
 * them, or an asset's rendered switch (and switch table), predicted, then
 * the pictures, maps, tables and the report written through one output
 * writer. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "tasks/report.h"
#include "tasks/tasks.h"

void jnd_pop_run_defaults(jnd_pop_run_params *p) {
  memset(p, 0, sizeof *p);
  jnd_model_defaults(&p->model);
  jnd_pop_defaults(&p->pop);
  jnd_pop_sequence_defaults(&p->seq);
  jnd_pop_asset_defaults(&p->asset);
  p->max_regions = 100;
  p->fail_above = NAN;
  jnd_run_options_defaults(&p->run);
}

void jnd_pop_run_result_free(jnd_pop_run_result *r) {
  if (!r) return;
  jnd_pop_result_free(&r->frame);
  jnd_pop_sequence_free(&r->sequence);
  jnd_pop_asset_report_free(&r->asset);
  free(r->report);
  free(r);
}

/* every file the frame form reads, frame by frame for a sequence */
static jnd_status frame_inputs(report_output *o, const jnd_pop_run_params *p) {
  const jnd_pop_paths *f = &p->frames;
  const char *const pat[] = {f->actual, f->expected, f->displacement, f->displacement_expected, f->depth,
                             f->depth_expected, f->prev_depth, f->prev_depth_expected, f->weights, f->prev_color,
                             f->prev_shading, f->mask};
  const int np = (int)(sizeof pat / sizeof pat[0]);
  if (!p->sequence) return report_output_add_inputs(o, pat, np);
  jnd_status s = JND_OK;
  for (int i = p->seq.first; i <= p->seq.last && !s; i++)
    for (int k = 0; k < np && !s; k++) {
      char name[4200];
      /* a path without a field serves every frame: once; a malformed one jnd_pop_sequence refuses */
      int field = pat[k] ? jnd_frame_path(pat[k], i, name, sizeof name) : -1;
      if (field == 1 || (field == 0 && i == p->seq.first)) {
        const char *one[] = {name};
        s = report_output_add_inputs(o, one, 1);
      }
    }
  return s;
}

static jnd_status write_image(const char *dir, const char *name, const jnd_image *img, int exr) {
  char path[4400];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  const char *ch[1] = {exr == 2 ? "W" : "JND"};
  return exr ? jnd_image_write_exr(path, img, ch, 0) : jnd_image_write_png(path, img, 8);
}

/* the same table as OUT/frames.csv (an empty max_rating: no region) */
static jnd_status frames_csv(const char *dir, const jnd_pop_sequence_result *q) {
  size_t cap = 128 + (size_t)q->nrows * 160, n = 0;
  char *t = malloc(cap);
  if (!t) return jnd_fail(JND_ERR_NOMEM, "pop: out of memory");
  n += (size_t)snprintf(t + n, cap - n, "frame,max_rating,detection_score,regions,max_delta_e94,coverage\n");
  for (int i = 0; i < q->nrows; i++) {
    const jnd_pop_frame_row *w = &q->rows[i];
    char r[40] = "";
    if (isfinite(w->max_rating)) snprintf(r, sizeof r, "%.6f", w->max_rating);
    n += (size_t)snprintf(t + n, cap - n, "%d,%s,%d,%d,%.6f,%.6f\n", w->frame, r, w->detection_score, w->nregions,
                          w->max_delta_e94, w->coverage);
  }
  char path[4400];
  snprintf(path, sizeof path, "%s/frames.csv", dir);
  jnd_status s = jnd_write_file_atomic(path, t, n);
  free(t);
  return s;
}

/* the prediction: the asset's rendered switch, a sequence or a pair */
static jnd_status predict(jnd_model *m, const char *model, const jnd_pop_run_params *p, jnd_pop_asset_params *ap,
                          jnd_pop_run_result *R) {
  jnd_status s;
  if (model) {
    ap->pop = p->pop;
    ap->progress = p->progress;
    ap->progress_user = p->progress_user;
    s = jnd_pop_asset_run(m, model, ap, &R->asset);
    R->pair = &R->asset.pair;
  } else if (p->sequence) {
    jnd_pop_sequence_params seq = p->seq;
    seq.progress = p->progress;
    seq.progress_user = p->progress_user;
    s = jnd_pop_sequence(m, &p->frames, &seq, &p->pop, &R->sequence);
    R->pair = &R->sequence.worst_result;
  } else {
    s = jnd_pop_files(m, &p->frames, &p->pop, &R->frame);
    R->pair = &R->frame;
  }
  return s;
}

jnd_status jnd_pop_run(const char *model, const jnd_pop_run_params *pp, const char *out_dir,
                       jnd_pop_run_result **out) {
  *out = NULL;
  jnd_pop_run_params p;
  if (pp) p = *pp;
  else jnd_pop_run_defaults(&p);
  if (!out_dir) return jnd_fail(JND_ERR_ARG, "pop: give an output folder");
  if (!model && (!p.frames.actual || !p.frames.expected))
    return jnd_fail(JND_ERR_ARG, "pop: needs two frames, NEW and EXPECTED, or a MODEL");
  if (model && p.sequence) return jnd_fail(JND_ERR_ARG, "pop: a sequence of frames is for the frame form");
  p.model.display.task = JND_TASK_FLICKER;   /* pop_model_create's, so that the report says it */
  double t0 = jnd_seconds();
  jnd_pop_asset_params ap = p.asset;
  /* the outputs checked before any work, written staged, published at the end */
  const char *ins[66] = {model, ap.views.render.env_path, ap.cameras};
  int nin = 3;
  for (int i = 0; model && i < ap.nlevel_paths && nin < 66; i++) ins[nin++] = ap.level_paths[i];
  report_output o;
  memset(&o, 0, sizeof o);
  jnd_status s = jnd_output_open(&o.w);
  if (!s) s = report_output_add_inputs(&o, ins, nin);
  if (!s && !model) s = frame_inputs(&o, &p);
  if (!s) s = jnd_output_add_dir(o.w, out_dir, &o.dir);
  if (!s && p.run.report_path && strcmp(p.run.report_path, "-") != 0)
    s = jnd_output_add_file(o.w, p.run.report_path, &o.copy);
  jnd_model *m = NULL;
  cJSON *report = NULL;
  jnd_pop_run_result *R = NULL;
  if (!s && !(R = jnd_calloc(1, sizeof *R))) s = jnd_fail(JND_ERR_NOMEM, "pop: out of memory");
  if (!s && (s = pop_model_create(&p.model, &m))) s = jnd_fail(s, "pop: %s", jnd_last_error());
  if (!s) s = predict(m, model, &p, &ap, R);
  /* only now, with a result, is anything created */
  if (!s) s = jnd_make_dirs(o.dir);
  double t_write = jnd_seconds();
  const jnd_pop_result *pair = R ? R->pair : NULL;
  if (!s) s = write_image(o.dir, "regions.png", &pair->picture, 0);
  if (!s && p.maps) s = write_image(o.dir, "jnd.exr", &pair->jnd, 1);
  if (!s && p.maps && pair->weights.data) s = write_image(o.dir, "weights.exr", &pair->weights, 2);
  if (!s && model && ap.decide) s = write_image(o.dir, "switch.png", &R->asset.plot, 0);
  if (!s && p.sequence) s = frames_csv(o.dir, &R->sequence);
  if (!s) {
    R->above = isfinite(p.fail_above) && pair->nregions && pair->max_rating > p.fail_above;
    double timings[2] = {jnd_seconds() - t_write, jnd_seconds() - t0};
    report = pop_report(model, &p, &ap, R, p.run.timings ? timings : NULL);
  }
  s = REPORT_OUTPUT_FINISH(&o, s, report, "pop.json", R);
  if (!s) R->total_s = jnd_seconds() - t0;
  jnd_model_free(m);
  if (s) {
    jnd_pop_run_result_free(R);
    return s;
  }
  *out = R;
  return JND_OK;
}
