/* `jnd diff` as one call (jnd_diff_run): two images read, compared on the
 * display, the map, the heatmap and the report written through one output
 * writer. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "io/io.h"
#include "tasks/report.h"
#include "tasks/tasks.h"
#include "vision/vision.h"

/* An EXR/HDR's values are cd/m² × the display's exr_scale (1 by default).
 * A file whose brightest pixel is a few units at most was more likely
 * written relative (1 = white), and at the default scale its white would be
 * 1 cd/m², where the eye sees little: said in one warning, once per file. */
#define EXR_RELATIVE_MAX 10.0

void jnd_diff_defaults(jnd_diff_params *p) {
  memset(p, 0, sizeof *p);
  jnd_model_defaults(&p->model);
  jnd_pooling_parse("p93", &p->pool);
  p->fail_above = -1;
  jnd_run_options_defaults(&p->run);
}

void jnd_diff_result_free(jnd_diff_result *r) {
  if (!r) return;
  free(r->report);
  free(r);
}

/* a linear file read as cd/m² whose brightest pixel says it was meant relative */
static void exr_scale_warn(const jnd_diff_params *p, const char *path, const jnd_image *img,
                           const jnd_image_info *info) {
  if (!p->run.warning || info->encoding != JND_ENCODING_LINEAR || p->exr_scale_given || !img->data) return;
  size_t n = (size_t)img->w * img->h;
  const float *r = jnd_image_plane(img, 0), *g = img->c >= 3 ? jnd_image_plane(img, 1) : r,
              *b = img->c >= 3 ? jnd_image_plane(img, 2) : r;
  double top = 0;
  for (size_t i = 0; i < n; i++) {
    double y = 0.2126 * r[i] + 0.7152 * g[i] + 0.0722 * b[i];
    if (y > top) top = y;
  }
  if (top > EXR_RELATIVE_MAX) return;
  char line[4400];
  snprintf(line, sizeof line,
           "%s: its brightest pixel is %.3g, read as cd/m2 (--exr-scale 1): if 1 means white, give --exr-scale the "
           "display's white in cd/m2 (e.g. %g)",
           path, top, p->model.display.peak_cdm2);
  p->run.warning(p->run.warning_user, line);
}

/* the reference as a display signal for the heatmap's grey backdrop: a
 * linear file as the display shows it (scaled to its peak, sRGB-encoded) */
static jnd_status heatmap_backdrop(const char *path, const jnd_display *d, jnd_image *out) {
  jnd_image_info info;
  jnd_status st = jnd_image_read(path, out, &info);
  if (st || info.encoding != JND_ENCODING_LINEAR) return st;
  size_t n = (size_t)out->w * out->h * out->c;
  for (size_t i = 0; i < n; i++) out->data[i] = (float)(out->data[i] * d->exr_scale / d->peak_cdm2);
  jnd_image enc = {0};
  if ((st = jnd_render_to_srgb(out, &enc))) return st;
  jnd_image_free(out);
  *out = enc;
  return JND_OK;
}

/* a motion or weight map of the reference's size */
static jnd_status read_map(const char *path, const jnd_image *ref, int motion, jnd_image *out) {
  jnd_status st = jnd_image_read(path, out, NULL);
  if (st) return st;
  if (motion && (out->w != ref->w || out->h != ref->h || out->c < 2))
    return jnd_fail(JND_ERR_ARG, "%s: motion map must be %d x %d with 2 channels (is %d x %d x %d)", path, ref->w,
                    ref->h, out->w, out->h, out->c);
  if (!motion && (out->w != ref->w || out->h != ref->h))
    return jnd_fail(JND_ERR_ARG, "%s: weight map must be %d x %d (is %d x %d)", path, ref->w, ref->h, out->w, out->h);
  if (!motion) out->c = 1;   /* the first channel */
  return JND_OK;
}

/* A file read for the model (jnd diff's ref or test): with lum (the
 * display's luminance of each code), an 8-bit RGB PNG is kept as its codes
 * and made into its pyramids at once (jnd_model_image_rgb8, on this thread:
 * the other file is decoding on the other), *prep set and out holding only
 * its size; any other file is read into out. */
static jnd_status read_prepared(const jnd_model *model, const char *path, const float *lum, jnd_image *out,
                                jnd_image_info *info, jnd_model_image **prep) {
  *prep = NULL;
  if (!lum) return jnd_image_read(path, out, info);
  unsigned char *rgb = NULL;
  jnd_status s = jnd_image_read_rgb8(path, out, info, &rgb);
  if (s == JND_OK && rgb && (s = jnd_model_image_rgb8(model, rgb, out->w, out->h, lum, 1, prep)) != JND_OK)
    s = jnd_fail(s, "%s: %s", path, jnd_last_error());
  return s;
}

