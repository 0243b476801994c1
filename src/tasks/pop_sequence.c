/* A level switch seen over a sequence of frames: the popping predictor
 * (pop.c, 004 §3.2) on every frame of a numbered sequence, one row per frame
 * and the worst frame's whole result.
 *
 *   1. each path of the pattern set that holds a frame-number field (%d or
 *      %0Nd, as ffmpeg and most renderers number their output) is expanded
 *      with the frame's number; a path without one (a mask) serves every frame
 *   2. jnd_pop_files on the frame's files: its regions, ratings and scores
 *   3. a row per frame: max R, detection score, regions, max ΔE*94 (004 §5.1)
 *   4. the worst frame: the highest max R, kept whole (regions, picture)
 *
 * 004 predicts one frame and ignores temporal integration (§3): so does the
 * table. It says which frames pop and how much, not whether a viewer adds
 * them up over time. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "tasks/tasks.h"

#define FRAME_PATH_MAX 4096 /* bytes of one expanded path */

void jnd_pop_sequence_defaults(jnd_pop_sequence_params *p) { memset(p, 0, sizeof *p); }

void jnd_pop_sequence_free(jnd_pop_sequence_result *r) {
  if (!r) return;
  free(r->rows);
  jnd_pop_result_free(&r->worst_result);
  memset(r, 0, sizeof *r);
}

/* Where pattern's frame-number field is: 1 and its span [*at, *end) with its
 * zero-padded width (0: none) when it holds exactly one %d or %0Nd and no
 * other % but %%; 0 when it has no field; −1 when a % is anything else. */
static int frame_field(const char *pattern, size_t *at, size_t *end, int *width) {
  int found = 0;
  for (size_t i = 0; pattern[i]; i++) {
    if (pattern[i] != '%') continue;
    if (pattern[i + 1] == '%') {
      i++;
      continue;
    }
    size_t j = i + 1;
    int wd = 0;
    if (pattern[j] == '0') {
      j++;
      if (pattern[j] < '1' || pattern[j] > '9') return -1;
      while (pattern[j] >= '0' && pattern[j] <= '9' && wd < 100) wd = wd * 10 + (pattern[j++] - '0');
      if (wd >= 100) return -1;
    }
    if (pattern[j] != 'd' || found) return -1;
    found = 1;
    *at = i;
    *end = j + 1;
    *width = wd;
    i = j;
  }
  return found;
}

int jnd_frame_path(const char *pattern, int frame, char *out, size_t size) {
  size_t at = 0, end = 0;
  int width = 0, k = frame_field(pattern, &at, &end, &width);
  if (k < 0 || frame < 0) return -1;
  size_t o = 0;
  for (size_t i = 0; pattern[i]; i++) {
    char num[128];
    const char *piece = NULL;
    if (k == 1 && i == at) {
      snprintf(num, sizeof num, "%0*d", width, frame);
      piece = num;
      i = end - 1;
    } else if (pattern[i] == '%' && pattern[i + 1] == '%') {
      piece = "%";
      i++;
    }
    size_t n = piece ? strlen(piece) : 1;
    if (o + n >= size) return -1;
    if (piece)
      memcpy(out + o, piece, n);
    else
      out[o] = pattern[i];
    o += n;
  }
  out[o] = 0;
  return k;
}

/* the pattern set's paths in one list (the order of jnd_pop_paths) */
enum { NPATHS = 12 };
static void paths_list(jnd_pop_paths *f, const char **slot[NPATHS]) {
  const char **s[NPATHS] = {&f->actual, &f->expected, &f->displacement, &f->displacement_expected,
                            &f->depth, &f->depth_expected, &f->prev_depth, &f->prev_depth_expected,
                            &f->weights, &f->prev_color, &f->prev_shading, &f->mask};
  memcpy(slot, s, sizeof s);
}

/* is a worse than b? a higher max R (a frame with regions above one
 * without), then a higher detection score; the earlier frame otherwise */
static int worse(const jnd_pop_result *a, const jnd_pop_result *b) {
  if (!a->nregions || !b->nregions) return a->nregions && !b->nregions;
  if (a->max_rating != b->max_rating) return a->max_rating > b->max_rating;
  return a->detection_score > b->detection_score;
}

