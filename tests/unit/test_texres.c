/* Texture resolution (000 §4–§9): memory accounting, and properties of the
 * search on the built-in asset rendered small. */
#include <cjson/cJSON.h>
#include <stdint.h>

#include "io/io.h"
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


static void small_params(jnd_texres_params *p, double coverage) {
  jnd_texres_defaults(p);
  p->judge.views.sampling.count = 3;
  p->judge.views.render.width = p->judge.views.render.height = 96;
  p->judge.views.sampling.coverage = coverage;
  p->matrix = 0;
  p->judge.views.render.anisotropy = 1;
  p->judge.views.render.samples = 1;
  p->confirm_rounds = 0;   /* the properties here are of the search on its views */
}

static int longer(const int *wh) { return wh[0] > wh[1] ? wh[0] : wh[1]; }

/* the built-in asset with 256² maps, for a search; NULL (skipped) without a renderer */
static jnd_scene *searchable_builtin(void) {
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return NULL;
  }
  jnd_builtin_params bp;
  jnd_builtin_defaults(&bp);
  bp.map_size = 256;
  jnd_scene *s = NULL;
  CHECK_OK(jnd_scene_builtin(&bp, &s));
  return s;
}

TEST(sizes_never_exceed_the_mip_bound_and_shrink_with_the_object) {
  jnd_scene *s = searchable_builtin();
  if (!s) return;
  jnd_texres_params p;
  jnd_texres_result near = {0}, far = {0};
  small_params(&p, 0.9);
  CHECK_OK(jnd_texres_search(s, &p, &near));
  small_params(&p, 0.25);
  CHECK_OK(jnd_texres_search(s, &p, &far));
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
    CHECK(a->image >= 0 && a->image < near.nimages);
  }
  /* the built-in asset's four maps are four images */
  CHECK(near.nimages == 4);
  for (int t = 0; t < near.nimages; t++)
    CHECK(near.images[t].bytes_after[JND_TEX_RGBA8] <= near.images[t].bytes_before[JND_TEX_RGBA8]);
  CHECK(far.after_bytes[JND_TEX_RGBA8] <= near.after_bytes[JND_TEX_RGBA8]);
  CHECK(near.nviews == 3 && near.view_p && near.worst_heatmap.data);
  /* the scene is left with the chosen sizes */
  jnd_map_info mi;
  CHECK_OK(jnd_scene_map_info(s, 0, &mi));
  CHECK(mi.width == far.maps[0].chosen[0]);
  jnd_texres_result_clear(&near);
  jnd_texres_result_clear(&far);
  jnd_scene_free(s);
}

