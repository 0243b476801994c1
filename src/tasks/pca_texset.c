/* Texture sets for PCA (001): a material's maps read, brought to one size
 * and split into the channels the decomposition sees (jnd_texset), with
 * the picks of --channels and the weights of --weights (docs/pca.md). */
#include <ctype.h>
#include <stddef.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "scene/scene.h"
#include "tasks/tasks.h"
#include "tasks/pca_stages.h"

#define MAXC JND_PCA_MAX_CHANNELS

/* ------------------------------------------------------------------------ */
/* Texture sets                                                             */
/* ------------------------------------------------------------------------ */

static const char letters[] = "rgba";

void jnd_texset_free(jnd_texset *set) {
  if (!set) return;
  free(set->data);
  memset(set, 0, sizeof *set);
}

static int plane_constant(const float *p, size_t n) {
  for (size_t i = 1; i < n; i++)
    if (p[i] != p[0]) return 0;
  return 1;
}

static int planes_equal(const float *a, const float *b, size_t n) { return memcmp(a, b, n * sizeof *a) == 0; }

/* A comma-separated list of NAME=VALUE (--channels, --weight): each
 * assignment handed to assign(user, name, value) in order, the first error
 * returned. option and form name the option and its form in the error for
 * an item without '=' ("--weight: 'x' is not NAME=WEIGHT (e.g. albedo=2)"). */
static jnd_status parse_assignments(const char *spec, const char *option, const char *form,
                                    jnd_status (*assign)(void *user, const char *name, const char *value),
                                    void *user) {
  if (!spec || !*spec) return JND_OK;
  char buf[1024];
  snprintf(buf, sizeof buf, "%s", spec);
  char *save = NULL;
  for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
    char *eq = strchr(tok, '=');
    if (!eq) return jnd_fail(JND_ERR_ARG, "%s: '%s' is not %s", option, tok, form);
    *eq = 0;
    jnd_status st = assign(user, tok, eq + 1);
    if (st != JND_OK) return st;
  }
  return JND_OK;
}

typedef struct {
  const char *const *names;
  int n;
  char (*picks)[8];
} picks_ctx;

static jnd_status assign_pick(void *user, const char *tok, const char *l) {
  picks_ctx *x = user;
  int m = -1;
  for (int i = 0; i < x->n; i++)
    if (strcmp(x->names[i], tok) == 0) m = i;
  if (m < 0) return jnd_fail(JND_ERR_ARG, "--channels: no map named '%s'", tok);
  size_t len = strlen(l);
  if (len == 0 || len > 4) return jnd_fail(JND_ERR_ARG, "--channels: '%s' needs 1 to 4 of r, g, b, a", tok);
  for (size_t k = 0; k < len; k++)
    if (!strchr(letters, tolower((unsigned char)l[k])))
      return jnd_fail(JND_ERR_ARG, "--channels: '%c' is not one of r, g, b, a", l[k]);
  for (size_t k = 0; k < len; k++) x->picks[m][k] = (char)tolower((unsigned char)l[k]);
  x->picks[m][len] = 0;
  return JND_OK;
}

/* "normal=rg,metalRoughness=gb" → picks[map] = letters string; -1 for unknown map */
static jnd_status parse_picks(const char *spec, const char *const *names, int n, char picks[][8]) {
  for (int i = 0; i < n; i++) picks[i][0] = 0;
  picks_ctx x = {names, n, picks};
  return parse_assignments(spec, "--channels", "MAP=LETTERS (e.g. normal=rg)", assign_pick, &x);
}

