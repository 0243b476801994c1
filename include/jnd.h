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
 * (see docs/model.md). out is allocated (3 channels). */
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

/* ------------------------------------------------------------------------ */
/* Tasks                                                                    */
/* ------------------------------------------------------------------------ */

/* `jnd diff` as a call: applies the model's display to two decoded files
 * (infos from jnd_image_read; alpha composited over the display's black),
 * compares them and summarises. ref and test are consumed (freed) to keep
 * memory low. jnd_out may be NULL when only the statistics are wanted. */
jnd_status jnd_diff_files(jnd_model *m, jnd_image *ref, const jnd_image_info *ref_info,
                          jnd_image *test, const jnd_image_info *test_info,
                          const jnd_diff_inputs *in, const jnd_pooling *pool,
                          jnd_image *jnd_out, jnd_diff_stats *stats);

#ifdef __cplusplus
}
#endif
#endif /* JND_H */