TEST(a_shared_judge_s_other_views_are_not_the_search_s) {
  /* A judge shared between searches (jnd budget: one a mesh level) holds
   * the earlier searches' confirmation and held-out views after its first
   * ones. A search's choice views are its first set and its own
   * confirmation sets, named: with two foreign views between them, the
   * search sees the same views, makes the same choice and reports the same
   * per-view P as on a judge of its own (it counted the foreign views and
   * shifted its sets before). */
  jnd_scene *s = searchable_builtin();
  if (!s) return;
  jnd_texres_params p;
  small_params(&p, 0.9);
  p.confirm_rounds = 1;
  jnd_texres_result alone = {0}, shared = {0};
  CHECK_OK(jnd_texres_search(s, &p, &alone));
  for (int i = 0; i < alone.nmaps; i++) jnd_scene_map_restore(s, i);   /* the reference state */
  jnd_judge_params jp = p.judge;
  jp.criterion.p = p.judge.criterion.p * (1 - p.margin);
  jnd_judge *j = NULL;
  CHECK_OK(jnd_judge_create(s, &jp, &j));
  jnd_view_set vs = p.judge.views;
  vs.sampling.count = 2;
  vs.sampling.seed += 77;   /* another search's views */
  jnd_view *views = NULL;
  int n = 0, first = 0;
  CHECK_OK(jnd_view_set_make(s, &vs, &views, &n));
  CHECK_OK(jnd_judge_add_views(j, views, n, &first));
  CHECK(first == 3 && n == 2);
  free(views);
  p.judge_shared = j;
  CHECK_OK(jnd_texres_search(s, &p, &shared));
  CHECK(alone.nviews == 6);   /* 3 views and one confirmation set of 3 */
  CHECK(shared.nviews == alone.nviews && shared.view_p && alone.view_p);
  for (int v = 0; v < shared.nviews && v < alone.nviews && shared.view_p && alone.view_p; v++)
    CHECK(shared.view_p[v] == alone.view_p[v]);
  CHECK(shared.nmaps == alone.nmaps);
  for (int i = 0; i < shared.nmaps && i < alone.nmaps; i++)
    CHECK(shared.maps[i].chosen[0] == alone.maps[i].chosen[0] && shared.maps[i].chosen[1] == alone.maps[i].chosen[1]);
  CHECK(shared.worst_view == alone.worst_view);
  /* which of the judge's views they are: the first three, then the confirmation set after the foreign two */
  static const int expect_judge[6] = {0, 1, 2, 5, 6, 7};
  for (int v = 0; v < 6 && shared.nviews == 6 && shared.view_judge && alone.view_judge; v++) {
    CHECK(shared.view_judge[v] == expect_judge[v]);
    CHECK(alone.view_judge[v] == v);
  }
  /* the worst view's picture is of that view, not of the judge's view of that index */
  const jnd_image *ha = &alone.worst_heatmap, *hs = &shared.worst_heatmap;
  CHECK(ha->data && hs->data && ha->w == hs->w && ha->h == hs->h && ha->c == hs->c);
  if (ha->data && hs->data && ha->w == hs->w && ha->h == hs->h && ha->c == hs->c)
    CHECK(memcmp(ha->data, hs->data, (size_t)ha->w * ha->h * ha->c * sizeof *ha->data) == 0);
  jnd_texres_result_clear(&alone);
  jnd_texres_result_clear(&shared);
  jnd_judge_free(j);
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
  CHECK_STATUS(jnd_texres_search(s, &p, &r), JND_ERR_ARG);
  CHECK(strstr(jnd_last_error(), "builtin/albedo") != NULL);
  p.maps = "emissive";
  CHECK_STATUS(jnd_texres_search(s, &p, &r), JND_ERR_ARG);
  jnd_scene_free(s);
}

/* the GLB at path: its JSON (parsed) and binary chunk (a pointer into *file) */
static cJSON *read_glb(const char *path, unsigned char **file, const unsigned char **bin, uint32_t *bin_n) {
  size_t n = 0;
  *file = NULL;
  *bin = NULL;
  *bin_n = 0;
  if (jnd_read_file(path, 1 << 26, file, &n) != JND_OK || n < 20 || memcmp(*file, "glTF", 4) != 0) return NULL;
  uint32_t jl;
  memcpy(&jl, *file + 12, 4);
  if (20 + (size_t)jl + 8 <= n) {
    memcpy(bin_n, *file + 20 + jl, 4);
    *bin = *file + 20 + jl + 8;
  }
  return cJSON_ParseWithLength((const char *)*file + 20, jl);
}

/* a GLB at path holding the glTF JSON js and no binary chunk */
static jnd_status write_json_glb(const char *path, const char *js) {
  size_t jl = strlen(js), jp = (jl + 3) & ~(size_t)3;
  unsigned char *glb = calloc(20 + jp, 1);
  if (!glb) return JND_ERR_NOMEM;
  uint32_t ver = 2, total = (uint32_t)(20 + jp), jlen = (uint32_t)jp, jtype = 0x4E4F534Au;
  memcpy(glb, "glTF", 4);
  memcpy(glb + 4, &ver, 4);
  memcpy(glb + 8, &total, 4);
  memcpy(glb + 12, &jlen, 4);
  memcpy(glb + 16, &jtype, 4);
  memset(glb + 20, ' ', jp);
  memcpy(glb + 20, js, jl);
  jnd_status st = jnd_write_file_atomic(path, glb, total);
  free(glb);
  return st;
}

