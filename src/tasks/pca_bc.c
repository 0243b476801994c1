/* GPU block compression of pca's components and of the maps themselves
 * (001 "Caveats"): PSNR and bytes with BC4/BC1, for the report. */
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
/* Block compression of the components and of the maps (001 "Caveats")     */
/* ------------------------------------------------------------------------ */

/* Compresses channels [first, first+n) of img with f and decodes them back
 * in place; returns the bytes it took, and in *gpu (may be NULL) adds the
 * texture's with its mip chain (000 Table 2, as jnd budget counts). */
static jnd_status bc_roundtrip(jnd_bc_format f, jnd_image *img, int first, size_t *bytes, size_t *gpu) {
  size_t n = jnd_bc_size(f, img->w, img->h);
  if (gpu)
    *gpu += jnd_texture_bytes(f == JND_BC1 ? JND_TEX_BC1 : f == JND_BC4 ? JND_TEX_BC4 : JND_TEX_BC5, img->w, img->h, 1);
  uint8_t *blocks = jnd_alloc(n, 1);
  if (!blocks) return JND_ERR_NOMEM;
  jnd_status s = jnd_bc_encode(f, img, first, blocks);
  if (s == JND_OK) s = jnd_bc_decode(f, blocks, img, first);
  free(blocks);
  *bytes += n;
  return s;
}

/* components grouped (by threes of one size when bc1, else pairs),
 * block-compressed and reconstructed into rec (w × h × C, allocated) */
static jnd_status bc_components(const jnd_pca_encoded *enc, int bc1, jnd_image *rec, size_t *bytes, size_t *gpu) {
  int K = enc->enc.components;
  jnd_image comp[MAXC];
  memset(comp, 0, sizeof comp);
  jnd_status s = JND_OK;
  *bytes = 0;
  int done[MAXC] = {0};
  for (int k = 0; k < K && s == JND_OK; k++) {
    if (done[k]) continue;
    int group[3] = {k, -1, -1}, n = 1, want = bc1 ? 3 : 2;
    for (int j = k + 1; j < K && n < want; j++)
      if (!done[j] && enc->enc.scale[j] == enc->enc.scale[k]) group[n++] = j;
    const jnd_image *src = &enc->comp[k];
    jnd_image packed = {0};
    s = jnd_image_alloc(&packed, src->w, src->h, n);
    for (int g = 0; g < n && s == JND_OK; g++) {
      memcpy(jnd_image_plane(&packed, g), enc->comp[group[g]].data, (size_t)src->w * src->h * sizeof(float));
      done[group[g]] = 1;
    }
    if (s == JND_OK) s = bc_roundtrip(n == 3 ? JND_BC1 : n == 2 ? JND_BC5 : JND_BC4, &packed, 0, bytes, gpu);
    for (int g = 0; g < n && s == JND_OK; g++) {
      s = jnd_image_alloc(&comp[group[g]], src->w, src->h, 1);
      if (s == JND_OK)
        memcpy(comp[group[g]].data, jnd_image_plane(&packed, g), (size_t)src->w * src->h * sizeof(float));
    }
    jnd_image_free(&packed);
  }
  if (s == JND_OK) s = jnd_pca_reconstruct(enc, comp, rec);
  for (int k = 0; k < K; k++) jnd_image_free(&comp[k]);
  return s;
}

/* the maps themselves, each in the format its channel count calls for */
static jnd_status bc_plain(const jnd_texset *set, jnd_image *rec, size_t *bytes) {
  *bytes = 0;
  jnd_status s = jnd_image_alloc(rec, set->w, set->h, set->c);
  if (s == JND_OK) memcpy(rec->data, set->data, (size_t)set->w * set->h * set->c * sizeof(float));
  for (int i = 0; i < set->nmaps && s == JND_OK; i++) {
    const jnd_texset_map *m = &set->maps[i];
    jnd_image view = {set->w, set->h, m->count, jnd_image_plane(rec, m->first)};
    switch (m->count) {
    case 1: s = bc_roundtrip(JND_BC4, &view, 0, bytes, NULL); break;
    case 2: s = bc_roundtrip(JND_BC5, &view, 0, bytes, NULL); break;
    case 3: s = bc_roundtrip(JND_BC1, &view, 0, bytes, NULL); break;
    default:
      s = bc_roundtrip(JND_BC1, &view, 0, bytes, NULL);
      if (s == JND_OK) s = bc_roundtrip(JND_BC4, &view, 3, bytes, NULL);
      break;
    }
  }
  if (s != JND_OK) jnd_image_free(rec);
  return s;
}

jnd_status jnd_pca_block_compressed(const jnd_texset *set, const jnd_pca_encoded *enc, jnd_pca_bc_variant v,
                                    jnd_image *out, size_t *bytes) {
  return pca_block_compressed_gpu(set, enc, v, out, bytes, NULL);
}

jnd_status pca_block_compressed_gpu(const jnd_texset *set, const jnd_pca_encoded *enc, jnd_pca_bc_variant v,
                                    jnd_image *out, size_t *bytes, size_t *gpu) {
  if (gpu) *gpu = 0;
  memset(out, 0, sizeof *out);
  size_t b = 0;
  if (!set || !set->data) return jnd_fail(JND_ERR_ARG, "block compression: no set");
  if (v != JND_PCA_BC_PLAIN && (!enc || enc->c != set->c || enc->w != set->w || enc->h != set->h))
    return jnd_fail(JND_ERR_ARG, "block compression: set and encoding differ");
  jnd_status s;
  switch (v) {
  case JND_PCA_BC_PCA_BC4: s = bc_components(enc, 0, out, &b, gpu); break;
  case JND_PCA_BC_PCA_BC1: s = bc_components(enc, 1, out, &b, gpu); break;
  case JND_PCA_BC_PLAIN: s = bc_plain(set, out, &b); break;
  default: return jnd_fail(JND_ERR_ARG, "block compression: variant %d", (int)v);
  }
  if (bytes) *bytes = b;
  return s;
}

jnd_status jnd_pca_block_compression(const jnd_texset *set, const jnd_pca_encoded *enc, jnd_pca_bc_report *out) {
  memset(out, 0, sizeof *out);
  if (!set || !enc || enc->c != set->c || enc->w != set->w || enc->h != set->h)
    return jnd_fail(JND_ERR_ARG, "block compression: set and encoding differ");
  double *psnr[3] = {out->psnr_pca_bc4_db, out->psnr_pca_bc1_db, out->psnr_plain_db};
  size_t *bytes[3] = {&out->bytes_pca_bc4, &out->bytes_pca_bc1, &out->bytes_plain};
  jnd_status s = JND_OK;
  for (int v = 0; v < 3 && s == JND_OK; v++) {
    jnd_image rec = {0};
    s = jnd_pca_block_compressed(set, enc, (jnd_pca_bc_variant)v, &rec, bytes[v]);
    if (s == JND_OK) s = jnd_texset_psnr(set, &rec, psnr[v], NULL);
    jnd_image_free(&rec);
  }
  return s;
}
