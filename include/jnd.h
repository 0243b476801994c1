/* jnd.h — the whole public API of libjnd.
 *
 * jnd answers "what is the cheapest asset nobody will notice?". Its core is a
 * model of human vision (Schwarz & Stamminger 2009, §3.1) that predicts, per
 * pixel, how many just-noticeable differences (JND) separate two images as a
 * viewer sees them on a given display, and the probability that a viewer
 * notices.
 *
 * Ten lines to compare two images:
 *
 *     jnd_image ref, test;  jnd_image_info ri, ti;
 *     jnd_image_read("ref.png", &ref, &ri);  jnd_image_read("test.png", &test, &ti);
 *     jnd_model_params p;  jnd_model_defaults(&p);          // standard-fhd display
 *     jnd_model *m;  jnd_model_create(&p, &m);
 *     jnd_diff_stats st;                                     // ref, test are consumed
 *     if (jnd_diff_files(m, &ref, &ri, &test, &ti, NULL, NULL, NULL, &st) != JND_OK)
 *         fprintf(stderr, "%s\n", jnd_last_error());
 *     printf("P(detect) = %.3f, max JND = %.2f\n", st.p_detect, st.jnd_max);
 *     jnd_model_free(m);
 *
 * Conventions: functions return jnd_status (JND_OK = 0); results go through
 * out-parameters; jnd_last_error() is a one-line message "FILE: what is wrong"
 * for the calling thread. The caller owns every image it passes in and every
 * image an out-parameter fills (free with jnd_image_free). Images inside the
 * library are linear: after a display model, values are cd/m².
 * Limits: images of at most JND_MAX_SIDE pixels a side and JND_MAX_PIXELS
 * pixels; larger inputs are refused with JND_ERR_LIMIT.
 */
#ifndef JND_H
#define JND_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------ */
/* Errors                                                                   */
/* ------------------------------------------------------------------------ */

typedef enum {
  JND_OK = 0,
  JND_ERR_IO,        /* a file is missing, unreadable or unwritable */
  JND_ERR_FORMAT,    /* a file's content is malformed or unsupported */
  JND_ERR_ARG,       /* an argument is invalid, or inputs do not match */
  JND_ERR_LIMIT,     /* an input exceeds a stated limit */
  JND_ERR_NOMEM,     /* out of memory */
  JND_ERR_GL,        /* the renderer could not get or use an OpenGL context */
  JND_ERR_INTERNAL   /* a bug: please report */
} jnd_status;

/* The message of the last error on this thread: one line, "FILE: problem"
 * where a file is involved. Never NULL; "" when there was none. */
const char *jnd_last_error(void);

/* The library's version, "MAJOR.MINOR.PATCH". */
const char *jnd_version(void);

/* ------------------------------------------------------------------------ */
/* Images                                                                   */
/* ------------------------------------------------------------------------ */

#define JND_MAX_SIDE 32768
#define JND_MAX_PIXELS ((size_t)1 << 27) /* 134 Mpixel */

/* A float32 image, planar: channel ch of pixel (x, y) is
 * data[((size_t)ch * h + y) * w + x]. */
typedef struct {
  int w, h, c;
  float *data;
} jnd_image;

/* Allocates a zeroed w × h × c image. Refuses sizes over the limits. */
jnd_status jnd_image_alloc(jnd_image *img, int w, int h, int c);

/* Frees the pixels and zeroes the struct; safe on a zeroed struct. */
void jnd_image_free(jnd_image *img);

/* A pointer to channel ch. */
float *jnd_image_plane(const jnd_image *img, int ch);

/* ------------------------------------------------------------------------ */
/* Image files                                                              */
/* ------------------------------------------------------------------------ */

typedef enum {
  JND_ENCODING_SRGB = 0, /* values 0..1 are sRGB-encoded display signal (PNG, JPEG) */
  JND_ENCODING_LINEAR    /* values are linear light (EXR, Radiance HDR) */
} jnd_encoding;

typedef struct {
  jnd_encoding encoding;
  int bits;          /* 8 or 16 for PNG/JPEG; 16 (half) or 32 for EXR; 32 for HDR */
  int channels;      /* channels in the file (1 grey, 2 grey+alpha, 3 RGB, 4 RGBA) */
  int has_alpha;
  char format[8];    /* "png", "jpeg", "hdr", "exr" */
} jnd_image_info;

/* Reads PNG (8/16-bit), JPEG, Radiance HDR or OpenEXR (half/float, scanline
 * or tiled). PNG/JPEG values are scaled to 0..1 (still sRGB-encoded); HDR/EXR
 * values are as stored. The image has the file's channel count (1–4); EXR
 * channels are ordered R, G, B, A when present, else alphabetically. Files
 * with NaN or Inf values are refused (JND_ERR_FORMAT). info may be NULL. */
jnd_status jnd_image_read(const char *path, jnd_image *out, jnd_image_info *info);

/* Writes a PNG with 8 or 16 bits per channel from values in 0..1 (clamped;
 * no transfer function is applied). 1–4 channels. Written to a temporary file
 * and renamed: never half-written. */
jnd_status jnd_image_write_png(const char *path, const jnd_image *img, int bits);

/* Writes an OpenEXR file (scanline, ZIP compression) with float (half = 0)
 * or half (half = 1) channels. names gives img->c channel names (NULL: "Y"
 * for one channel, "R","G","B"["A"] for 3–4, "X","Y" for 2). Atomic. */
jnd_status jnd_image_write_exr(const char *path, const jnd_image *img,
                               const char *const *names, int half);

/* CSV files. */
typedef struct {
  int ncols, nrows;
  char **header;   /* ncols names */
  char ***cells;   /* nrows × ncols strings ("" for empty) */
} jnd_csv;

/* Reads a comma-separated file with a header row; quoted fields ("a,b",
 * "say ""hi""") are supported. Rows must have the header's column count. */
jnd_status jnd_csv_read(const char *path, jnd_csv *out);
jnd_status jnd_csv_parse(const char *name, const char *text, size_t n, jnd_csv *out);
void jnd_csv_free(jnd_csv *csv);
/* Index of a column by name, or -1. */
int jnd_csv_column(const jnd_csv *csv, const char *name);
/* Parses a cell as a number; NaN for "NaN"/"NA"/"". Returns 0 if not a number. */
int jnd_csv_number(const char *cell, double *out);

/* A heatmap of a JND map over a dimmed grey copy of the reference, on a
 * logarithmic scale of JND with a colour bar (ticks in JND, the 1 JND line,
 * P = 0.5, marked), so that structure above 1 JND stays visible:
 * differences below min_jnd are not drawn; max_jnd is the top of the scale,
 * or 0 for the map's 99.9th percentile rounded up to 1, 2 or 5 × 10^k (at
 * least 2). Images whose shorter side is below min_side are magnified by a
 * whole factor (nearest pixel) up to it, within 2048 pixels a side. */
typedef struct {
  double max_jnd;     /* top of the scale, JND (0: auto, as above) */
  double min_jnd;     /* bottom of the scale, JND (0.1) */
  int min_side;       /* pixels (256) */
  int beside;         /* 1: the reference itself left of the heatmap */
  const char *title;  /* a line above the picture (NULL: none) */
} jnd_heatmap_params;
void jnd_heatmap_defaults(jnd_heatmap_params *p);

/* Draws the heatmap figure. ref holds the reference's file signal (0..1,
 * 1–4 channels, as jnd_image_read gives); jnd_map has its size. out is
 * allocated: 3 channels, sRGB-encoded 0..1, for jnd_image_write_png. */
jnd_status jnd_heatmap_draw(const jnd_heatmap_params *p, const jnd_image *ref, const jnd_image *jnd_map,
                            jnd_image *out);

/* jnd_heatmap_draw with the defaults and the given top of the scale
 * (max_jnd <= 0: auto). */
jnd_status jnd_heatmap(const jnd_image *ref, const jnd_image *jnd_map, double max_jnd, jnd_image *out);

/* Writes n bytes to path through a temporary file in the same folder and a
 * rename, so path is either the old file or the complete new one. */
jnd_status jnd_write_file_atomic(const char *path, const void *data, size_t n);

/* ------------------------------------------------------------------------ */
/* Display model (Schwarz & Stamminger 2009 §3.1, first stage)              */
/* ------------------------------------------------------------------------ */

typedef struct {
  char name[32];
  double ppd;            /* pixels per degree of visual angle at the screen centre */
  double peak_cdm2;      /* luminance of full white, cd/m² */
  double black_cdm2;     /* luminance the display emits for black, cd/m² */
  double ambient_lux;    /* illuminance of the room on the screen, lux */
  double reflectivity;   /* fraction of ambient light the screen reflects (Lambertian) */
  double exr_scale;      /* linear (EXR/HDR) inputs: cd/m² per unit value */
  /* geometry the ppd came from (0 where ppd was given directly) */
  double diagonal_in, distance_m;
  int width_px, height_px;
} jnd_display;

/* The standard-fhd display: 24", 1920×1080 at 60 cm, 200 cd/m². */
void jnd_display_defaults(jnd_display *d);

/* Fills d from a preset name: standard-fhd, standard-4k, phone, laptop, vr.
 * JND_ERR_ARG with the list of names for an unknown one. */
jnd_status jnd_display_preset(const char *name, jnd_display *d);

/* The names of the presets, NULL-terminated. */
const char *const *jnd_display_preset_names(void);

/* Pixels per degree at the centre of a flat screen of the given diagonal
 * (inches) and resolution, seen from distance_m metres. */
double jnd_ppd_from_geometry(double diagonal_in, int width_px, int height_px, double distance_m);

/* Display model: converts an image in the file's encoding to absolute linear
 * RGB (Rec.709 primaries) in cd/m²: L = (peak − black)·EOTF(V) + black +
 * reflectivity·ambient/π. sRGB inputs use the sRGB EOTF; linear inputs are
 * multiplied by exr_scale and get the reflected ambient added. Grey images
 * become three equal channels; alpha is composited over the display's black
 * (see docs/model.md). out gets 3 channels; out may be in itself, which an
 * RGB or RGBA image is then converted in place (no second image in memory). */
jnd_status jnd_display_apply(const jnd_display *d, const jnd_image *in, jnd_encoding enc,
                             int has_alpha, jnd_image *out);

/* ------------------------------------------------------------------------ */
/* The vision model (Schwarz & Stamminger 2009 §3.1–3.2)                    */
/* ------------------------------------------------------------------------ */