/* labels name the inputs in errors (paths for files) */
static jnd_status texset_build(const jnd_image *maps, const char *const *names, const char *const *labels, int n,
                               const char *channels, jnd_texset *out) {
  memset(out, 0, sizeof *out);
  if (n <= 0) return jnd_fail(JND_ERR_ARG, "a texture set needs at least one map");
  if (n > JND_PCA_MAX_MAPS) return jnd_fail(JND_ERR_LIMIT, "%d maps is over the limit of %d", n, JND_PCA_MAX_MAPS);
  int W = 0, H = 0;
  for (int i = 0; i < n; i++) {
    if (!maps[i].data || maps[i].c < 1 || maps[i].c > 4)
      return jnd_fail(JND_ERR_FORMAT, "%s: needs 1 to 4 channels (has %d)", labels[i], maps[i].c);
    if ((size_t)maps[i].w * maps[i].h > (size_t)W * H) {
      W = maps[i].w;
      H = maps[i].h;
    }
  }
  for (int i = 0; i < n; i++)
    if ((long long)maps[i].w * H != (long long)maps[i].h * W)
      return jnd_fail(JND_ERR_ARG, "%s: %d × %d does not have the shape of the set's largest map (%d × %d)",
                      labels[i], maps[i].w, maps[i].h, W, H);
  char picks[JND_PCA_MAX_MAPS][8];
  jnd_status s = parse_picks(channels, names, n, picks);
  if (s != JND_OK) return s;
  size_t np = (size_t)W * H;
  /* choose channels */
  int total = 0;
  for (int i = 0; i < n; i++) {
    jnd_texset_map *m = &out->maps[i];
    snprintf(m->name, sizeof m->name, "%s", names[i]);
    m->file_w = maps[i].w;
    m->file_h = maps[i].h;
    m->file_channels = maps[i].c;
    m->resampled = maps[i].w != W || maps[i].h != H;
    m->first = total;
    size_t fp = (size_t)maps[i].w * maps[i].h;
    int dup_of[4] = {-1, -1, -1, -1};   /* index into m->src */
    if (picks[i][0]) {
      for (int k = 0; picks[i][k]; k++) {
        int ch = (int)(strchr(letters, picks[i][k]) - letters);
        if (ch >= maps[i].c)
          return jnd_fail(JND_ERR_ARG, "%s: --channels asks for '%c' of a %d-channel map", labels[i], picks[i][k],
                          maps[i].c);
        m->src[m->count++] = ch;
      }
    } else {
      for (int ch = 0; ch < maps[i].c; ch++) {
        const float *p = jnd_image_plane(&maps[i], ch);
        if (plane_constant(p, fp)) {
          m->constants++;
          continue;
        }
        int dup = -1;
        for (int k = 0; k < m->count && dup < 0; k++)
          if (planes_equal(p, jnd_image_plane(&maps[i], m->src[k]), fp)) dup = k;
        if (dup >= 0) {
          m->duplicates++;
          dup_of[ch] = dup;
          continue;
        }
        m->src[m->count++] = ch;
      }
      if (m->count == 0) {   /* a constant map still needs one channel */
        m->src[m->count++] = 0;
        m->constants--;
      }
    }
    for (int ch = 0; ch < 4; ch++) {
      m->from[ch] = -1;
      m->constant[ch] = 0;
      if (ch >= maps[i].c) continue;
      for (int k = 0; k < m->count; k++)
        if (m->src[k] == ch) m->from[ch] = total + k;
      if (dup_of[ch] >= 0) m->from[ch] = total + dup_of[ch];
      if (m->from[ch] < 0 && !picks[i][0]) m->constant[ch] = jnd_image_plane(&maps[i], ch)[0];
    }
    total += m->count;
  }
  if (total > MAXC) return jnd_fail(JND_ERR_LIMIT, "%d channels is over the limit of %d (pick with --channels)", total, MAXC);
  s = jnd_check_size(W, H, total, labels[0]);
  if (s != JND_OK) return s;
  out->data = jnd_alloc(np * (size_t)total, sizeof *out->data);
  if (!out->data) return JND_ERR_NOMEM;
  out->w = W;
  out->h = H;
  out->c = total;
  out->nmaps = n;
  for (int i = 0; i < n; i++) {
    jnd_texset_map *m = &out->maps[i];
    /* a grey file (with or without alpha), or grey stored as RGB(A) */
    /* a grey file (with or without alpha), grey stored as RGB(A), or a
     * constant map (one channel kept for it): named after the map */
    int grey = m->count == 1 && m->src[0] == 0 && !picks[i][0] &&
               (m->file_channels <= 2 || m->duplicates >= 1 || m->constants == m->file_channels - 1);
    for (int k = 0; k < m->count; k++) {
      int c = m->first + k;
      out->map_of[c] = i;
      if (grey)
        snprintf(out->names[c], sizeof out->names[c], "%s", m->name);
      else
        snprintf(out->names[c], sizeof out->names[c], "%s.%c", m->name, letters[m->src[k]]);
      const float *p = jnd_image_plane(&maps[i], m->src[k]);
      float *d = out->data + (size_t)c * np;
      if (m->resampled) {
        s = jnd_resample_plane(p, maps[i].w, maps[i].h, d, W, H, (double)maps[i].w / W, (double)maps[i].h / H, 0, 0);
        if (s != JND_OK) {
          jnd_texset_free(out);
          return s;
        }
      } else {
        memcpy(d, p, np * sizeof *d);
      }
    }
  }
  return JND_OK;
}

jnd_status jnd_texset_from_images(const jnd_image *maps, const char *const *names, int n, const char *channels,
                                  jnd_texset *out) {
  return texset_build(maps, names, names, n, channels, out);
}

/* file stem: after the last '/', before the last '.' */
static void stem(const char *path, char *out, size_t n) {
  const char *b = strrchr(path, '/');
  b = b ? b + 1 : path;
  snprintf(out, n, "%s", b);
  char *dot = strrchr(out, '.');
  if (dot && dot != out) *dot = 0;
}

