/* Fitted parameters of 002's models read back: the report `jnd gaze fit`
 * writes (gaze_fit.json), or the combined form of
 * scripts/gaze-defaults.json, for `jnd gaze MODEL --params FIT.json`.
 *
 * A fit report carries one model: result.model "spatial" (result.parameters
 * alpha, beta, s_deg, w_vdp, k_s, gamma, each {value, ...}, and the fixed
 * floor parameters.b; w_g is 1) or "temporal" (w_t, gamma_t). The combined
 * form has "fixed" {w_g, b} and "spatial", "temporal" objects with
 * "parameters" as above. Every parameter of a model given must be there and
 * valid; the fields of a model not given are kept. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "io/io.h"
#include "jnd.h"

typedef struct {
  const char *name;
  size_t offset;
  double lo, hi;   /* valid: lo < v <= hi, or lo <= v for the floor and k_s */
  int closed;      /* 1: lo itself is valid */
} param_spec;

static const param_spec SPATIAL[] = {
    {"alpha", offsetof(jnd_gaze_model, alpha), 0, 1e6, 0},  {"beta", offsetof(jnd_gaze_model, beta), 0, 1e3, 0},
    {"s_deg", offsetof(jnd_gaze_model, s_deg), -90, 90, 1}, {"w_vdp", offsetof(jnd_gaze_model, w_vdp), 0, 1e6, 1},
    {"k_s", offsetof(jnd_gaze_model, k_s), 1, 1e3, 1},      {"gamma", offsetof(jnd_gaze_model, gamma), 0, 1e3, 0},
};
static const param_spec TEMPORAL[] = {
    {"w_t", offsetof(jnd_gaze_model, w_t), 0, 1e6, 1},
    {"gamma_t", offsetof(jnd_gaze_model, gamma_t), 0, 1e3, 0},
};
static const param_spec FLOOR_B = {"b", offsetof(jnd_gaze_model, b), 0, 1e6, 1};
static const param_spec W_G = {"w_g", offsetof(jnd_gaze_model, w_g), 0, 1e6, 0};

/* o[key] (a number, or an object with "value") into the model; 0 or an error */
static jnd_status take(const char *name, const cJSON *o, const char *where, const param_spec *ps, jnd_gaze_model *m) {
  const cJSON *x = cJSON_GetObjectItemCaseSensitive(o, ps->name);
  if (cJSON_IsObject(x)) x = cJSON_GetObjectItemCaseSensitive(x, "value");
  if (!x) return jnd_fail(JND_ERR_FORMAT, "%s: %s.%s is missing", name, where, ps->name);
  double v = cJSON_IsNumber(x) ? x->valuedouble : NAN;
  if (!isfinite(v) || (ps->closed ? v < ps->lo : v <= ps->lo) || v > ps->hi)
    return jnd_fail(JND_ERR_FORMAT, "%s: %s.%s is not a number in %s%g, %g]", name, where, ps->name,
                    ps->closed ? "[" : "(", ps->lo, ps->hi);
  *(double *)((char *)m + ps->offset) = v;
  return JND_OK;
}

static jnd_status take_all(const char *name, const cJSON *o, const char *where, const param_spec *ps, int n,
                           jnd_gaze_model *m) {
  if (!cJSON_IsObject(o)) return jnd_fail(JND_ERR_FORMAT, "%s: %s is not an object", name, where);
  jnd_status st = JND_OK;
  for (int i = 0; i < n && st == JND_OK; i++) st = take(name, o, where, &ps[i], m);
  return st;
}

static jnd_status from_json(const char *name, const cJSON *root, jnd_gaze_model *m) {
  if (!cJSON_IsObject(root)) return jnd_fail(JND_ERR_FORMAT, "%s: not a JSON object", name);
  const cJSON *res = cJSON_GetObjectItemCaseSensitive(root, "result");
  jnd_status st;
  if (res) {
    /* a `jnd gaze fit` report */
    const cJSON *kind = cJSON_GetObjectItemCaseSensitive(res, "model");
    const char *k = cJSON_GetStringValue(kind);
    const cJSON *par = cJSON_GetObjectItemCaseSensitive(res, "parameters");
    if (k && strcmp(k, "temporal") == 0) return take_all(name, par, "result.parameters", TEMPORAL, 2, m);
    if (!k || strcmp(k, "spatial") != 0)
      return jnd_fail(JND_ERR_FORMAT, "%s: result.model is not \"spatial\" or \"temporal\" (write it with jnd gaze fit)",
                      name);
    if ((st = take_all(name, par, "result.parameters", SPATIAL, 6, m)) != JND_OK) return st;
    if ((st = take(name, cJSON_GetObjectItemCaseSensitive(root, "parameters"), "parameters", &FLOOR_B, m)) != JND_OK)
      return st;
    m->w_g = 1;   /* the fit holds it at 1 (docs/gaze.md "Fitting") */
    return JND_OK;
  }
  /* the combined form (scripts/gaze-defaults.json) */
  const cJSON *fixed = cJSON_GetObjectItemCaseSensitive(root, "fixed"),
              *sp = cJSON_GetObjectItemCaseSensitive(root, "spatial"),
              *tm = cJSON_GetObjectItemCaseSensitive(root, "temporal");
  if (!sp && !tm)
    return jnd_fail(JND_ERR_FORMAT, "%s: neither a jnd gaze fit report (\"result\") nor \"spatial\"/\"temporal\" parameters",
                    name);
  if (sp) {
    if ((st = take_all(name, cJSON_GetObjectItemCaseSensitive(sp, "parameters"), "spatial.parameters", SPATIAL, 6, m)) !=
        JND_OK)
      return st;
    if ((st = take(name, fixed, "fixed", &FLOOR_B, m)) != JND_OK) return st;
    if ((st = take(name, fixed, "fixed", &W_G, m)) != JND_OK) return st;
  }
  if (tm) return take_all(name, cJSON_GetObjectItemCaseSensitive(tm, "parameters"), "temporal.parameters", TEMPORAL, 2, m);
  return JND_OK;
}

jnd_status jnd_gaze_model_parse(const char *name, const char *text, size_t n, jnd_gaze_model *m) {
  cJSON *root = cJSON_ParseWithLength(text, n);
  if (!root) return jnd_fail(JND_ERR_FORMAT, "%s: not JSON", name);
  jnd_gaze_model t = *m;   /* nothing half-applied */
  jnd_status st = from_json(name, root, &t);
  cJSON_Delete(root);
  if (st == JND_OK) *m = t;
  return st;
}

jnd_status jnd_gaze_model_read(const char *path, jnd_gaze_model *m) {
  unsigned char *text = NULL;
  size_t n = 0;
  jnd_status st = jnd_read_file(path, (size_t)16 << 20, &text, &n);
  if (st != JND_OK) return st;
  st = jnd_gaze_model_parse(path, (const char *)text, n, m);
  free(text);
  return st;
}
