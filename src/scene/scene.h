/* Internal view of a scene, shared by the scene and render layers. */
#ifndef JND_SCENE_H
#define JND_SCENE_H

#include <stddef.h>
#include <stdint.h>
#include "jnd.h"

/* Interleaved vertex layout uploaded as is by the renderer. */
enum { JND_VTX_FLOATS = 18 };   /* pos 3, normal 3, tangent 4, uv0 2, uv1 2, colour 4 */

typedef struct {
  float *vertices;        /* nverts × JND_VTX_FLOATS */
  uint32_t *indices;      /* 3 × ntris */
  size_t nverts, ntris;
  int material;
  uint64_t version;       /* changes whenever vertices or indices change (a level of detail is
                             selected), so that a renderer knows what to upload again */
} jnd_mesh;

/* One mesh at one level of detail (lod.c). */
typedef struct {
  float *vertices;        /* owned; NULL: level 0's vertices of the mesh (a simplified level
                             indexes the input's vertices) */
  size_t nverts;
  uint32_t *indices;      /* owned, 3 × ntris */
  size_t ntris;
  double error_abs;       /* meshoptimizer's error bound, object units */
  int sloppy;             /* made by meshopt_simplifySloppy */
  uint64_t version;       /* the jnd_mesh version it gets when selected */
} jnd_lod_mesh;

typedef struct {
  jnd_lod_mesh *mesh;     /* one per scene mesh */
  jnd_lod_level_info info;
} jnd_lod_level;

typedef enum { JND_WRAP_REPEAT = 0, JND_WRAP_CLAMP, JND_WRAP_MIRROR } jnd_wrap;

typedef struct {
  jnd_image orig;         /* the file's map, values 0..1 in the slot's encoding */
  jnd_image now;          /* a replacement (resampled or set); data NULL = use orig */
  int uv_set;
  float uvxf[6];          /* KHR_texture_transform on the uvs: u' = [0]u + [1]v + [2], v' = [3]u + [4]v + [5] */
  jnd_wrap wrap_s, wrap_t;
  int mag_nearest;        /* glTF sampler magFilter NEAREST */
  int min_nearest;        /* glTF sampler minFilter NEAREST* (mips still used) */
  uint64_t version;       /* changes whenever the map in use changes (unique across scenes) */
  int image;              /* the first map that samples the same image of the file (itself when
                             none before it does): a packed occlusion-roughness-metal image, an
                             image two materials share */
  char *source;           /* the file's reference to that image (import.c), owned; NULL: its own */
} jnd_map;

typedef struct {
  char name[96];
  float base_color[4];
  float metallic, roughness;
  float normal_scale, occlusion_strength;
  float emissive[3];
  jnd_alpha_mode alpha_mode;
  float alpha_cutoff;
  int double_sided;
  int map[JND_MAP_SLOTS];  /* index into scene maps, or -1 */
} jnd_material;

struct jnd_scene {
  char path[1024];
  jnd_mesh *meshes;
  int nmeshes;
  jnd_material *materials;
  int nmaterials;
  jnd_map *maps;
  int nmaps;
  char **warnings;
  int nwarnings;
  double centre[3], radius;
  double subject_centre[3], subject_radius;   /* bounds without the ground plane */
  int ground_mesh;         /* the ground plane's mesh, or -1 (jnd_scene_compute_bounds) */
  /* levels of detail (lod.c): none until a chain is built or added; then
   * lod[0] owns the file's arrays and meshes[i] points at lod[lod_now]'s */
  jnd_lod_level *lod;
  int nlod, lod_now;
  uint64_t id;             /* unique per scene object, so a renderer knows what it uploaded */
  int threads;             /* threads resampling its maps (0: OpenMP's default); a judge on a CPU
                              rasteriser sets 1, since OpenMP workers spinning after each resize
                              take the cores the rasteriser's threads render on */
  const jnd_scene *twin_of; /* a twin (jnd_scene_twin): owns only its meshes array */
};

/* The map in use now. */
static inline const jnd_image *jnd_map_image(const jnd_map *m) {
  return m->now.data ? &m->now : &m->orig;
}

jnd_scene *jnd_scene_new(const char *path);
/* A second handle on s for another thread (jnd_lod_run judges screens in
 * parallel): its own level of detail shown (jnd_scene_lod_select), sharing
 * s's levels, materials, maps and warnings, which neither may change while
 * the twin lives. jnd_scene_free frees the twin's own part; s must outlive
 * it. NULL when out of memory. */