jnd_status jnd_texset_read(const char *const *paths, int n, const char *channels, jnd_texset *out) {
  memset(out, 0, sizeof *out);
  if (n <= 0) return jnd_fail(JND_ERR_ARG, "a texture set needs at least one map");
  if (n > JND_PCA_MAX_MAPS) return jnd_fail(JND_ERR_LIMIT, "%d maps is over the limit of %d", n, JND_PCA_MAX_MAPS);
  char stems[JND_PCA_MAX_MAPS][64];
  const char *names[JND_PCA_MAX_MAPS];
  for (int i = 0; i < n; i++) stem(paths[i], stems[i], sizeof stems[i]);
  /* drop the prefix every stem shares, up to a separator ("Default_") */
  size_t pre = 0;
  if (n > 1) {
    size_t common = strlen(stems[0]);
    for (int i = 1; i < n; i++) {
      size_t k = 0;
      while (k < common && stems[i][k] == stems[0][k]) k++;
      common = k;
    }
    for (size_t k = 0; k < common; k++)
      if (strchr("_-. ", stems[0][k])) pre = k + 1;
    for (int i = 0; i < n; i++)
      if (!stems[i][pre]) pre = 0;
  }
  for (int i = 0; i < n; i++) {
    names[i] = stems[i] + pre;
    for (int j = 0; j < i; j++)
      if (strcmp(names[i], names[j]) == 0)
        return jnd_fail(JND_ERR_ARG, "%s: a second map named '%s'", paths[i], names[i]);
  }
  jnd_image maps[JND_PCA_MAX_MAPS];
  memset(maps, 0, sizeof maps);
  jnd_status s = JND_OK;
  for (int i = 0; i < n && s == JND_OK; i++) s = jnd_image_read(paths[i], &maps[i], NULL);
  if (s == JND_OK) s = texset_build(maps, names, paths, n, channels, out);
  for (int i = 0; i < n; i++) jnd_image_free(&maps[i]);
  return s;
}

jnd_status jnd_texset_map_image(const jnd_texset *set, const jnd_image *channels, int map, jnd_image *out) {
  memset(out, 0, sizeof *out);
  if (map < 0 || map >= set->nmaps) return jnd_fail(JND_ERR_ARG, "map %d of a set of %d", map, set->nmaps);
  if (channels->w != set->w || channels->h != set->h || channels->c != set->c)
    return jnd_fail(JND_ERR_ARG, "map image: channels are %d × %d × %d, the set %d × %d × %d", channels->w,
                    channels->h, channels->c, set->w, set->h, set->c);
  const jnd_texset_map *m = &set->maps[map];
  jnd_status s = jnd_image_alloc(out, set->w, set->h, m->file_channels);
  if (s != JND_OK) return s;
  size_t np = (size_t)set->w * set->h;
  for (int ch = 0; ch < m->file_channels; ch++) {
    float *d = jnd_image_plane(out, ch);
    if (m->from[ch] >= 0)
      memcpy(d, jnd_image_plane(channels, m->from[ch]), np * sizeof *d);
    else
      for (size_t i = 0; i < np; i++) d[i] = m->constant[ch];
  }
  return JND_OK;
}

typedef struct {
  const jnd_texset *set;
  double *weights;
} weights_ctx;

static jnd_status assign_weight(void *user, const char *tok, const char *value) {
  weights_ctx *x = user;
  const jnd_texset *set = x->set;
  char *end;
  double w = strtod(value, &end);
  if (end == value || *end || !(w > 0) || !isfinite(w))
    return jnd_fail(JND_ERR_ARG, "--weight: %s: '%s' is not a positive number", tok, value);
  int hit = 0;
  for (int c = 0; c < set->c; c++)
    if (strcmp(set->names[c], tok) == 0 || strcmp(set->maps[set->map_of[c]].name, tok) == 0) {
      x->weights[c] = w;
      hit = 1;
    }
  if (!hit) return jnd_fail(JND_ERR_ARG, "--weight: no map or channel named '%s'", tok);
  return JND_OK;
}

jnd_status jnd_texset_parse_weights(const jnd_texset *set, const char *spec, double *weights) {
  for (int c = 0; c < set->c; c++) weights[c] = 1.0;
  weights_ctx x = {set, weights};
  return parse_assignments(spec, "--weight", "NAME=WEIGHT (e.g. albedo=2)", assign_weight, &x);
}

/* the set's planes (pca_stages.h) */
const float *const *pca_set_planes(const jnd_texset *set, const float **planes) {
  for (int c = 0; c < set->c; c++) planes[c] = set->data + (size_t)c * set->w * set->h;
  return planes;
}