jnd_status jnd_pop_sequence(jnd_model *m, const jnd_pop_paths *patterns, const jnd_pop_sequence_params *sp,
                            const jnd_pop_params *p, jnd_pop_sequence_result *out) {
  memset(out, 0, sizeof *out);
  if (!patterns->actual || !patterns->expected) return jnd_fail(JND_ERR_ARG, "pop: two frame patterns are needed");
  if (sp->first < 0 || sp->last < sp->first)
    return jnd_fail(JND_ERR_ARG, "pop: frames %d..%d: the first must be >= 0 and <= the last", sp->first, sp->last);
  if ((long long)sp->last - sp->first >= JND_POP_MAX_FRAMES)
    return jnd_fail(JND_ERR_ARG, "pop: frames %d..%d: at most %d frames", sp->first, sp->last, JND_POP_MAX_FRAMES);
  /* 1: which paths are patterns; both frames must be */
  jnd_pop_paths pat = *patterns, f = *patterns;
  const char **ps[NPATHS], **fs[NPATHS];
  paths_list(&pat, ps);
  paths_list(&f, fs);
  char *buf = malloc((size_t)NPATHS * FRAME_PATH_MAX);
  if (!buf) return JND_ERR_NOMEM;
  for (int k = 0; k < NPATHS; k++) {
    if (!*ps[k]) continue;
    size_t a, b;
    int wd, kind = frame_field(*ps[k], &a, &b, &wd);
    if (kind < 0) {
      free(buf);
      return jnd_fail(JND_ERR_ARG, "%s: a frame pattern holds one frame number field, %%d or %%0Nd (%%%% for a %%)",
                      *ps[k]);
    }
    if (kind == 0 && k < 2) {
      free(buf);
      return jnd_fail(JND_ERR_ARG, "%s: a sequence needs the frame number in the name (%%d or %%0Nd, e.g. new_%%04d.png)",
                      *ps[k]);
    }
    *fs[k] = buf + (size_t)k * FRAME_PATH_MAX;
  }
  const int n = sp->last - sp->first + 1;
  out->rows = jnd_calloc((size_t)n, sizeof *out->rows);
  if (!out->rows) {
    free(buf);
    return JND_ERR_NOMEM;
  }
  jnd_status s = JND_OK;
  jnd_pop_result cur;
  memset(&cur, 0, sizeof cur);
  for (int i = 0; i < n && s == JND_OK; i++) {
    const int frame = sp->first + i;
    if (sp->progress) sp->progress(sp->progress_user, "frame", i, n);
    for (int k = 0; k < NPATHS && s == JND_OK; k++)
      if (*ps[k] && jnd_frame_path(*ps[k], frame, (char *)*fs[k], FRAME_PATH_MAX) < 0)
        s = jnd_fail(JND_ERR_ARG, "%s: frame %d: the path is too long", *ps[k], frame);
    if (s != JND_OK) break;
    /* 2 */
    if ((s = jnd_pop_files(m, &f, p, &cur)) != JND_OK) break;
    if (i > 0 && (cur.w != out->worst_result.w || cur.h != out->worst_result.h)) {
      s = jnd_fail(JND_ERR_ARG, "%s: size %d × %d differs from frame %d's (%d × %d)", f.actual, cur.w, cur.h,
                   sp->first, out->worst_result.w, out->worst_result.h);
      break;
    }
    /* 3 */
    jnd_pop_frame_row *r = &out->rows[i];
    r->frame = frame;
    r->nregions = cur.nregions;
    r->max_rating = cur.max_rating;
    r->rating_top = cur.rating_top;
    r->coverage = cur.coverage;
    r->coverage_score = cur.coverage_score;
    r->rating_score = cur.rating_score;
    r->detection_score = cur.detection_score;
    r->max_delta_e94 = cur.max_delta_e94;
    r->jnd_max = cur.jnd_max;
    out->nrows = i + 1;
    /* 4: keep the worse of the two whole */
    if (i == 0 || worse(&cur, &out->worst_result)) {
      jnd_pop_result_free(&out->worst_result);
      out->worst_result = cur;
      out->worst = i;
    } else {
      jnd_pop_result_free(&cur);
    }
    memset(&cur, 0, sizeof cur);
  }
  jnd_pop_result_free(&cur); /* a frame refused after it was predicted (its size) */
  if (sp->progress && s == JND_OK) sp->progress(sp->progress_user, "frame", n, n);
  free(buf);
  if (s != JND_OK) jnd_pop_sequence_free(out);
  return s;
}