typedef struct {
  jnd_display display;
  double sensitivity;        /* multiplier on the achromatic CSF (fitted, docs/model.md) */
  double sens_rg;            /* multiplier on the red–green CSF (fitted) */
  double sens_yv;            /* multiplier on the yellow–violet CSF (fitted) */
  double minkowski;          /* exponent across bands and channels (2.4, 004 §3.2) */
  double min_band_cpd;       /* bands are added while their peak is >= this (004: 0.5 cpd;
                                see docs/model.md for the default) */
  double summation_cycles;   /* local probability summation: Gaussian window of this many
                                cycles of each band (0: none, as 004); docs/model.md */
  double summation_beta;     /* exponent of that summation */
  double eye_velocity_dps;   /* fixational eye movements: sensitivity is the best over retinal
                                velocities [v, v + this] (0: v only, as 004); docs/model.md */
  double chroma_sat_td;      /* retinal illuminance (trolands) where the chromatic square-root
                                law turns into Weber's law (0: pure square root, as 004) */
  double rg_cutoff_cpd;      /* red–green CSF centre cut-off (Kelly 1983 form, docs/model.md) */
  double yv_cutoff_cpd;      /* yellow–violet CSF centre cut-off */
  double beta;               /* psychometric slope (3.5, 000 eq. 4) */
  double fps;                /* frames per second, to turn motion maps into deg/s */
  int has_gaze;              /* 1: gaze_x/gaze_y give the fixation point */
  double gaze_x, gaze_y;     /* pixels; may lie outside the image */
  int threads;               /* 0: OpenMP's default */
} jnd_model_params;

/* Fills p with the defaults: standard-fhd display and the fitted constants. */
void jnd_model_defaults(jnd_model_params *p);

/* A model instance: caches the per-display tables (band peak frequencies,
 * CSF look-up tables). Reusable for any number of comparisons; not for
 * concurrent use from several threads. */
typedef struct jnd_model jnd_model;

jnd_status jnd_model_create(const jnd_model_params *p, jnd_model **out);
void jnd_model_free(jnd_model *m);

/* The parameters the model was created with. */
const jnd_model_params *jnd_model_get_params(const jnd_model *m);

/* Optional per-pixel inputs of a comparison; any field may be NULL / 0. */
typedef struct {
  const jnd_image *motion;   /* 2 channels: screen displacement in pixels per frame
                                (needs params.fps); goes through the eye-movement model */
  const jnd_image *weights;  /* 1 channel: multiplies the difference map (004 §3.2) */
  double retinal_dps;        /* > 0: every pixel moves on the retina at this speed (deg/s),
                                bypassing the eye-movement model (psychophysics with fixation) */
} jnd_diff_inputs;

/* JND map of two images of absolute linear RGB in cd/m² (as jnd_display_apply
 * gives), same size, 3 channels. jnd_out is allocated: 1 channel, in units of
 * just-noticeable differences (1 = one JND). ref and test are not modified. */
jnd_status jnd_model_diff(jnd_model *m, const jnd_image *ref, const jnd_image *test,
                          const jnd_diff_inputs *in, jnd_image *jnd_out);

/* The same, using ref and test as scratch space: their pixels are destroyed
 * and they are freed. The low-memory path for large images. */
jnd_status jnd_model_diff_consume(jnd_model *m, jnd_image *ref, jnd_image *test,
                                  const jnd_diff_inputs *in, jnd_image *jnd_out);

/* The same for images in CIE XYZ (cd/m²), for stimuli defined colorimetrically. */
jnd_status jnd_model_diff_xyz(jnd_model *m, const jnd_image *ref_xyz, const jnd_image *test_xyz,
                              const jnd_diff_inputs *in, jnd_image *jnd_out);

/* Probability of detection from JND (000 eq. 4): 1 − exp(ln 0.5 · jnd^beta). */
double jnd_probability(double jnd, double beta);

/* The JND a probability corresponds to (the inverse of jnd_probability). */
double jnd_probability_inverse(double p, double beta);

/* The peak frequency of each contrast pyramid band of the model, cycles per
 * degree (finest first); returns the number of bands (at most max). */
int jnd_model_band_peaks(const jnd_model *m, double *cpd, int max);

/* ------------------------------------------------------------------------ */
/* Pooling (000 §6)                                                         */
/* ------------------------------------------------------------------------ */

/* How a map becomes one number. */
typedef enum { JND_POOL_PERCENTILE = 0, JND_POOL_MAX, JND_POOL_MEAN, JND_POOL_MINKOWSKI } jnd_pool_kind;
typedef struct {
  jnd_pool_kind kind;
  double percentile;         /* 0..100 for JND_POOL_PERCENTILE; default 93 (000 §6) */
} jnd_pooling;

/* The p-th percentile (0..100, linear interpolation between order
 * statistics) of n values; values is not modified. NaN for n = 0. */
double jnd_percentile(const float *values, size_t n, double p);

/* Pools n values by kind (Minkowski mean with exponent e). */
double jnd_pool(const float *values, size_t n, const jnd_pooling *pool, double e);

/* Parses "p93", "max", "mean", "minkowski" or "pNN[.N]". */
jnd_status jnd_pooling_parse(const char *s, jnd_pooling *out);

/* The name of a pooling ("p93", "max", ...) written into buf. */
const char *jnd_pooling_name(const jnd_pooling *p, char *buf, size_t n);

/* Statistics of one comparison. */
typedef struct {
  double p_detect;           /* pooled probability with the pooling asked for (default p93) */
  double p_p50, p_p93, p_p99, p_max, p_mean;
  double jnd_mean, jnd_p93, jnd_max;
  double jnd_minkowski;      /* Minkowski mean of the JND map (exponent 2.4) */
} jnd_diff_stats;

/* Summarises a JND map: the P map (000 eq. 4, slope beta) pooled every way;
 * pool NULL means p93. */
jnd_status jnd_diff_summarise(const jnd_image *jnd_map, double beta, const jnd_pooling *pool,
                              jnd_diff_stats *stats);

/* The view criterion (000 §9): a candidate passes when at most a fraction q
 * of the sampled views have P above p (000: p = 0.2, q = 0.1). */
typedef struct {
  int views;             /* n, the number of views */
  int above;             /* views with P > p */
  int allowed;           /* floor(q·n): views that may be above p */
  double statistic;      /* the (allowed + 1)-th largest P: passes exactly when statistic <= p */
  int worst_view;        /* index of the largest P (the first of equals) */
  int pass;              /* above <= allowed */
  double fraction_above; /* above / n */
  double fraction_upper; /* one-sided upper confidence bound (Clopper–Pearson, at the confidence asked)
                            on the fraction of all possible views above p, given `above` of n */
} jnd_criterion_result;

/* Applies the criterion to the per-view probabilities p_views[0..n) (n >= 1,
 * each in 0..1), threshold p (0..1), fraction q (0 <= q < 1) and confidence
 * (0 < confidence < 1, e.g. 0.9) for the upper bound. */
jnd_status jnd_criterion_eval(const double *p_views, int n, double p, double q, double confidence,
                              jnd_criterion_result *out);

/* The one-sided Clopper–Pearson upper bound on a binomial proportion: the
 * largest u with P(X <= k | n, u) >= 1 − confidence (1 when k = n). */
double jnd_binomial_upper(int k, int n, double confidence);

/* ------------------------------------------------------------------------ */
/* Scene                                                                    */
/* ------------------------------------------------------------------------ */
/* An asset as the renderer sees it: triangle meshes in object units (the
 * file's units, node transforms applied), glTF metallic-roughness materials
 * and their texture maps. Every map of every material is addressable by a
 * name "MATERIAL/SLOT" (e.g. "Helmet/baseColor") and can be replaced for a
 * rendering by a resampled version at any resolution (000 §4). */

typedef struct jnd_scene jnd_scene;

/* The texture slots of a material (glTF 2.0 metallic-roughness). */
typedef enum {
  JND_MAP_BASE_COLOR = 0,      /* "baseColor": sRGB RGB(A), × base colour factor */
  JND_MAP_METALLIC_ROUGHNESS,  /* "metallicRoughness": G = roughness, B = metallic */
  JND_MAP_NORMAL,              /* "normal": tangent-space normal, RGB = (xyz + 1) / 2 */
  JND_MAP_OCCLUSION,           /* "occlusion": R = ambient occlusion */
  JND_MAP_EMISSIVE,            /* "emissive": sRGB RGB, × emissive factor */
  JND_MAP_SLOTS
} jnd_map_slot;

/* How a map's values are resampled (000 §4). */
typedef enum {
  JND_MAP_KIND_COLOR = 0,      /* sRGB-encoded colour: filtered in linear light; alpha as is */
  JND_MAP_KIND_NORMAL,         /* unit vectors encoded as (v + 1) / 2: renormalised after filtering */
  JND_MAP_KIND_DATA            /* plain values (roughness, metallic, occlusion) */
} jnd_map_kind;

typedef enum { JND_ALPHA_OPAQUE = 0, JND_ALPHA_MASK, JND_ALPHA_BLEND } jnd_alpha_mode;

/* The slot's name ("baseColor", "metallicRoughness", "normal", "occlusion",
 * "emissive") and the kind of values it holds. */
const char *jnd_map_slot_name(jnd_map_slot slot);
jnd_map_kind jnd_map_slot_kind(jnd_map_slot slot);

/* Loads a glTF 2.0 (.gltf with external or embedded buffers, .glb) or OBJ +
 * MTL file with assimp: triangulated, node transforms applied, tangents
 * computed where the file has none (docs/render.md). A texture file that is
 * missing or unreadable is not an error: the slot falls back to its factor
 * and a warning is recorded (jnd_scene_warning). A malformed model, or one
 * without triangles, is JND_ERR_FORMAT "PATH: problem"; a missing model
 * JND_ERR_IO. *out is owned by the caller (jnd_scene_free). */
jnd_status jnd_scene_load(const char *path, jnd_scene **out);

/* Parameters of the built-in procedural asset. */
typedef struct {
  int map_size;          /* side of the square texture maps, pixels (default 2048) */
  int shape;             /* 0: rounded box (default), 1: sphere */
  uint64_t seed;         /* seed of the procedural detail (default 1) */
} jnd_builtin_params;

/* Fills p with the defaults above. */
void jnd_builtin_defaults(jnd_builtin_params *p);

/* Makes the built-in asset needing no files: a rounded box of side 2 (or a
 * sphere of radius 1) in object units, centred at the origin, with one
 * material "builtin" carrying baseColor (fine albedo detail), normal (from
 * a height field), metallicRoughness (roughness variation) and occlusion
 * maps of map_size² pixels. p may be NULL (defaults). */