jnd_status jnd_diff_run(const char *ref_path, const char *test_path, const jnd_diff_params *pp, jnd_diff_result **out) {
  *out = NULL;
  if (!ref_path || !test_path) return jnd_fail(JND_ERR_ARG, "diff: needs two images, REF and TEST");
  jnd_diff_params p;
  if (pp) p = *pp;
  else jnd_diff_defaults(&p);
  jnd_model_params mp = p.model;
  jnd_pooling pool = p.pool;
  jnd_calibration cal;
  jnd_status s = JND_OK;
  if (p.calibration_path) { /* 000 §7: the calibration's transform, slope and percentile */
    if ((s = jnd_calibration_load(p.calibration_path, &cal))) return s;
    mp.beta = cal.beta;
    pool.kind = JND_POOL_PERCENTILE;
    pool.percentile = cal.percentile;
  }
  double t0 = jnd_seconds();
  /* outputs checked before any work, written staged, published together */
  const char *inputs[] = {ref_path, test_path, p.motion_path, p.weights_path, p.calibration_path};
  const char *map_out = NULL, *heat_out = NULL;
  report_output o;
  s = report_output_open(&o, inputs, 5, NULL, NULL);
  if (s) return s;
  if (p.map_path) s = jnd_output_add_file(o.w, p.map_path, &map_out);
  if (!s && p.heatmap_path) s = jnd_output_add_file(o.w, p.heatmap_path, &heat_out);
  if (!s && p.run.report_path && strcmp(p.run.report_path, "-") != 0)
    s = jnd_output_add_file(o.w, p.run.report_path, &o.copy);
  jnd_image ref = {0}, test = {0}, motion = {0}, weights = {0}, map = {0};
  jnd_image_info ri, ti;
  jnd_model *model = NULL;
  cJSON *report = NULL;
  jnd_diff_result *R = jnd_calloc(1, sizeof *R);
  if (!s && !R) s = jnd_fail(JND_ERR_NOMEM, "diff: out of memory");
  /* an 8-bit RGB PNG is kept as its codes (a quarter of the planes'
   * memory), which the model maps through the display's luminance of each
   * code (the values jnd_display_apply would give, bit for bit); a display
   * whose luminances are wrong is reported by jnd_display_apply as before */
  float lum[256];
  const int by_code = jnd_display_code_luminances(&mp.display, lum) == JND_OK;
  jnd_model_image *prep[2] = {NULL, NULL};
  if (!s && (s = jnd_model_create(&mp, &model))) s = jnd_fail(s, "diff: %s", jnd_last_error());
  if (!s) {
    /* the two files decode at the same time, each then made into its
     * pyramids on its own thread (read_prepared) */
    int ok[2];
    char msg[2][1024] = {"", ""};
    const char *paths[2] = {ref_path, test_path};
    jnd_image *img[2] = {&ref, &test};
    jnd_image_info *info[2] = {&ri, &ti};
#pragma omp parallel for num_threads(mp.threads == 1 ? 1 : 2) schedule(static, 1)
    for (int a = 0; a < 2; a++) {
      ok[a] = read_prepared(model, paths[a], by_code ? lum : NULL, img[a], info[a], &prep[a]) == JND_OK;
      /* the message lives on the thread that failed: take it along */
      if (!ok[a]) snprintf(msg[a], sizeof msg[a], "%s", jnd_last_error());
    }
    if (!ok[0] || !ok[1]) s = jnd_fail(JND_ERR_IO, "%s", msg[ok[0] ? 1 : 0]);
  }
  if (!s) {
    exr_scale_warn(&p, ref_path, &ref, &ri);
    exr_scale_warn(&p, test_path, &test, &ti);
    if (ref.w != test.w || ref.h != test.h)
      s = jnd_fail(JND_ERR_ARG, "%s: size %d x %d differs from %s (%d x %d)", test_path, test.w, test.h, ref_path,
                   ref.w, ref.h);
    else if (mp.has_gaze && !(mp.gaze_x >= 0 && mp.gaze_x < ref.w && mp.gaze_y >= 0 && mp.gaze_y < ref.h))
      s = jnd_fail(JND_ERR_ARG, "diff: --gaze: %g,%g is outside the %d x %d image", mp.gaze_x, mp.gaze_y, ref.w,
                   ref.h);
  }
  jnd_diff_inputs in = {0};
  if (!s && p.motion_path && !(s = read_map(p.motion_path, &ref, 1, &motion))) in.motion = &motion;
  if (!s && p.weights_path && !(s = read_map(p.weights_path, &ref, 0, &weights))) in.weights = &weights;
  double times[3] = {jnd_seconds() - t0, 0, 0};
  if (!s) {
    R->width = ref.w;
    R->height = ref.h;
    s = diff_files_codes(model, &ref, &ri, &test, &ti, prep, lum, &in, &pool, &map, &R->stats);
  }
  if (!s && p.calibration_path) s = jnd_diff_summarise_calibrated(&map, &cal, &R->stats);
  times[1] = jnd_seconds() - t0 - times[0];
  if (!s && p.map_path) {
    const char *name[1] = {"JND"};
    s = jnd_image_write_exr(map_out, &map, name, 0);
  }
  if (!s && p.heatmap_path) {
    jnd_image back = {0}, heat = {0};
    s = heatmap_backdrop(ref_path, &mp.display, &back);
    if (!s) s = jnd_heatmap(&back, &map, p.heatmap_max, &heat);
    if (!s) s = jnd_image_write_png(heat_out, &heat, 8);
    jnd_image_free(&back);
    jnd_image_free(&heat);
  }
  if (!s) {
    R->total_s = times[2] = jnd_seconds() - t0;
    R->above = p.fail_above >= 0 && R->stats.p_detect > p.fail_above;
    jnd_pooling_name(&pool, R->pooling, sizeof R->pooling);
    report = diff_report(ref_path, test_path, &ri, &ti, &p, &mp, model, R, p.run.timings ? times : NULL);
  }
  s = REPORT_OUTPUT_FINISH(&o, s, report, NULL, R);
  jnd_model_free(model);
  jnd_image_free(&ref);
  jnd_image_free(&test);
  jnd_model_image_free(prep[0]);
  jnd_model_image_free(prep[1]);
  jnd_image_free(&motion);
  jnd_image_free(&weights);
  jnd_image_free(&map);
  if (s) {
    jnd_diff_result_free(R);
    return s;
  }
  *out = R;
  return JND_OK;
}
