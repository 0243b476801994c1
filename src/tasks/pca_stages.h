/* The stages of pca (001) that its files share: pca.c (resampling,
 * decomposition, encoding), pca_texset.c (texture sets), pca_psnr.c (the
 * choice by PSNR), pca_render.c (the rendered choice), pca_bc.c (block
 * compression). Internal to the library; each is documented where it is
 * defined. */
#ifndef JND_TASKS_PCA_STAGES_H
#define JND_TASKS_PCA_STAGES_H

#include "jnd.h"

/* pca_texset.c: the set's C planes (w·h floats each) into planes */
const float *const *pca_set_planes(const jnd_texset *set, const float **planes);

/* pca_render.c: a material's maps as a set (jnd_pca_render_material_set's
 * rule) from any scene, the file's (orig 1) or as in use now (0) */
jnd_status pca_scene_material_set(const jnd_scene *scene, int material, int orig, const char *channels,
                                  jnd_texset *set, jnd_map_slot *slots, int *map_of, size_t *orig_bytes);

/* pca_bc.c: jnd_pca_block_compressed, and in *gpu (may be NULL) the bytes of
 * its textures with their mip chains, as a GPU holds them */
jnd_status pca_block_compressed_gpu(const jnd_texset *set, const jnd_pca_encoded *enc, jnd_pca_bc_variant v,
                                    jnd_image *out, size_t *bytes, size_t *gpu);

/* pca.c: a component's side at scale s (1/2^s of n, rounded up) */
int pca_coarse_side(int n, int s);

/* pca_render.c: a and b keep the same components at the same scales and bits */
int pca_same_encoding(const jnd_pca_encoding *a, const jnd_pca_encoding *b);

/* pca.c */
jnd_status pca_upsample(const float *coarse, int w, int h, int s, float *dst);
void pca_project(const jnd_texset *set, const jnd_pca *pca, int K, float *proj);
jnd_status pca_store_component(const float *u, int w, int h, int s, int bits, jnd_image *img, double *scale,
                               double *offset);
jnd_status pca_encode_from(const jnd_texset *set, const jnd_pca *pca, const float *proj, const jnd_pca_encoding *e,
                           jnd_pca_encoded *out);

/* pca_psnr.c: the PSNR search set up once (projections, per-option
 * distortions) for any number of targets: the rendered search asks for
 * many. */
typedef struct {
  struct pca_search *S;
  float *proj;   /* all C component planes at full size */
} psnr_chooser;
void pca_chooser_free(psnr_chooser *ch);
jnd_status pca_chooser_init(const jnd_texset *set, const jnd_pca *pca, int max_scale, psnr_chooser *ch);
jnd_status pca_chooser_run(psnr_chooser *ch, const jnd_texset *set, const jnd_pca *pca, double min_psnr_db,
                           jnd_pca_encoding *out);

#endif