jnd_status jnd_scene_builtin(const jnd_builtin_params *p, jnd_scene **out);

/* Frees a scene and all its maps; safe on NULL. A renderer that drew it
 * forgets it on its next rendering of another scene. */
void jnd_scene_free(jnd_scene *s);

/* The path the scene came from ("builtin" for the procedural asset). */
const char *jnd_scene_path(const jnd_scene *s);

/* Counts: meshes (after triangulation), triangles, materials. */
int jnd_scene_mesh_count(const jnd_scene *s);
size_t jnd_scene_triangle_count(const jnd_scene *s);
int jnd_scene_material_count(const jnd_scene *s);
const char *jnd_scene_material_name(const jnd_scene *s, int material);

/* The bounding sphere of the scene (object units): centre[3] and radius. */
void jnd_scene_bounds(const jnd_scene *s, double centre[3], double *radius);

/* Warnings recorded while loading (missing textures, ...): count, and the
 * i-th one-line message (owned by the scene). */
int jnd_scene_warning_count(const jnd_scene *s);
const char *jnd_scene_warning(const jnd_scene *s, int i);

/* One texture map of a material. */
typedef struct {
  char name[128];        /* "MATERIAL/SLOT" */
  int material;          /* material index */
  jnd_map_slot slot;
  jnd_map_kind kind;
  int width, height;     /* resolution used for rendering now, pixels */
  int orig_width, orig_height;  /* resolution in the file, pixels */
  int channels;          /* 1–4 */
  int uv_set;            /* texture coordinate set, 0 or 1 */
  float uv_transform[6]; /* glTF KHR_texture_transform as an affine map of the uvs:
                            u' = t[0]u + t[1]v + t[2], v' = t[3]u + t[4]v + t[5];
                            {1, 0, 0, 0, 1, 0} without one */
} jnd_map_info;

/* Number of texture maps (material slots that have a texture), and the
 * description of map i (0 ≤ i < count), in material order then slot order. */
int jnd_scene_map_count(const jnd_scene *s);
jnd_status jnd_scene_map_info(const jnd_scene *s, int i, jnd_map_info *info);

/* The index of the map called name ("MATERIAL/SLOT"), or -1. Material names
 * that repeat get "#N" appended in file order (docs/render.md). */
int jnd_scene_map_find(const jnd_scene *s, const char *name);

/* Replaces map i for subsequent renderings by the original resampled to
 * w × h pixels (any size ≥ 1, not only powers of two) with
 * jnd_resample_map. w, h equal to the original restore it exactly. */
jnd_status jnd_scene_map_resize(jnd_scene *s, int i, int w, int h);

/* Replaces map i by a copy of img (the caller keeps img), in the slot's
 * encoding: values 0..1, sRGB-encoded for colour slots, (v + 1) / 2 for
 * normals; 1–4 channels, any size. */
jnd_status jnd_scene_map_set(jnd_scene *s, int i, const jnd_image *img);

/* Restores map i to the file's version. */
void jnd_scene_map_restore(jnd_scene *s, int i);

/* A copy of map i as used now (caller frees it); orig = 1 for the file's version. */
jnd_status jnd_scene_map_get(const jnd_scene *s, int i, int orig, jnd_image *out);

/* Resamples a texture map to w × h pixels with a separable Lanczos-3 filter
 * (000 §4), widened by the scale factor when shrinking so that it
 * antialiases. Colour maps (values sRGB-encoded 0..1) are filtered in linear
 * light and re-encoded, with alpha filtered as is; normal maps are decoded
 * to vectors, filtered and renormalised; data maps are filtered as plain
 * values. Results are clamped to 0..1. Edges are clamped (wrap = 0) or
 * wrapped (wrap = 1, for tiling maps). out is allocated (caller frees). */
jnd_status jnd_resample_map(const jnd_image *in, int w, int h, jnd_map_kind kind, int wrap,
                            jnd_image *out);

/* ------------------------------------------------------------------------ */
/* Renderer                                                                 */
/* ------------------------------------------------------------------------ */
/* A headless OpenGL 4.5 core renderer (EGL, no window system: a GPU through
 * the EGL device platform when there is one, else Mesa's surfaceless
 * platform, e.g. llvmpipe on the CPU). It shades with Cook–Torrance (GGX,
 * Smith masking, Schlick Fresnel), normal, occlusion and emissive maps,
 * image-based lighting from an equirectangular environment and up to
 * JND_MAX_LIGHTS punctual lights; textures are sampled as engines do
 * (full mip chains, trilinear, 8× anisotropic). An instance stays open for
 * any number of renderings: meshes and textures are uploaded once per scene
 * and only changed maps are uploaded again. Not thread-safe: one thread uses
 * one renderer. See docs/render.md. */

typedef struct jnd_renderer jnd_renderer;

#define JND_MAX_LIGHTS 8

typedef struct {
  int width, height;        /* image size, pixels (default 512 × 512) */
  int samples;              /* MSAA samples of the colour pass (default 4; capped by the driver) */
  int anisotropy;           /* maximum anisotropy (default 8) */
  const char *env_path;     /* equirectangular .hdr/.exr environment; NULL: the built-in studio */
  const char *platform;     /* NULL/"auto", "device" or "surfaceless" (also $JND_EGL_PLATFORM) */
} jnd_renderer_params;

/* Fills p with the defaults above (512 × 512, 4 samples, anisotropy 8, studio). */
void jnd_renderer_defaults(jnd_renderer_params *p);

/* Opens the EGL display and an OpenGL 4.5 core context, compiles the
 * shaders and prepares the environment (diffuse irradiance as spherical
 * harmonics, specular prefiltered per roughness; computed at load).
 * JND_ERR_GL when no context can be had; JND_ERR_IO/FORMAT for a bad
 * environment file. *out is owned by the caller (jnd_renderer_free). */
jnd_status jnd_renderer_create(const jnd_renderer_params *p, jnd_renderer **out);

/* Frees the renderer's GL objects and context; safe on NULL. The EGL
 * display stays initialised for the process (it is shared by renderers). */
void jnd_renderer_free(jnd_renderer *r);

/* "GL_RENDERER string (EGL platform)", e.g. "llvmpipe (LLVM 15.0.6, 256 bits) (surfaceless)". */
const char *jnd_renderer_description(const jnd_renderer *r);

/* Changes the output size (pixels) for the next renderings. */
jnd_status jnd_renderer_resize(jnd_renderer *r, int width, int height);

/* A pinhole camera, object units. */
typedef struct {
  double eye[3], target[3], up[3];
  double fov_y_deg;          /* vertical field of view, degrees */
  double znear, zfar;        /* clip distances, object units (0: from the scene bounds) */
} jnd_camera;

typedef enum { JND_LIGHT_DIRECTIONAL = 0, JND_LIGHT_POINT, JND_LIGHT_SPOT } jnd_light_type;

typedef struct {
  jnd_light_type type;
  double position[3];        /* point, spot: object units */
  double direction[3];       /* directional, spot: the direction the light travels */
  double color[3];           /* linear RGB, multiplied by intensity */
  double intensity;          /* directional: illuminance (1 = white diffuse surface facing
                                it reflects radiance 1/π); point/spot: intensity, falls off 1/d² */
  double range;              /* point/spot: 0 = unlimited, else a smooth cut-off, object units */
  double inner_deg, outer_deg; /* spot cone half-angles, degrees */
} jnd_light;

/* Outputs of a rendering (bit flags). */
enum {
  JND_OUT_COLOR = 1,         /* linear RGB (after exposure), 4× MSAA resolved */
  JND_OUT_DEPTH = 2,         /* distance along the view axis, object units; 0 off the object */
  JND_OUT_MASK = 4,          /* object coverage 0..1 (MSAA-resolved silhouette) */
  JND_OUT_MOTION = 8,        /* screen displacement from the previous pose, pixels (x right, y down) */
  JND_OUT_MIP = 16           /* per slot, the mip level sampled (−1 where no map or no object),
                                and the material index per pixel */
};

/* Everything that defines one image. */
typedef struct {
  jnd_camera camera;
  double model[16];          /* object-to-world transform, column-major (identity by default) */
  int has_prev;              /* 1: prev_camera / prev_model give the previous pose for motion */
  jnd_camera prev_camera;
  double prev_model[16];
  jnd_light lights[JND_MAX_LIGHTS];
  int nlights;
  double env_intensity;      /* multiplier on the environment (default 1; 0: no IBL) */
  double env_rotation_deg;   /* rotation of the environment about +Y, degrees */
  double exposure;           /* multiplier on the linear result (default 1) */
  int background_env;        /* 1: the environment is visible behind the object; 0: black */
  unsigned outputs;          /* JND_OUT_* (default colour) */
} jnd_view;

/* A view with a camera at distance 3 on +Z looking at the origin, fov 45°,
 * no punctual lights, environment intensity 1, exposure 1, colour only. */
void jnd_view_defaults(jnd_view *v);

/* The images of one rendering (each allocated only when asked for; the
 * caller frees them with jnd_frame_free). Row 0 is the top of the image. */
typedef struct {
  jnd_image color;           /* 3 channels, linear light */
  jnd_image depth;           /* 1 channel */
  jnd_image mask;            /* 1 channel */
  jnd_image motion;          /* 2 channels */
  jnd_image mip;             /* JND_MAP_SLOTS channels, in jnd_map_slot order: the mip level
                                (0 = full resolution, fractional between levels) that
                                trilinear + anisotropic filtering samples; −1 where none */
  jnd_image material;        /* 1 channel: material index of the pixel, −1 off the object
                                (with JND_OUT_MIP, so that levels can be pooled per map) */
} jnd_frame;

/* Frees the images of a frame; safe on a zeroed frame. */
void jnd_frame_free(jnd_frame *f);

/* Renders scene as seen from view into frame (allocated; previous contents
 * are not freed). The scene's meshes and textures are uploaded on first use
 * and kept while the same scene is rendered; maps changed since (resize,
 * set, restore) are uploaded again. */
jnd_status jnd_render(jnd_renderer *r, const jnd_scene *scene, const jnd_view *view,
                      jnd_frame *frame);

/* Display transform: linear RGB × 1 → sRGB-encoded 0..1 (clamped), for PNG. */
jnd_status jnd_render_to_srgb(const jnd_image *linear, jnd_image *out);

