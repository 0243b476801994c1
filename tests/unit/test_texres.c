/* Texture resolution (000 §4–§9): memory accounting, and properties of the
 * search on the built-in asset rendered small. */
#include "jnd.h"
#include "test.h"

TEST(memory_of_a_mip_chain_counts_every_level) {
  /* 000 Table 2: two 1024² maps without mips in RGBA8 are 8 MB */
  CHECK(jnd_texture_bytes(JND_TEX_RGBA8, 1024, 1024, 0) * 2 == 8u << 20);
  size_t texels = 0;
  for (int s = 1024; s >= 1; s /= 2) texels += (size_t)s * s;
  CHECK(jnd_texture_bytes(JND_TEX_RGBA8, 1024, 1024, 1) == 4 * texels);
  /* BC1 and BC4: 8 bytes a 4x4 block; BC5/BC7/ASTC 4x4: 16; levels under 4x4 take a block */
  CHECK(jnd_texture_bytes(JND_TEX_BC1, 1024, 1024, 0) == 512u * 1024);
  CHECK(jnd_texture_bytes(JND_TEX_BC7, 1024, 1024, 0) == 1024u * 1024);
  CHECK(jnd_texture_bytes(JND_TEX_BC1, 4, 4, 1) == 3 * 8);
  CHECK(jnd_texture_bytes(JND_TEX_BC5, 8, 8, 1) == jnd_texture_bytes(JND_TEX_BC4, 8, 8, 1) * 2);
  CHECK(jnd_texture_bytes(JND_TEX_ASTC6, 1024, 1024, 0) == 171u * 171 * 16);
  CHECK(jnd_texture_bytes(JND_TEX_ASTC4, 256, 128, 0) == jnd_texture_bytes(JND_TEX_BC7, 256, 128, 0));
  /* non-square chains stop at 1x1 */
  CHECK(jnd_texture_bytes(JND_TEX_RGBA8, 4, 1, 1) == 4 * (4 + 2 + 1));
  CHECK(strcmp(jnd_tex_format_name(JND_TEX_ASTC6), "astc6x6") == 0);
  CHECK(jnd_slot_block_format(JND_MAP_NORMAL, 3) == JND_TEX_BC5);
}

static int renderer_available(void) {
  jnd_renderer_params rp;
  jnd_renderer_defaults(&rp);
  rp.width = rp.height = 16;
  jnd_renderer *r;
  if (jnd_renderer_create(&rp, &r) != JND_OK) return 0;
  jnd_renderer_free(r);
  return 1;
}

static void small_params(jnd_texres_params *p, double coverage) {
  jnd_texres_defaults(p);
  p->views = 3;
  p->width = p->height = 96;
  p->coverage = coverage;
  p->matrix = 0;
  p->anisotropy = 4;
  p->samples = 1;
}

static int longer(const int *wh) { return wh[0] > wh[1] ? wh[0] : wh[1]; }

TEST(sizes_never_exceed_the_mip_bound_and_shrink_with_the_object) {
  if (!renderer_available()) {
    fprintf(stderr, "skip: no OpenGL context\n");
    return;
  }
  jnd_builtin_params bp;
  jnd_builtin_defaults(&bp);
  bp.map_size = 256;
  jnd_scene *s;
  CHECK_OK(jnd_scene_builtin(&bp, &s));
  jnd_texres_params p;
  jnd_texres_result near = {0}, far = {0};
  small_params(&p, 0.9);
  CHECK_OK(jnd_texres_run(s, &p, &near));
  small_params(&p, 0.25);
  CHECK_OK(jnd_texres_run(s, &p, &far));
  CHECK(near.nmaps == 4 && far.nmaps == 4);
  for (int i = 0; i < near.nmaps && i < far.nmaps; i++) {
    const jnd_texres_map *a = &near.maps[i], *b = &far.maps[i];
    CHECK(longer(a->chosen) <= longer(a->mip_bound));
    CHECK(longer(b->chosen) <= longer(b->mip_bound));
    /* a smaller object on screen never gets larger maps */
    CHECK(longer(b->chosen) <= longer(a->chosen));
    CHECK(longer(b->mip_bound) <= longer(a->mip_bound));
    /* aspect kept, candidates descending from the original */
    CHECK(a->cand[0][0] == a->orig[0] && a->cand[0][1] == a->orig[1]);
    for (int k = 1; k < a->ncand; k++) CHECK(a->cand[k][0] < a->cand[k - 1][0]);
    CHECK(a->bytes_after[JND_TEX_RGBA8] <= a->bytes_before[JND_TEX_RGBA8]);
  }
  CHECK(far.after_bytes[JND_TEX_RGBA8] <= near.after_bytes[JND_TEX_RGBA8]);
  CHECK(near.nviews == 3 && near.view_p && near.worst_heatmap.data);
  /* the scene is left with the chosen sizes */
  jnd_map_info mi;
  CHECK_OK(jnd_scene_map_info(s, 0, &mi));
  CHECK(mi.width == far.maps[0].chosen[0]);
  jnd_texres_result_free(&near);
  jnd_texres_result_free(&far);
  jnd_scene_free(s);
}

TEST(unknown_map_names_are_refused_before_rendering) {
  jnd_builtin_params bp;
  jnd_builtin_defaults(&bp);
  bp.map_size = 16;
  jnd_scene *s;
  CHECK_OK(jnd_scene_builtin(&bp, &s));
  jnd_texres_params p;
  small_params(&p, 0.8);
  p.maps = "builtin/albedo";
  jnd_texres_result r;
  CHECK_STATUS(jnd_texres_run(s, &p, &r), JND_ERR_ARG);
  CHECK(strstr(jnd_last_error(), "builtin/albedo") != NULL);
  p.maps = "emissive";
  CHECK_STATUS(jnd_texres_run(s, &p, &r), JND_ERR_ARG);
  jnd_scene_free(s);
}

RUN_TESTS(memory_of_a_mip_chain_counts_every_level, sizes_never_exceed_the_mip_bound_and_shrink_with_the_object,
          unknown_map_names_are_refused_before_rendering)