jnd_scene *jnd_scene_twin(const jnd_scene *s);
jnd_status jnd_scene_add_warning(jnd_scene *s, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
/* Adds a map for (material, slot); takes ownership of img. Returns its index or -1. */
int jnd_scene_add_map(jnd_scene *s, int material, jnd_map_slot slot, jnd_image *img);
void jnd_material_defaults(jnd_material *m, const char *name);
/* Computes per-vertex tangents (xyz, handedness in w) for a mesh that has
 * normals and uv0: per-triangle tangents weighted by the corner angle,
 * Gram–Schmidt orthogonalised to the normal. */
void jnd_mesh_compute_tangents(jnd_mesh *m);
/* Bounding sphere of all meshes (centre of the box, radius to the farthest
 * vertex), the ground plane if there is one, and the sphere of the rest. */
void jnd_scene_compute_bounds(jnd_scene *s);
uint64_t jnd_scene_next_version(void);
/* Points sampled on level 0's surface, uniformly by area and stratified
 * (distance.c): *out gets samples × 3 doubles (caller frees). */
jnd_status jnd_scene_surface_samples(const jnd_scene *s, int samples, uint64_t seed, double **out);
/* Distances from n points to the nearest point of level `level`'s surface. */
jnd_status jnd_scene_points_distance(const jnd_scene *s, int level, const double *pts, int n,
                                     jnd_surface_distance *out);
/* Levels of detail a glTF file has as MSFT_lod nodes (gltf_lod.c): *nlevels
 * gets their number (1: none; 0 when the file's JSON or GLB container does
 * not parse, with an error); with out, *out gets the file (GLB or JSON, as it
 * came) rewritten so that assimp sees level `level` (caller frees).
 * JND_ERR_FORMAT "NAME: ..." for a malformed MSFT_lod. */
jnd_status jnd_gltf_lod_variant(const char *name, const unsigned char *file, size_t n, int level, int *nlevels,
                                unsigned char **out, size_t *out_n);
/* references.c: "%20"-style escapes of a glTF URI decoded in place; and
 * ref (a URI when uri is 1, else a file name) as a path beside model: in
 * model's folder unless absolute, backslashes read as slashes. */
void jnd_uri_decode(char *s);
void jnd_model_relative(const char *model, const char *ref, int uri, char *full, size_t n);
/* The largest side of level 0's bounding box, over every mesh (the unit of
 * meshoptimizer's relative errors, lod.c). */
double jnd_scene_extent(const jnd_scene *s);
/* jnd_scene_write_lod_glb with the scene's levels first.. only (jnd budget
 * drops the levels finer than its choice): written level j is the scene's
 * first + j, coverage[j] its MSFT_screencoverage (gltf_write.c). */
jnd_status jnd_scene_write_lod_glb_from(const jnd_scene *s, const char *path, const double *coverage, int first);

/* ---- gltf_edit.c: a glTF document edited, not regenerated ---- */
/* A .gltf or .glb file read for editing: its JSON and binary chunk. An edit
 * changes only the members it needs, so what jnd does not model
 * (animations, extensions, extras) survives into the copy. */
typedef struct jnd_gltf_doc jnd_gltf_doc;
/* Reads src (JND_ERR_FORMAT "SRC: not a glTF 2.0 file ..." for a file whose
 * container or JSON does not parse); free with jnd_gltf_doc_free. */
jnd_status jnd_gltf_doc_read(const char *src, jnd_gltf_doc **out);
void jnd_gltf_doc_free(jnd_gltf_doc *d);
/* gmat[j] (caller's, one per scene material) gets the glTF material that
 * scene's material j is, in the order assimp loads them (the default
 * scene's meshes first use them, a node's children before its own mesh), or
 * -1 for a material the file does not have. The match is checked against the
 * scene (names; need, NULL or materials × JND_MAP_SLOTS flags: those slots
 * must have a texture): JND_ERR_FORMAT rather than a copy that would not
 * match. */
jnd_status jnd_gltf_doc_materials(const jnd_gltf_doc *d, const jnd_scene *scene, const unsigned char *need,
                                  int *gmat);
/* A slot of glTF material `material` to sample the scene's map `map`, which
 * is width × height now. */
typedef struct {
  int material;
  jnd_map_slot slot;
  int map, width, height;
} jnd_gltf_image_edit;
/* Applies edits: each slot's image re-encoded from the map as the file had
 * it (PNG or JPEG; PNG for a map with alpha). Slots that sample one image at
 * one size keep one image; an image another slot still uses as it was, or
 * at another size, is copied (new image and texture, appended). Slots
 * without a texture are skipped. Call once. */
jnd_status jnd_gltf_doc_set_images(jnd_gltf_doc *d, const jnd_scene *scene, const jnd_gltf_image_edit *edits,
                                   int n);
/* Writes the document under out_dir with the source's file name: a .glb as
 * one .glb (binary chunk compacted view by view, new images in it); a .gltf
 * with its new images (NAME_imageI.png/.jpg) and external buffers and
 * images as files beside it. out_path (NULL or n bytes) gets the path. */
jnd_status jnd_gltf_doc_write(jnd_gltf_doc *d, const char *out_dir, char *out_path, size_t n);

/* Frees the level storage (lod.c); the meshes then own nothing. */
void jnd_scene_lod_free(jnd_scene *s);

/* ---- resample.c: the one resampler of planes and maps ---- */
/* Lanczos-3 (000 §4) of a sw × sh plane to dw × dh: output x sits at input
 * (x + 0.5)·rx − 0.5 (rx input samples per output sample), the kernel
 * widened by rx when shrinking; edges clamped (wrap 0) or wrapped. */
jnd_status jnd_resample_plane(const float *src, int sw, int sh, float *dst, int dw, int dh, double rx, double ry,
                              int wrap, int threads);
/* jnd_resample_map (jnd.h) with a thread count (0: OpenMP's default). */
jnd_status jnd_resample_map_threads(const jnd_image *in, int w, int h, jnd_map_kind kind, int wrap, int threads,
                                    jnd_image *out);
/* Averages 2^s × 2^s boxes (partial boxes at the edge average what they
 * cover): dst is ceil(w/2^s) × ceil(h/2^s). */
void jnd_box_down_plane(const float *src, int w, int h, int s, float *dst);
/* Mip level lev of a map as a driver builds it: 2^lev boxes, sRGB colour
 * averaged in linear light, other channels as stored. out is allocated. */
jnd_status jnd_box_reduce_map(const jnd_image *orig, int lev, jnd_map_kind kind, jnd_image *out);

/* Whether meshoptimizer can be called (opened on first use where CMake read
 * its soname: src/scene/meshopt_lazy.c); 0 with the loader's message as the
 * last error */
int jnd_meshopt_ready(void);

#endif