/* How views are sampled around an object. */
typedef struct {
  int count;                 /* number of views (default 8) */
  uint64_t seed;             /* seed of the rotation of the point set and of the lights (default 1) */
  double coverage;           /* fraction of the image height the bounding sphere fills (default 0.8) */
  double distance;           /* > 0: camera distance from the centre in object units, overriding coverage */
  double fov_y_deg;          /* vertical field of view, degrees (default 45) */
  double aspect;             /* width / height of the image (default 1) */
  double min_elevation_deg;  /* lowest camera elevation, degrees (default −60) */
  double max_elevation_deg;  /* highest (default 75) */
  int lights;                /* directional key lights sampled per view (default 1) */
  double light_intensity;    /* their illuminance (default 2) */
} jnd_view_sampling;

/* Fills p with the defaults above. */
void jnd_view_sampling_defaults(jnd_view_sampling *p);

/* Fills views[0..count-1] (caller-allocated) with cameras on a sphere around
 * the scene's bounding sphere: a Fibonacci spiral over the allowed band of
 * elevations, rotated about +Y by a seeded angle, looking at the centre;
 * each gets p->lights directional lights from the seeded generator, coming
 * from above and from the camera's side. Deterministic in p. Every other
 * field is from jnd_view_defaults. */
jnd_status jnd_views_sample(const jnd_scene *scene, const jnd_view_sampling *p, jnd_view *views);

/* Views from JSON text (what `jnd render --cameras` reads): a list of views,
 * or {"views": [...]}; each view is a camera {"eye", "target" (default
 * centre), "up" (default +Y), "fov_y_deg" or "fov" (default fov_y_deg),
 * "znear", "zfar"} or {"camera": {...}, "prev": {...} (the previous frame's
 * camera, for motion vectors), "lights": [{"type": "directional" | "point" |
 * "spot", "position", "direction", "color", "intensity", "range",
 * "inner_deg", "outer_deg"}]}. A view without "lights" gets nlights = −1 (the
 * caller fills them). *out is allocated (free it); name is used in errors. */
jnd_status jnd_views_parse(const char *name, const char *text, size_t n, const double centre[3], double fov_y_deg,
                           jnd_view **out, int *count);

/* The camera distance (object units) at which a sphere of radius r fills
 * fraction coverage of the image height with vertical field of view fov. */
double jnd_camera_distance_for_coverage(double radius, double coverage, double fov_y_deg);

/* ------------------------------------------------------------------------ */
/* Texture-set PCA (001)                                                    */
/* ------------------------------------------------------------------------ */
/* A material's maps (albedo, normal, roughness, ...) packed as one (w·h) × C
 * matrix and decorrelated by a principal component analysis (Wronski, 001):
 * a few components at full resolution carry most of the information, the
 * rest can be shrunk, quantised or dropped. Values are used as stored (0..1,
 * not linearised), as 001 does. Typical use:
 *
 *     jnd_texset set;  jnd_texset_read(paths, n, NULL, &set);
 *     jnd_pca pca;     jnd_pca_analyse(&set, NULL, &pca);        // weights 1
 *     jnd_pca_encoding e;  jnd_pca_encoding_default(&pca, &e);  // all at full, 8-bit
 *     e.components = 5;
 *     jnd_pca_encoded enc;  jnd_pca_encode(&set, &pca, &e, &enc);
 *     // enc.psnr_db[c] per channel, enc.comp[k] images, enc.recon the matrix
 *     jnd_pca_encoded_free(&enc);  jnd_texset_free(&set);
 */

#define JND_PCA_MAX_CHANNELS 32   /* channels of a set */
#define JND_PCA_MAX_MAPS 16       /* maps of a set */
#define JND_PCA_MAX_SCALE 3       /* coarsest component resolution: 1/2^3 */

/* One map of a texture set and where its channels went. */
typedef struct {
  char name[64];        /* file stem less the prefix every map shares ("Default_") */
  int file_w, file_h;   /* the file's size, pixels */
  int file_channels;    /* channels in the file (1–4) */
  int resampled;        /* 1: the file was resampled (Lanczos-3) to the set's size */
  int first, count;     /* its channels in the set: first .. first + count − 1 */
  int src[4];           /* file channel (0 = R .. 3 = A) of each of its set channels */
  int duplicates;       /* file channels left out as exact copies of another (grey stored as RGB) */
  int constants;        /* file channels left out because they are constant */
  int from[4];          /* for each file channel: the set channel that carries it
                           (an identical copy's source too), or −1 if constant */
  float constant[4];    /* the value of each constant file channel */
} jnd_texset_map;

/* A texture set: C channels of one size, planar, values as stored. */
typedef struct {
  int w, h, c;                                /* pixels, channels */
  float *data;                                /* c planes of w·h floats; owned, jnd_texset_free */
  int nmaps;
  jnd_texset_map maps[JND_PCA_MAX_MAPS];
  char names[JND_PCA_MAX_CHANNELS][72];       /* "albedo.r", ... or the map name for a grey map */
  int map_of[JND_PCA_MAX_CHANNELS];           /* index into maps of each channel */
} jnd_texset;

/* Builds a set from n decoded maps (each 1–4 channels; names[i] is map i's
 * name). Maps smaller or larger than the largest are resampled to it with a
 * Lanczos-3 filter (maps[i].resampled says so); a map whose aspect ratio
 * differs is refused (JND_ERR_ARG, "NAME: ..."). Without a pick, a map keeps
 * every channel that carries information: channels identical to an earlier
 * one of the same map (a grey JPEG stored as RGB) and constant channels are
 * left out (one channel is always kept). channels (NULL or "") picks
 * explicitly: "normal=rg,metalRoughness=gb" (MAP=letters among r, g, b, a).
 * The images are not modified; out owns new memory. */
jnd_status jnd_texset_from_images(const jnd_image *maps, const char *const *names, int n,
                                  const char *channels, jnd_texset *out);

/* Reads n map files (PNG, JPEG, HDR, EXR) and builds the set as above; map
 * names are the file stems less their shared prefix. Errors name the file:
 * "PATH: problem". */
jnd_status jnd_texset_read(const char *const *paths, int n, const char *channels, jnd_texset *out);

/* Frees the planes and zeroes the struct; safe on a zeroed struct. */
void jnd_texset_free(jnd_texset *set);

/* Rebuilds map `map` as its file had it (file_channels channels, the set's
 * size) from channels, a w × h × C image in the set's channel order (the set
 * itself or a reconstruction): identical copies are filled from their
 * source, constant channels with their value, channels --channels left out
 * with 0. out is allocated. */
jnd_status jnd_texset_map_image(const jnd_texset *set, const jnd_image *channels, int map, jnd_image *out);

/* Parses per-channel importance weights (001 "Input channel weighting"):
 * "albedo=2,height=0.75"; a key is a map name (all its channels) or a
 * channel name ("albedo.g"). weights[c] for c < set->c is filled: 1 where
 * not named. Weights must be > 0. JND_ERR_ARG for an unknown name. */
jnd_status jnd_texset_parse_weights(const jnd_texset *set, const char *spec, double *weights);

/* The decomposition of a set. Channel c enters as weight[c]·(x_c − mean[c]);
 * no standardisation (001: ranges already carry importance). */
typedef struct {
  int c;                                           /* channels (= components) */
  double mean[JND_PCA_MAX_CHANNELS];               /* per channel, as stored */
  double weight[JND_PCA_MAX_CHANNELS];
  double energy[JND_PCA_MAX_CHANNELS];             /* variance of each component, descending
                                                      (eigenvalues of the weighted covariance) */
  double total_variance;                           /* Σ weighted channel variances = Σ energy */
  double basis[JND_PCA_MAX_CHANNELS * JND_PCA_MAX_CHANNELS];
      /* basis[c·C + k]: unit column k, component k in weighted channel space;
       * its largest-magnitude entry is positive (deterministic sign) */
  int knee;                                        /* components up to the knee of the
                                                      cumulative energy curve (001) */
} jnd_pca;

/* Mean-centres the set, weights it (weights NULL = all 1), accumulates the
 * C × C covariance in double precision (fixed-order reduction: results do not
 * depend on threads) and eigen-decomposes it with LAPACK (dsyev). */
jnd_status jnd_pca_analyse(const jnd_texset *set, const double *weights, jnd_pca *out);

/* The contribution matrix |S·Tᵀ| of 001: out[k·C + c] = sqrt(energy_k) ·
 * |basis[c·C + k]|, how much input channel c feeds component k. out holds
 * C·C doubles (caller's). */
void jnd_pca_contribution(const jnd_pca *pca, double *out);

/* A picture of the contribution matrix: a row per input channel (named
 * from set; NULL: numbered), a column per component (1 = the most energy,
 * with its share of the energy), each cell coloured and labelled with its
 * contribution, and a colour legend. out is allocated (3 channels, sRGB
 * 0..1) for jnd_image_write_png. */
jnd_status jnd_pca_contribution_plot(const jnd_pca *pca, const jnd_texset *set, jnd_image *out);

/* How the components are stored. */
typedef struct {
  int components;                        /* K: components kept, 0..C */
  int scale[JND_PCA_MAX_CHANNELS];       /* component k at 1/2^scale[k] of the size
                                            (0 full, 1 half, ... JND_PCA_MAX_SCALE);
                                            box-filtered down, Lanczos-3 up */
  int bits[JND_PCA_MAX_CHANNELS];        /* 8 or 16; 0 = float, no quantisation */
} jnd_pca_encoding;

/* All C components at full resolution with 8 bits. */
void jnd_pca_encoding_default(const jnd_pca *pca, jnd_pca_encoding *e);

/* Storage of an encoding of a w × h set in bytes: Σ_k pixels_k · bits_k / 8
 * (float counts 4 bytes) plus the float32 reconstruction matrix. */
size_t jnd_pca_storage_bytes(const jnd_pca_encoding *e, int c, int w, int h);

/* An encoded set. Stored value q ∈ [0,1] of component k stands for the
 * component value offset[k] + scale[k]·q. The reconstruction of channel c
 * is x_c = Σ_k recon[c·(K+1) + k]·q_k + recon[c·(K+1) + K]: a C × (K+1)
 * homogeneous matrix, row-major, K + 1 multiply-adds per channel (001
 * "Runtime cost"; weights and means folded in). */
typedef struct {
  jnd_pca_encoding enc;
  int c, w, h;                               /* the set's channels and size */
  jnd_image comp[JND_PCA_MAX_CHANNELS];      /* K one-channel images, 0..1, at their sizes */
  double scale[JND_PCA_MAX_CHANNELS], offset[JND_PCA_MAX_CHANNELS];
  double recon[JND_PCA_MAX_CHANNELS * (JND_PCA_MAX_CHANNELS + 1)];
  double psnr_db[JND_PCA_MAX_CHANNELS];      /* per input channel, peak 1 (INFINITY if exact) */
  double mse[JND_PCA_MAX_CHANNELS];
  size_t storage_bytes;                      /* jnd_pca_storage_bytes */
} jnd_pca_encoded;