/* the built-in asset at 16² maps with its first (base colour) map halved,
 * the scene the model-writer tests write back; out_dir (made) under the
 * test's folder for the copies */
static jnd_scene *halved_builtin(const char *name, char *out_dir, size_t cap) {
  jnd_builtin_params bp;
  jnd_builtin_defaults(&bp);
  bp.map_size = 16;
  jnd_scene *s = NULL;
  CHECK_OK(jnd_scene_builtin(&bp, &s));
  if (!s) return NULL;
  jnd_map_info mi;
  CHECK_OK(jnd_scene_map_info(s, 0, &mi));
  CHECK(mi.slot == JND_MAP_BASE_COLOR);
  CHECK_OK(jnd_scene_map_resize(s, 0, 8, 8));
  char cmd[1400];
  snprintf(out_dir, cap, "%s/%s", test_tmp_dir(), name);
  CHECK(system((snprintf(cmd, sizeof cmd, "mkdir -p '%s'", out_dir), cmd)) == 0);
  return s;
}

/* the model writer's copy of the GLB src (written with the glTF JSON js)
 * for scene s, read back: its JSON, or NULL */
static cJSON *write_back(const jnd_scene *s, const char *src, const char *js, const char *out_dir, char *out,
                         size_t cap, unsigned char **file, const unsigned char **bin, uint32_t *bin_n) {
  *file = NULL;
  CHECK_OK(write_json_glb(src, js));
  CHECK_OK(jnd_texres_write_model(s, src, out_dir, out, cap));
  return read_glb(out, file, bin, bin_n);
}

TEST(model_writer_gives_a_resized_data_uri_image_its_own_view_in_a_glb_that_had_none) {
  /* found by fuzz_gltf: a GLB without bufferViews or buffers whose image is
   * a data uri. The resized image moves into the binary chunk, so the copy
   * needs a view and a buffer for it (the writer leaked them before). */
  char src[1200], out_dir[1200], out[4400];
  jnd_scene *s = halved_builtin("noviews_out", out_dir, sizeof out_dir);
  if (!s) return;
  /* a 16² PNG as the data uri (its pixels do not matter: the writer re-encodes the map) */
  snprintf(src, sizeof src, "%s/noviews.glb", test_tmp_dir());
  const char *js = "{\"asset\": {\"version\": \"2.0\"}, \"images\": [{\"uri\": \"data:image/png;base64,AAAA\"}],"
                   " \"textures\": [{\"source\": 0}],"
                   " \"materials\": [{\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0}}}]}";
  unsigned char *file;
  const unsigned char *bin;
  uint32_t bin_n;
  cJSON *root = write_back(s, src, js, out_dir, out, sizeof out, &file, &bin, &bin_n);
  CHECK(root != NULL && bin != NULL);
  if (root && bin) {
    const cJSON *img = cJSON_GetArrayItem(cJSON_GetObjectItem(root, "images"), 0);
    const cJSON *bv = cJSON_GetArrayItem(cJSON_GetObjectItem(root, "bufferViews"),
                                         cJSON_GetObjectItem(img, "bufferView")->valueint);
    const cJSON *b0 = cJSON_GetArrayItem(cJSON_GetObjectItem(root, "buffers"), 0);
    CHECK(bv && b0 && cJSON_GetObjectItem(img, "uri") == NULL);
    if (bv && b0) {
      int off = cJSON_GetObjectItem(bv, "byteOffset")->valueint, len = cJSON_GetObjectItem(bv, "byteLength")->valueint;
      CHECK(cJSON_GetObjectItem(b0, "byteLength")->valueint == (int)bin_n);
      CHECK(off >= 0 && len > 0 && (uint32_t)(off + len) <= bin_n);
      jnd_image im;
      jnd_image_info info;
      CHECK_OK(jnd_decode_png("view", bin + off, (size_t)len, &im, &info));
      CHECK(im.w == 8 && im.h == 8);
      jnd_image_free(&im);
    }
  }
  cJSON_Delete(root);
  free(file);
  jnd_scene_free(s);
}