/* Projects the set on the first K components, stores each at its scale and
 * bit depth, reconstructs at full size and measures PSNR per channel
 * (10·log10(1/MSE), values 0..1, as 001). out owns the component images. */
jnd_status jnd_pca_encode(const jnd_texset *set, const jnd_pca *pca, const jnd_pca_encoding *e,
                          jnd_pca_encoded *out);

/* Reconstructs the set (w × h × C, allocated in out) from components comp
 * (K images, 0..1, any of the sizes 1/2^s; NULL = enc->comp), e.g. after
 * block compression. */
jnd_status jnd_pca_reconstruct(const jnd_pca_encoded *enc, const jnd_image *comp, jnd_image *out);

/* Per-channel PSNR (dB, peak 1) of a reconstruction (w × h × C) against the
 * set; mse may be NULL. */
jnd_status jnd_texset_psnr(const jnd_texset *set, const jnd_image *recon, double *psnr_db, double *mse);

/* Frees the component images; safe on a zeroed struct. */
void jnd_pca_encoded_free(jnd_pca_encoded *enc);

/* The smallest encoding (K, per-component scale in 0..max_scale, bits 8 or
 * 16) whose every channel reaches min_psnr_db. Candidates are ranked with
 * an additive error model (components are decorrelated: a channel's MSE is
 * Σ_k basis[c][k]²·D_k / weight_c², D_k measured per component and option),
 * then the best is encoded for real and checked; out is that encoding.
 * JND_ERR_ARG when even all components at 16 bits miss the target. */
jnd_status jnd_pca_choose_psnr(const jnd_texset *set, const jnd_pca *pca, double min_psnr_db,
                               int max_scale, jnd_pca_encoding *out);

/* Rendered visibility (001 + the renderer + the vision model): the material
 * of a model is rendered from sampled views with its maps replaced by a
 * reconstruction of the set, and with the set itself (the reference), and
 * each view's JND map is pooled into a probability of detection P. An
 * encoding passes when at most a fraction max_fraction of the views has
 * P > max_p. See docs/pca.md "Rendered visibility". Typical use:
 *
 *     jnd_pca_render_params rp;  jnd_pca_render_defaults(&rp);
 *     jnd_pca_render *r;  jnd_pca_render_open("ctrl.glb", "body", &rp, &r);
 *     jnd_texset set;  jnd_map_slot slots[JND_PCA_MAX_MAPS];
 *     jnd_pca_render_material_set(r, NULL, &set, slots, NULL);  // the material's own maps
 *     jnd_pca_render_bind(r, &set, slots);                       // renders the reference once
 *     jnd_pca pca;  jnd_pca_analyse(&set, NULL, &pca);
 *     jnd_pca_encoding e;  jnd_pca_visibility v;
 *     jnd_pca_choose_rendered(r, &set, &pca, 2, &e, &v, NULL);   // the cheapest that passes
 *     jnd_pca_render_free(r);  jnd_texset_free(&set);
 */

#define JND_PCA_MAX_VIEWS 64    /* views of a rendered-visibility measurement */
#define JND_PCA_MAX_TRIED 32    /* candidates a rendered search records */

typedef struct {
  int views;                  /* sampled views (default 8), 1..JND_PCA_MAX_VIEWS */
  int width, height;          /* rendered image size, pixels (default 512 × 512) */
  double coverage;            /* fraction of the image height the bounding sphere fills (0.8) */
  uint64_t seed;              /* seed of the view sampling (1) */
  const char *platform;       /* EGL platform: NULL/"auto", "device", "surfaceless" */
  int builtin_map_size;       /* map side of the "builtin" asset, pixels (2048) */
  jnd_model_params model;     /* vision model and display (jnd_model_defaults) */
  jnd_pooling pool;           /* per-view pooling of the P map (p93, 000 §6) */
  double max_p;               /* a view is above when its pooled P > max_p (0.2) */
  double max_fraction;        /* at most this fraction of the views may be above (0.1) */
} jnd_pca_render_params;

/* Fills p with the defaults above. */
void jnd_pca_render_defaults(jnd_pca_render_params *p);

/* A model's material, an open renderer, the vision model and the sampled
 * views, kept for any number of measurements. Not thread-safe. */
typedef struct jnd_pca_render jnd_pca_render;

/* Loads model_path (glTF/GLB/OBJ, or "builtin", "builtin:sphere"), finds
 * material (JND_ERR_ARG "PATH: no material 'NAME' (...)" listing them),
 * opens a renderer of width × height (JND_ERR_GL without a context),
 * creates the vision model and samples the views. *out is the caller's
 * (jnd_pca_render_free). */
jnd_status jnd_pca_render_open(const char *model_path, const char *material, const jnd_pca_render_params *p,
                               jnd_pca_render **out);

/* Frees everything open; safe on NULL. */
void jnd_pca_render_free(jnd_pca_render *r);

/* "GL_RENDERER (platform)" of the renderer in use. */
const char *jnd_pca_render_description(const jnd_pca_render *r);

/* The material's own maps (the file's versions) as a texture set, maps
 * named after their slots ("baseColor", "normal", ...), with the channels
 * the shader reads: metallicRoughness G and B, occlusion R (channels, as in
 * jnd_texset_from_images, overrides per slot name); the other maps keep
 * their informative channels. slots[i] receives map i's slot (caller's,
 * JND_PCA_MAX_MAPS). orig_bytes (may be NULL) receives the bytes of the
 * distinct original images at 8 bits per channel (a glTF image packing
 * occlusion with metal-roughness counts once). JND_ERR_ARG when the material
 * has no texture maps. */
jnd_status jnd_pca_render_material_set(const jnd_pca_render *r, const char *channels, jnd_texset *set,
                                       jnd_map_slot *slots, size_t *orig_bytes);

/* The slot a map name suggests: an exact slot name, else by words (case
 * ignored): "emissive"/"emission" → emissive; "normal" → normal;
 * "metal"/"rough"/"orm" → metallicRoughness; "occlusion", "ao" (whole word)
 * → occlusion; "basecolor"/"base_color"/"albedo"/"diffuse"/"color"/"colour"
 * → baseColor. Returns 0 when none fits. */
int jnd_pca_slot_guess(const char *name, jnd_map_slot *slot);

/* Binds map i of set to slot slots[i] of the material (that slot must have
 * a texture in the model), and renders the reference: every view with the
 * set's own values in those slots (maps resampled to the set's size go
 * back to their file's size). The set must outlive the binding's use. */
jnd_status jnd_pca_render_bind(jnd_pca_render *r, const jnd_texset *set, const jnd_map_slot *slots);

/* Pooled probability of detection per view and the criterion. */
typedef struct {
  int views;
  double p[JND_PCA_MAX_VIEWS];   /* pooled P of each view, 0..1 */
  int above;                     /* views with P > max_p */
  int allowed;                   /* views allowed above: floor(max_fraction · views) */
  double p_criterion;            /* the (allowed + 1)-th largest P: passes iff <= max_p */
  int pass;                      /* above <= allowed */
} jnd_pca_visibility;

/* Renders every view with the bound maps rebuilt from channels (w × h × C
 * in the set's channel order: a reconstruction, e.g. jnd_pca_reconstruct)
 * and compares with the reference. The maps stay replaced until the next
 * call. */
jnd_status jnd_pca_render_measure(jnd_pca_render *r, const jnd_image *channels, jnd_pca_visibility *out);

/* What a rendered search tried, in the order tried. */
typedef struct {
  int candidates;                               /* encodings in the family */
  int tried;                                    /* rendered */
  jnd_pca_encoding enc[JND_PCA_MAX_TRIED];
  size_t storage_bytes[JND_PCA_MAX_TRIED];
  double psnr_target_db[JND_PCA_MAX_TRIED];     /* the PSNR floor that produced it (0: lossless) */
  jnd_pca_visibility vis[JND_PCA_MAX_TRIED];
  int chosen;                                   /* index into the arrays, -1 if none passed */
} jnd_pca_search_log;

/* The cheapest encoding whose rendering passes the criterion. Candidates:
 * for PSNR floors of 14, 16, ... 60 dB, the smallest encoding
 * jnd_pca_choose_psnr finds (K, scale 0..max_scale and 8/16 bits per
 * component), plus all components at 16 bits; deduplicated and sorted by
 * storage. Along that family P falls as storage grows, so the cheapest
 * passing candidate is found by bisection (about log2(n) renderings of all
 * views), then the floor is bisected (3 steps) between the failing
 * candidate below it and the chosen one, where a cheaper encoding may lie.
 * out and vis (may be NULL) receive the encoding and its
 * measurement, log (may be NULL) what was tried. JND_ERR_ARG when not even
 * the lossless candidate passes. */
jnd_status jnd_pca_choose_rendered(jnd_pca_render *r, const jnd_texset *set, const jnd_pca *pca, int max_scale,
                                   jnd_pca_encoding *out, jnd_pca_visibility *vis, jnd_pca_search_log *log);

/* The simple call: opens model_path with the defaults, binds the set's maps
 * to the slots their names suggest (jnd_pca_slot_guess), measures enc and
 * returns the criterion statistic (jnd_pca_visibility.p_criterion). */
jnd_status jnd_pca_rendered_visibility(const jnd_texset *set, const jnd_pca_encoded *enc,
                                       const char *model_path, const char *material,
                                       double *p_detect);

/* Block compression (001 "Caveats"). 8-bit texels; blocks of 4 × 4 texels,
 * the image edge replicated into partial blocks. BC1: 8 bytes a block, RGB
 * as two RGB565 endpoints and 2-bit indices (4-colour mode); BC4: 8 bytes,
 * one channel as two 8-bit endpoints and 3-bit indices; BC5: two BC4. */
typedef enum { JND_BC1 = 1, JND_BC4 = 4, JND_BC5 = 5 } jnd_bc_format;

/* Bytes a w × h texture takes in format f. */
size_t jnd_bc_size(jnd_bc_format f, int w, int h);

/* Encodes channels [first, first+n) of img (values 0..1, n = 3 for BC1,
 * 1 for BC4, 2 for BC5) into blocks (jnd_bc_size bytes, caller's). BC1 fits
 * the principal axis of each block then refines the endpoints by least
 * squares; BC4 starts from the block's min/max and refines likewise. */
jnd_status jnd_bc_encode(jnd_bc_format f, const jnd_image *img, int first, uint8_t *blocks);

/* Decodes blocks into channels [first, first+n) of img (already allocated
 * w × h, values 0..1 on the 8-bit grid). */
jnd_status jnd_bc_decode(jnd_bc_format f, const uint8_t *blocks, jnd_image *img, int first);

/* The set as it comes back from block compression, w × h × C in out
 * (allocated): JND_PCA_BC_PCA_BC4 / _BC1 compress the components of enc as
 * jnd_pca_block_compression does and reconstruct; JND_PCA_BC_PLAIN
 * compresses the maps themselves (enc unused, may be NULL). bytes (may be
 * NULL) receives the compressed size. */
typedef enum { JND_PCA_BC_PCA_BC4 = 0, JND_PCA_BC_PCA_BC1, JND_PCA_BC_PLAIN } jnd_pca_bc_variant;
jnd_status jnd_pca_block_compressed(const jnd_texset *set, const jnd_pca_encoded *enc, jnd_pca_bc_variant v,
                                    jnd_image *out, size_t *bytes);

/* PSNR and storage of the set under block compression. */
typedef struct {
  double psnr_pca_bc4_db[JND_PCA_MAX_CHANNELS]; /* components one each in BC4 (pairs as BC5) */
  double psnr_pca_bc1_db[JND_PCA_MAX_CHANNELS]; /* components by threes of one size in BC1
                                                   (a pair left over in BC5, one in BC4) */
  double psnr_plain_db[JND_PCA_MAX_CHANNELS];   /* the maps themselves: BC1 for 3 channels,
                                                   BC4 for 1, BC5 for 2, BC1+BC4 for 4 */
  size_t bytes_pca_bc4, bytes_pca_bc1, bytes_plain;
} jnd_pca_bc_report;

/* Encodes the components of enc (8-bit view of them) and the set's maps with
 * block compression, decodes, reconstructs and measures PSNR per channel. */
jnd_status jnd_pca_block_compression(const jnd_texset *set, const jnd_pca_encoded *enc,
                                     jnd_pca_bc_report *out);

/* ------------------------------------------------------------------------ */
/* Texture resolution (000)                                                 */
/* ------------------------------------------------------------------------ */
/* Which texture resolution nobody notices (Wolski et al. 2019, 000 §4–§9):
 * every map of an asset is shrunk to candidate sizes, the asset is rendered
 * from sampled views, each view is compared with the full-resolution
 * rendering, and the smallest maps are kept for which at most a fraction q
 * of the views have a pooled probability of detection above p. Also: the
 * cross-population psychometric function of 000 eq. 1 and its fit, memory
 * accounting of maps with their mip chains (000 Table 2), and calibration of
 * the model to measured thresholds (000 §6–§7). See docs/texres.md and
 * docs/calibrate.md. */

/* The cross-population psychometric function of 000 eq. 1 over texture
 * resolution r (pixels): P_det(r) = 1 − Θ(x; µ, σ), Θ the cumulative normal,
 * x = r (domain 0, pixels, as 000) or x = log2 r (domain 1, octaves). */
typedef struct {
  double mu, sigma;          /* in the domain's units (pixels or log2 pixels) */
  int log2_domain;           /* 0: x = r; 1: x = log2 r */
  double rmse;               /* root mean squared error of the fit in probability */
} jnd_psychometric;

/* P_det at resolution r (pixels) for f. */
double jnd_psychometric_eval(const jnd_psychometric *f, double r);

/* The resolution (pixels) where P_det = p (0 < p < 1). */
double jnd_psychometric_resolution(const jnd_psychometric *f, double p);

/* Fits µ and σ (σ > 0) of 000 eq. 1 to n >= 2 points (r[i] pixels > 0,
 * p[i] in 0..1) by least squares on probability: a small grid over (µ, log σ)
 * refined by Nelder–Mead from a probit-analysis start. Detection must fall as r grows; data that never
 * change (all 0 or all 1) give the nearest step function (σ small, µ just
 * outside the data's range). log2_domain picks the domain (see above).
 * JND_ERR_ARG for n < 2 or values out of range. */
jnd_status jnd_psychometric_fit(const double *r, const double *p, int n, int log2_domain,
                                jnd_psychometric *out);

/* Texture storage formats of the memory accounting (000 Table 2). */
typedef enum {
  JND_TEX_RGBA8 = 0,   /* uncompressed, 32 bits per texel */
  JND_TEX_BC1,         /* 4 bits per texel (8-byte 4×4 blocks) */
  JND_TEX_BC4,         /* 4 bits per texel, one channel */
  JND_TEX_BC5,         /* 8 bits per texel, two channels */
  JND_TEX_BC7,         /* 8 bits per texel (16-byte 4×4 blocks) */
  JND_TEX_ASTC4,       /* ASTC 4×4: 8 bits per texel */
  JND_TEX_ASTC6,       /* ASTC 6×6: 3.56 bits per texel (16-byte 6×6 blocks) */
  JND_TEX_FORMATS
} jnd_tex_format;

/* The format's name ("rgba8", "bc1", "bc4", "bc5", "bc7", "astc4x4", "astc6x6"). */
const char *jnd_tex_format_name(jnd_tex_format f);

/* Bytes of a w × h texture in format f; with mips = 1, of its full mip chain
 * (levels down to 1 × 1, each side halved and rounded down, at least 1; block
 * formats round each level up to whole blocks). */
size_t jnd_texture_bytes(jnd_tex_format f, int w, int h, int mips);

/* The block format engines usually pick for a slot: baseColor BC7 (BC1 for
 * channels <= 3 is smaller but BC7 is the quality default), normal BC5,
 * occlusion BC4, metallicRoughness BC1, emissive BC1. */
jnd_tex_format jnd_slot_block_format(jnd_map_slot slot, int channels);

/* A calibration of the model to a task (000 §6–§7): the per-pixel JND is
 * transformed to max(0, scale·JND + bias) before the psychometric function
 * P = 1 − exp(ln 0.5 · x^beta) (000 eq. 4), and the P map is pooled with the
 * given percentile. The identity is scale 1, bias 0, p93. */
typedef struct {
  double percentile;         /* pooling percentile, 0..100 (93) */
  double scale, bias;        /* linear transform of the JND map (1, 0) */
  double beta;               /* psychometric slope (3.5) */
  double threshold_p;        /* the P at which thresholds are read (0.2, 000 §6) */
  double mae_px;             /* fitted: cross-validated mean absolute error, pixels (0 unknown) */
} jnd_calibration;

/* Fills c with the identity calibration above. */
void jnd_calibration_defaults(jnd_calibration *c);

/* Reads a calibration file written by jnd_calibration_save / `jnd
 * calibrate` (JSON with "calibration": {"percentile", "scale", "bias",
 * "beta", ...}). JND_ERR_IO / JND_ERR_FORMAT "PATH: problem". */
jnd_status jnd_calibration_load(const char *path, jnd_calibration *c);

/* Writes c as JSON to path (atomic). */
jnd_status jnd_calibration_save(const char *path, const jnd_calibration *c);

/* The calibrated pooled probability of a JND map: JND → max(0, scale·JND +
 * bias) → P (eq. 4, c->beta) → c->percentile over the pixels where mask >
 * 0.5 (mask NULL: every pixel). NaN when no pixel counts. */
double jnd_calibration_pool(const jnd_calibration *c, const jnd_image *jnd_map, const jnd_image *mask);

/* Summarises a JND map as jnd_diff_summarise does, but through the
 * calibration: the JND statistics are of the transformed map, the P map uses
 * c->beta and p_detect is its c->percentile. */
jnd_status jnd_diff_summarise_calibrated(const jnd_image *jnd_map, const jnd_calibration *c,
                                         jnd_diff_stats *stats);

/* Calibration data: one scene (an asset's map, or a series of image pairs)
 * with the model's JND percentiles per tested resolution and the measured
 * cross-population threshold (000 eq. 1, pixels). */
#define JND_CALIB_PCT_LO 90   /* percentiles tested: 90 .. 99 (000 §6) */
#define JND_CALIB_NPCT 10
typedef struct {
  char name[128];            /* scene name; folds group by it */
  int nres;                  /* resolutions of the series (>= 2) */
  const double *res;         /* nres resolutions, pixels */
  const double *jnd_pct;     /* nres × JND_CALIB_NPCT: percentile 90 + k of the model's JND map
                                at res[i] (jnd_calib_percentiles) */
  double mu, sigma;          /* measured threshold distribution, pixels (000 eq. 1) */
} jnd_calib_scene;

/* The JND percentiles 90..99 of a map over the pixels where mask > 0.5 (mask
 * NULL: all), into out[JND_CALIB_NPCT]. */
jnd_status jnd_calib_percentiles(const jnd_image *jnd_map, const jnd_image *mask, double *out);

typedef struct {
  int folds;                 /* k of k-fold cross-validation by scene (5; at most the scenes) */
  double beta;               /* psychometric slope (3.5) */
  double threshold_p;        /* P at which threshold resolutions are compared (0.2) */
  double bias_min, bias_max; /* exhaustive bias range, JND (−2 .. 2) */
  int bias_steps;            /* grid steps over it (21) */
  double scale_min, scale_max; /* scale range (0.05 .. 20), searched in log */
} jnd_calibrate_params;

/* Fills p with the defaults above. */
void jnd_calibrate_defaults(jnd_calibrate_params *p);

/* What a calibration fit found. */
typedef struct {
  jnd_calibration cal;       /* fitted on all scenes */
  double mae_px;             /* training error on all scenes, pixels */
  int folds;
  double fold_mae_px[32];    /* held-out error of each fold, pixels */
  double cv_mae_px;          /* mean held-out absolute error over scenes, pixels */
  double *errors_px;         /* per scene: predicted − measured threshold, held out (pixels);
                                owned, jnd_calibrate_result_free */
  double *predicted_px;      /* per scene: predicted threshold with the final calibration */
  int nscenes;
  double pct_mae_px[JND_CALIB_NPCT]; /* best training error per percentile */
} jnd_calibrate_result;

/* Fits percentile (90..99), scale and bias minimising the mean absolute
 * error between predicted and measured threshold resolution (at P =
 * threshold_p) over the scenes, 000 §6–§7.1: per percentile, an exhaustive
 * search over bias with the best scale for each (golden section in log
 * scale), then a local refinement; the predicted threshold of a scene is
 * read from 000 eq. 1 fitted to the calibrated pooled P over its series,
 * in pixels as 000. Then k-fold cross-validation by scene (000 §7.3).
 * Deterministic. out owns arrays (jnd_calibrate_result_free). */