TEST(model_writer_walks_each_node_once_in_a_file_that_names_nodes_twice_or_in_a_cycle) {
  /* found by fuzz_gltf (CI of stop 38): a node tree 64 deep in which every
   * node names its child twice made the material walk 2^64 calls; a node
   * that is its own child is a cycle. glTF nodes have one parent, so the
   * walk visits each node once and the writer finishes. The material is
   * still found through the tree (the mesh hangs from the deepest node),
   * at any depth (a chain of 300). */
  char src[1200], out_dir[1200], out[4400];
  jnd_scene *s = halved_builtin("twice_out", out_dir, sizeof out_dir);
  if (!s) return;
  enum { DEEP = 70, CHAIN = 300 };
  char js[16384];
  for (int variant = 0; variant < 3; variant++) {
    /* variant 2: the mesh's material is the file's second (the first has no
     * map), under a chain of CHAIN nodes: the walk must reach it (a depth
     * bound left it to the file's order, which names the wrong material) */
    int k = snprintf(js, sizeof js,
                     "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [0]}],"
                     " \"images\": [{\"uri\": \"data:image/png;base64,AAAA\"}], \"textures\": [{\"source\": 0}],"
                     " \"meshes\": [{\"primitives\": [{\"attributes\": {}, \"material\": %d}]}],"
                     " \"materials\": [%s{\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0}}}],"
                     " \"nodes\": [",
                     variant == 2, variant == 2 ? "{}, " : "");
    if (variant == 1)   /* node i's children are [i+1, i+1]; the last holds the mesh */
      for (int i = 0; i < DEEP; i++)
        k += i < DEEP - 1 ? snprintf(js + k, sizeof js - (size_t)k, "{\"children\": [%d, %d]}, ", i + 1, i + 1)
                          : snprintf(js + k, sizeof js - (size_t)k, "{\"mesh\": 0}");
    else if (variant == 0)   /* node 0 is its own child, twice, and node 1 holds the mesh (first: a walk
                              * that enters a node twice overruns its stack at once, not after 2^70 steps) */
      k += snprintf(js + k, sizeof js - (size_t)k, "{\"children\": [0, 0, 1]}, {\"mesh\": 0}");
    else   /* node i's child is i + 1; the last holds the mesh */
      for (int i = 0; i < CHAIN; i++)
        k += i < CHAIN - 1 ? snprintf(js + k, sizeof js - (size_t)k, "{\"children\": [%d]}, ", i + 1)
                           : snprintf(js + k, sizeof js - (size_t)k, "{\"mesh\": 0}");
    snprintf(js + k, sizeof js - (size_t)k, "]}");
    snprintf(src, sizeof src, "%s/twice%d.glb", test_tmp_dir(), variant);
    unsigned char *file;
    const unsigned char *bin;
    uint32_t bin_n;
    cJSON *root = write_back(s, src, js, out_dir, out, sizeof out, &file, &bin, &bin_n);
    CHECK(root != NULL);
    cJSON_Delete(root);
    free(file);
    remove(out);
  }
  jnd_scene_free(s);
}

RUN_TESTS(a_shared_judge_s_other_views_are_not_the_search_s, model_writer_walks_each_node_once_in_a_file_that_names_nodes_twice_or_in_a_cycle, model_writer_gives_a_resized_data_uri_image_its_own_view_in_a_glb_that_had_none, memory_of_a_mip_chain_counts_every_level, sizes_never_exceed_the_mip_bound_and_shrink_with_the_object,
          unknown_map_names_are_refused_before_rendering)