jnd_status jnd_calibrate_fit(const jnd_calib_scene *scenes, int n, const jnd_calibrate_params *p,
                             jnd_calibrate_result *out);

/* Frees the arrays of a result; safe on a zeroed struct. */
void jnd_calibrate_result_free(jnd_calibrate_result *r);

/* Parameters of a texture resolution search. */
typedef struct {
  int views;                 /* N sampled views for the choice (8) */
  int verify_views;          /* M further views for a held-out check (0: none) */
  uint64_t seed;             /* view sampling seed (1); held-out views use another seed */
  int width, height;         /* rendering size, pixels (384 × 384) */
  double coverage;           /* fraction of the image height the bounding sphere fills (0.8) */
  double distance;           /* > 0: camera distance in object units instead of coverage */
  double fov_y_deg;          /* vertical field of view (45) */
  int lights;                /* directional lights per view (1) */
  int anisotropy;            /* renderer anisotropy (8) */
  int samples;               /* MSAA samples (4) */
  const char *env_path;      /* environment (NULL: the studio) */
  const char *platform;      /* EGL platform (NULL: auto) */
  double p_threshold;        /* p: a view is "above" when its pooled P > p (0.2) */
  double max_fraction;       /* q: at most this fraction of views above p (0.1) */
  int min_size;              /* floor of the power-of-two candidates, pixels (32) */
  const int *sizes;          /* explicit candidate sizes (longer side, pixels) or NULL */
  int nsizes;
  const char *maps;          /* NULL: every map; else a comma list of MATERIAL/SLOT names or
                                bare slot names (that slot of every material) to search;
                                the others stay at their size */
  int matrix;                /* baseColor × normal matrix of each material that has both
                                (000 Fig. 13): 0 none; 1 the candidates down to each map's
                                first failure on its own; 2 (default) every candidate */
  jnd_calibration calibration; /* transform and pooling (identity p93 by default) */
  jnd_model_params model;    /* display and model constants */
  void (*progress)(void *user, int done, int total); /* NULL or called after each rendering */
  void *progress_user;
} jnd_texres_params;

/* Fills p with the defaults above. */
void jnd_texres_defaults(jnd_texres_params *p);

#define JND_TEXRES_MAX_CAND 16
/* The outcome for one map. */
typedef struct {
  char name[128];            /* MATERIAL/SLOT */
  int map, material;
  jnd_map_slot slot;
  int channels;
  int searched;              /* 0: not in --maps; kept at its size */
  int orig[2], chosen[2];    /* width, height in pixels */
  int mip_bound[2];          /* finest mip level any pixel of any view samples (000 §4) */
  double mip_min;            /* that level (fractional); −1: never sampled */
  int eye_bound[2];          /* texel density the eye can resolve at the condition */
  int ncand;                 /* candidates (descending), the first the original */
  int cand[JND_TEXRES_MAX_CAND][2];
  double series[JND_TEXRES_MAX_CAND]; /* the criterion statistic (the view quantile of pooled P)
                                with only this map at candidate k; NaN where not evaluated */
  jnd_psychometric fit;      /* 000 eq. 1 fitted to series (log2 domain) */
  int fit_ok;
  double fit_res;            /* continuous resolution at P = p (longer side, pixels) */
  int fit_cand[2];           /* rounded up to a candidate */
  size_t bytes_before[JND_TEX_FORMATS], bytes_after[JND_TEX_FORMATS]; /* with mip chains */
} jnd_texres_map;

/* A full two-map matrix (000 Fig. 13): p[(v·na + a)·nb + b], v a view,
 * a the first map's candidate, b the second's. */
typedef struct {
  int map_a, map_b;          /* indices into the result's maps */
  int na, nb, nviews;
  int size_a[JND_TEXRES_MAX_CAND], size_b[JND_TEXRES_MAX_CAND]; /* longer sides */
  double *p;                 /* owned */
  double *stat;              /* na × nb: the criterion statistic per cell */
  int best_a, best_b;        /* the passing cell with the least memory (−1: none) */
  int complete;              /* 1: every candidate of both maps; 0: smaller ones fail alone */
} jnd_texres_matrix;

/* The outcome of a search. */
typedef struct {
  int nmaps;
  jnd_texres_map *maps;      /* owned */
  int nviews;
  double *view_p;            /* pooled P per view of the chosen combination */
  double stat;               /* the criterion statistic of the choice */
  double fraction_above;     /* fraction of the views with P > p */
  int passes;                /* 1: fraction_above <= q */
  int verify_views;          /* M (0: not run) */
  double *verify_p;          /* pooled P per held-out view */
  double verify_fraction;    /* fraction of the held-out views above p */
  int verify_passes;
  int worst_view;            /* the view with the highest P (choice) */
  jnd_image worst_heatmap;   /* its heatmap (jnd_heatmap), sRGB 0..1 */
  int nmatrix;
  jnd_texres_matrix *matrix; /* owned */
  size_t before_bytes[JND_TEX_FORMATS], after_bytes[JND_TEX_FORMATS]; /* all maps, mip chains */
  double ppd;                /* the display's pixels per degree */
  int evaluations, renderings;
  char renderer[160];
} jnd_texres_result;

/* Runs the search of docs/texres.md on scene (loaded by the caller; its
 * maps are left at the chosen sizes on return): mip-usage bound, per-map
 * series from the bound down (stopping one candidate after the criterion
 * fails), coordinate descent over the maps until the combination passes,
 * the optional matrices, and the verification on held-out views. out owns
 * arrays (jnd_texres_result_free). JND_ERR_ARG for a scene without texture
 * maps or an unknown map name. */
jnd_status jnd_texres_run(jnd_scene *scene, const jnd_texres_params *p, jnd_texres_result *out);

/* Frees a result's arrays; safe on a zeroed struct. */
void jnd_texres_result_free(jnd_texres_result *r);

/* A picture of matrix t of a result (000 Fig. 13): the criterion statistic
 * for every pair of sizes (columns the first map's, rows the second's, the
 * longer side in pixels) with axis titles, each cell's value and a colour
 * legend of P, the chosen pair outlined; below it the same per view. out is
 * allocated (3 channels, sRGB 0..1) for jnd_image_write_png. */
jnd_status jnd_texres_matrix_figure(const jnd_texres_result *r, int t, jnd_image *out);

/* The model's JND percentiles 90..99 of map `map` (MATERIAL/SLOT) of scene
 * at nres sizes (longer side in pixels, aspect kept; the other maps as they
 * are), over the object's pixels of p->views sampled views together, each
 * against the rendering with the file's map: the image series of `jnd
 * calibrate` for an asset. out holds nres × JND_CALIB_NPCT doubles
 * (caller's). The map is restored on return. */
jnd_status jnd_texres_series_percentiles(jnd_scene *scene, const char *map, const int *sizes, int nres,
                                         const jnd_texres_params *p, double *out);

/* Writes a copy of the glTF/GLB model at src_path under out_dir whose maps
 * are the scene's maps at the sizes in use now (jnd_scene_map_get of each
 * resized map, encoded as the file had it: PNG or JPEG), and which points
 * at them; unchanged maps and buffers are copied. A .glb stays one .glb
 * file; a .gltf gets its images and buffers as files beside it. The model
 * file's name is kept. The input is never modified. out_path (NULL or
 * caller's, n bytes) receives the written model's path. */
jnd_status jnd_texres_write_model(const jnd_scene *scene, const char *src_path, const char *out_dir,
                                  char *out_path, size_t n);

/* ------------------------------------------------------------------------ */
/* Tasks                                                                    */
/* ------------------------------------------------------------------------ */

/* The built-in example pair (no files needed): a synthetic sRGB reference
 * (gradients, gratings, edges, colour, texture) and a test with four known
 * distortions, one per quadrant — 3×3 blur (top left), 1% noise (top right), a
 * colour shift (bottom left), a faint 1% luminance step (bottom right).
 * Both are allocated: w × h × 3, sRGB-encoded 0..1. w, h >= 64. */
jnd_status jnd_example_pair(int w, int h, jnd_image *ref, jnd_image *test);

/* A contrast-detection stimulus in castleCSF's terms (`jnd csf`). */
typedef enum { JND_STIM_GABOR = 0, JND_STIM_GRATING, JND_STIM_DISK } jnd_stim_kind;
typedef struct {
  jnd_stim_kind kind;
  double luminance;       /* background luminance, cd/m² */
  double s_frequency;     /* cycles per degree (0 for discs) */
  double t_frequency;     /* Hz; > 0: a drifting grating, seen under fixation */
  double area;            /* deg² (gratings: a square aperture; discs: a disc) */
  double ge_sigma;        /* Gabor envelope sigma, degrees */
  double eccentricity;    /* degrees from fixation */
  double orientation;     /* degrees */
  double bkg_lms[3];      /* background, CIE 2006 LMS (luminance = L + M) */
  double dir_lms[3];      /* colour direction of the modulation, CIE 2006 LMS */
} jnd_csf_stimulus;

typedef struct {
  double ppd;             /* sampling density used */
  int side_px;            /* image side */
  int evaluations;        /* model runs in the search */
} jnd_csf_detail;

/* A context for many threshold searches with one set of model constants: it
 * keeps the models it builds (one per sampling density and fixation) for
 * reuse. Not for concurrent use: give each thread its own. */
typedef struct jnd_csf_context jnd_csf_context;
jnd_status jnd_csf_context_create(const jnd_model_params *base, jnd_csf_context **out);
void jnd_csf_context_free(jnd_csf_context *ctx);

/* The model's sensitivity (1 / threshold RMS cone contrast) for a stimulus:
 * the contrast where the max-pooled probability of detection is 0.5, found in
 * log contrast. The context's constants are used; the display's ppd is
 * replaced by one suited to the stimulus (docs/csf.md). detail may be NULL. */
jnd_status jnd_csf_threshold(jnd_csf_context *ctx, const jnd_csf_stimulus *s, double *sensitivity,
                             jnd_csf_detail *detail);

/* The sampling chosen for a stimulus: pixels per degree, half-extent and edge taper in degrees. */
void jnd_csf_sampling(const jnd_csf_stimulus *s, double *ppd, double *half_deg, double *taper_deg);

/* `jnd diff` as a call: applies the model's display to two decoded files
 * (infos from jnd_image_read; alpha composited over the display's black),
 * compares them and summarises. ref and test are consumed (freed) to keep
 * memory low. jnd_out may be NULL when only the statistics are wanted. */
jnd_status jnd_diff_files(jnd_model *m, jnd_image *ref, const jnd_image_info *ref_info,
                          jnd_image *test, const jnd_image_info *test_info,
                          const jnd_diff_inputs *in, const jnd_pooling *pool,
                          jnd_image *jnd_out, jnd_diff_stats *stats);

/* ------------------------------------------------------------------------ */
/* Batch: a library of assets (docs/batch.md)                               */
/* ------------------------------------------------------------------------ */
/* A manifest lists assets, each with a jnd command (texres, pca, diff,
 * render) and that command's options. A batch runs each asset's command as
 * a child process of the jnd program (`jnd COMMAND ASSET OPTIONS -o DIR`), so
 * that a bad or crashing asset fails alone; its outputs appear in OUT/<id>/,
 * exactly as the command writes them, only once complete (a rename); a rerun
 * skips complete assets; shards split a manifest deterministically for job
 * arrays; merge writes OUT/summary.json and summary.csv; report writes a
 * static HTML site. Typical use:
 *
 *     jnd_batch_manifest m;  jnd_batch_manifest_read("assets.csv", NULL, NULL, &m);
 *     jnd_batch_params p;    jnd_batch_defaults(&p);
 *     p.out_dir = "out";     p.jnd_exe = "/usr/bin/jnd";
 *     jnd_batch_totals t;    jnd_batch_run(&m, &p, &t);   // rows' failures are in t, not errors
 *     jnd_batch_merge("out", 1, &t);  jnd_batch_report("out", NULL, 0);
 *     jnd_batch_manifest_free(&m);
 */

#define JND_BATCH_MAX_ID 100 /* bytes of an asset id */

/* One asset of a manifest. */
typedef struct {
  int line;             /* CSV: line of the file (the header is line 1); JSON: entry
                           (1-based); glob: match (1-based, sorted) */
  char *id;             /* [A-Za-z0-9][A-Za-z0-9._-]*: the folder OUT/<id> */
  char *asset;          /* path relative to the manifest's folder, or `builtin[:...]` */
  char *command;
  char *options;        /* as written: one shell-quoted string */
  int argc;             /* options as words (split as a shell does, never expanded) */
  char **argv;
  char *error;          /* NULL, or why this row cannot run: one line, "MANIFEST:LINE: ..." */
} jnd_batch_row;

typedef struct {
  char *source;         /* the manifest's path, or the glob, absolute */
  char *base_dir;       /* absolute folder where asset paths and options are resolved */
  int nrows;
  jnd_batch_row *rows;
} jnd_batch_manifest;

/* Reads a manifest: a CSV file with the header id,asset,command,options (any
 * order; options may be left out; RFC 4180 quoting), or a JSON file (a list,
 * or {"assets": [...]}, of objects with those keys; options a string or a
 * list of words). With command not NULL, path is instead a glob ("models/
 * *.glb", relative to the working folder) and every match becomes a row with
 * that command and options; its id is the match's path less the extension
 * and the folders all matches share, '/' as '-'. Rows are checked: a valid
 * unique id (ids equal but for case collide), a known command, options that
 * split and do not set what batch sets (-o, --json, ...), an asset file that
 * exists; a row that fails gets its one-line error and the others are kept.
 * Returns an error (unreadable file, malformed CSV/JSON, a wrong header, no
 * rows, no match) only for what no row survives. out is allocated. */
jnd_status jnd_batch_manifest_read(const char *path, const char *command, const char *options,
                                   jnd_batch_manifest *out);

/* The parsers under jnd_batch_manifest_read, on bytes (name is used in
 * messages; assets are not looked for: jnd_batch_manifest_check does that). */
jnd_status jnd_batch_manifest_parse_csv(const char *name, const char *text, size_t n, jnd_batch_manifest *out);
jnd_status jnd_batch_manifest_parse_json(const char *name, const char *text, size_t n, jnd_batch_manifest *out);
/* Marks rows whose asset file is missing (relative to m->base_dir). */
void jnd_batch_manifest_check(jnd_batch_manifest *m);
/* Frees every row and string and zeroes m; safe on a zeroed manifest. */
void jnd_batch_manifest_free(jnd_batch_manifest *m);

/* Parses a shard "I/N" (0 <= I < N <= 100000). JND_ERR_ARG with a message. */
jnd_status jnd_batch_shard_parse(const char *spec, int *index, int *count);

typedef enum {
  JND_ASSET_PENDING = 0, /* not run yet (its shard has not run, or was interrupted) */
  JND_ASSET_OK,          /* the command finished (exit 0), outputs complete */
  JND_ASSET_ABOVE,       /* finished with exit 1: complete, but the choice fails its
                            criterion (texres) or is above --fail-above (diff) */
  JND_ASSET_FAILED       /* bad row, bad input (exit 2), a crash or the timeout */
} jnd_asset_status;

/* What the progress callback hears after each asset of the shard. */
typedef struct {
  const char *id, *command;
  jnd_asset_status status;
  int skipped;           /* 1: complete from an earlier run, not run again */
  int exit_status;       /* the command's exit status; -1: killed (signal, timeout); -2: not run */
  const char *error;     /* the failure's one line, else NULL */
  double seconds;        /* this asset's wall time (0 when skipped) */
  int done, total;       /* assets of the shard finished so far, and in all */
  int failed;            /* failures so far */
  double elapsed_s;      /* since the run began */
} jnd_batch_event;

typedef struct {
  const char *out_dir;   /* OUT (created) */
  int shard, shards;     /* this run takes the rows whose index r (0-based, in manifest
                            order) has r % shards == shard; default 0 of 1 */
  int jobs;              /* assets run at the same time (1) */
  int threads;           /* threads of each asset's command (OMP_NUM_THREADS); 0: the
                            environment's OMP_NUM_THREADS, else the CPUs / jobs */
  double timeout_s;      /* a command running longer is killed; the asset fails (0: none) */
  int force;             /* run complete assets again */
  const char *jnd_exe;   /* the jnd program that runs each asset's command (NULL: "jnd"
                            on PATH) */
  void (*progress)(void *user, const jnd_batch_event *e);
  void *progress_user;
} jnd_batch_params;

/* Fills p with the defaults above: shard 0 of 1, one job, the environment's
 * threads, no timeout, no force, "jnd" on PATH, no progress callback. */
void jnd_batch_defaults(jnd_batch_params *p);

typedef struct {
  int assets;            /* rows (merge: all; run: this shard's) */
  int ran, skipped;      /* run: commands started; complete ones left alone */
  int ok, above, failed, pending;
} jnd_batch_totals;

/* Runs a shard of the manifest (docs/batch.md): for each row, in order, at
 * most p->jobs at once: a row with an error is a failure; a complete asset
 * (its last run finished, for the same command, options, asset file size and
 * time, and jnd version) is skipped unless p->force; otherwise its command
 * runs in OUT/_batch/work/<id>/ with the working folder m->base_dir; when it
 * finishes its outputs replace OUT/<id>/ by a rename and then its record
 * OUT/_batch/records/<id>.json is written (atomically): the record is what
 * makes an asset complete, so a crash at any point leaves either the old
 * result or the new one. A failure (exit 2, a signal, the timeout) records its
 * exit status and the last line of its stderr, and the batch goes on. Writes
 * the plan OUT/_batch/manifest.json (what merge reads). Returns an error only
 * for what stops the whole run (bad parameters, OUT not writable, fork
 * failing); totals may be NULL. */
jnd_status jnd_batch_run(const jnd_batch_manifest *m, const jnd_batch_params *p, jnd_batch_totals *totals);

/* Merges what the shards recorded in OUT into OUT/summary.json (the report
 * envelope: jnd_version, command "batch merge", inputs, parameters, result
 * {totals, assets[]}) and OUT/summary.csv, one row per manifest row in
 * manifest order: status, exit status, error, memory before and after, the
 * probability of detection, what was chosen, and (timings != 0) seconds.
 * Without timings the files depend only on the manifest and the assets'
 * reports: n shards merge to the bytes of a single run. totals may be NULL. */
jnd_status jnd_batch_merge(const char *out_dir, int timings, jnd_batch_totals *totals);

/* Writes the HTML report of OUT (after jnd_batch_merge): OUT/report/
 * index.html (totals; the assets in a table sortable by column and
 * filterable by status) and a page per asset with the numbers of its report
 * and the pictures that justify its decision, some drawn here (PNG under
 * OUT/report/<id>/). Self-contained: no network, works from file://.
 * index_path (n bytes, may be NULL) receives the index's path. */
jnd_status jnd_batch_report(const char *out_dir, char *index_path, size_t n);

/* A Slurm job array for a manifest: task i of the array runs shard i of
 * shards; a second job, dependent on the whole array (afterok), merges and
 * writes the report. */
typedef struct {
  int shards;              /* array tasks (>= 1) */
  int array_limit;         /* at most this many tasks at once (--array=0-(n-1)%limit; 0: no limit) */
  int cpus_per_task;       /* 1.. */
  const char *mem;         /* memory per task, sbatch syntax ("4G"); NULL: the cluster's default */
  const char *time;        /* time limit per task ("2:00:00", minutes, "1-00:00:00"); NULL: default */
  const char *partition, *account, *gres; /* NULL: none */
  const char *const *extra;/* further sbatch options, one "--name=value" each */
  int nextra;
  const char *job_name;    /* "jnd-batch" */
} jnd_slurm_params;

/* Fills p: 1 shard, no array limit, 1 CPU per task, the cluster's default
 * memory and time limit, no partition, account or GRES, job name "jnd-batch". */
void jnd_slurm_defaults(jnd_slurm_params *p);

/* The two job scripts, as text (caller frees): array_script runs `JND batch
 * SOURCE -o OUT --shard $SLURM_ARRAY_TASK_ID/N` (with run's jobs, threads,
 * timeout, force, and command/options for a glob) and merge_script runs `JND
 * batch merge OUT` and `JND report OUT`. Paths are made absolute. run->jnd_exe
 * is the program the nodes run. */
jnd_status jnd_slurm_scripts(const jnd_batch_manifest *m, const char *glob_command, const char *glob_options,
                             const jnd_batch_params *run, const jnd_slurm_params *sp, char **array_script,
                             char **merge_script);

/* Writes the scripts to OUT/_batch/slurm/{array,merge}.sh and submits them:
 * `sbatch --parsable array.sh`, then `sbatch --parsable
 * --dependency=afterok:ARRAY merge.sh`. The job ids are returned (n bytes
 * each). sbatch comes from PATH. */
jnd_status jnd_slurm_submit(const char *out_dir, const char *array_script, const char *merge_script,
                            char *array_job, char *merge_job, size_t n);

#ifdef __cplusplus
}
#endif
#endif /* JND_H */
