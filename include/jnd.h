/* jnd.h — the whole public API of libjnd.
 *
 * jnd answers "what is the cheapest asset nobody will notice?". Its core is a
 * model of human vision (Schwarz & Stamminger 2009, §3.1) that predicts, per
 * pixel, how many just-noticeable differences (JND) separate two images as a
 * viewer sees them on a given display, and the probability that a viewer
 * notices.
 *
 * Ten lines to make a model's textures as small as nobody will notice
 * (tests/e2e/exports.sh compiles them with the core tier only, and runs
 * them on a missing file):
 *
 *     jnd_texres_params p;  jnd_texres_defaults(&p);  // 16 views, standard-fhd display, 000 §9's criterion
 *     jnd_texres_result *r = NULL;                     // allocated by the run: yours to free
 *     if (jnd_texres_run("model.glb", &p, "smaller", &r) != JND_OK) {  // smaller/: model, maps, texres.json
 *       fprintf(stderr, "jnd: %s\n", jnd_last_error());  // one line; nothing was written
 *       return 2;
 *     }
 *     for (int i = 0; i < r->nmaps; i++)
 *       printf("%s: %dx%d -> %dx%d\n", r->maps[i].name, r->maps[i].orig[0], r->maps[i].orig[1],
 *              r->maps[i].chosen[0], r->maps[i].chosen[1]);
 *     printf("%s, %zu -> %zu bytes\n", r->passes ? "unnoticed" : "visible", r->block_before_bytes, r->block_after_bytes);
 *     jnd_texres_result_free(r);
 *
 * Ten lines to compare two images (tests/e2e/exports.sh compiles and runs them):
 *
 *     jnd_image ref = {0}, test = {0};  jnd_image_info ri, ti;
 *     jnd_model_params p;  jnd_model_defaults(&p);          // standard-fhd display
 *     jnd_model *m = NULL;  jnd_diff_stats st;
 *     if (jnd_image_read("ref.png", &ref, &ri) != JND_OK || jnd_image_read("test.png", &test, &ti) != JND_OK ||
 *         jnd_model_create(&p, &m) != JND_OK ||
 *         jnd_diff_files(m, &ref, &ri, &test, &ti, NULL, NULL, NULL, &st) != JND_OK) { // frees ref, test
 *       fprintf(stderr, "jnd: %s\n", jnd_last_error());
 *       jnd_image_free(&ref);  jnd_image_free(&test);  jnd_model_free(m);
 *       return 2;
 *     }
 *     printf("P(detect) = %.3f, max JND = %.2f\n", st.p_detect, st.jnd_max);
 *     jnd_model_free(m);
 *
 * Conventions: functions return jnd_status (JND_OK = 0); results go through
 * out-parameters; jnd_last_error() is a one-line message "FILE: what is wrong"
 * for the calling thread. Ownership: the caller owns what it passes in and
 * what an out-parameter gives it — a run's result (jnd_<task>_result_free),
 * every image an out-parameter fills (jnd_image_free) — except where a
 * function says it consumes (frees) its inputs, as jnd_diff_files does with
 * ref and test; freeing a zeroed or consumed image is safe, as is every
 * _free(NULL). Images inside the
 * library are linear: after a display model, values are cd/m².
 * Limits: images of at most JND_MAX_SIDE pixels a side and JND_MAX_PIXELS
 * pixels; larger inputs are refused with JND_ERR_LIMIT.
 *
 * The header reads by layer: errors; images and files; the display and the
 * vision model; pooling and psychometrics; the scene; the renderer and
 * views; the judge (render, show, compare, pool, apply the criterion);
 * tasks. Comments cite the papers the project implements by number and
 * section ("000 §9" is section 9 of paper 000):
 *   000  Wolski et al., "Selecting texture resolution using a task-specific
 *        visibility metric", Pacific Graphics 2019 (pooling, criterion, texres)
 *   001  Wronski, "Dimensionality reduction for image and texture set
 *        compression" (texture-set PCA)
 *   002  Surace et al., "Gaze-contingent perceptual level of detail
 *        prediction", EGSR 2023
 *   003  Wu, Agu & Lindsay, "Pareto-based perceptual metric for imperceptible
 *        simplification on mobile displays", Eurographics 2007
 *   004  Schwarz & Stamminger, "On predicting visual popping in dynamic
 *        scenes", APGV 2009 (the vision model)
 */
#ifndef JND_H
#define JND_H

#include <stddef.h>
#include <stdint.h>

/* Two tiers (docs/architecture.md "The header's tiers"). A declaration
 * without a mark is the stable core: errors; images and the display; the
 * vision model; pooling and the criterion; scene, views and the renderer;
 * the judge; the output writer; one jnd_<task>_run per task with its
 * defaults and _result_free; the gaze table's lookup; a batch's run.
 * A declaration marked JND_EXPERIMENTAL is a task's internals, a figure,
 * a parser, a utility or a test hook: exported and documented, but it may
 * change between versions (meshoptimizer marks MESHOPTIMIZER_EXPERIMENTAL the
 * same way). A program that wants to know where it leaves the core defines
 * the mark before including this header, e.g.
 *     #define JND_EXPERIMENTAL __attribute__((deprecated("jnd: experimental")))
 * and gets a warning at each use (tests/e2e/exports.sh compiles the first
 * example that way, with -Werror). */
#ifndef JND_EXPERIMENTAL
#define JND_EXPERIMENTAL
#endif

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

/* Seconds on a monotonic clock (CLOCK_MONOTONIC; only differences mean
 * anything), and the CPU seconds of every thread of the process so far:
 * what the timings in every report are measured with. Never part of a
 * decision. */
JND_EXPERIMENTAL double jnd_seconds(void);
JND_EXPERIMENTAL double jnd_cpu_seconds(void);

/* For a program whose threads are all jnd's OpenMP threads (the jnd tool's
 * diff): holds each of them to a CPU of its own when it runs one thread per
 * CPU it may use (threads: 0 for OpenMP's default, as in the parameters).
 * Returns how many it holds; 0 when it leaves them free: fewer or more
 * threads than CPUs (two processes would pile onto the same CPUs), a
 * binding asked for by OMP_PROC_BIND, OMP_PLACES, GOMP_CPU_AFFINITY or
 * KMP_AFFINITY, one CPU, or no affinity interface. A thread started later
 * by a held thread inherits its one CPU, so a program that starts threads
 * of its own (a CPU rasteriser's) should not ask. Never changes a result. */
JND_EXPERIMENTAL int jnd_threads_pin(int threads);

/* ------------------------------------------------------------------------ */
/* Images and image files                                                   */
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
JND_EXPERIMENTAL jnd_status jnd_csv_read(const char *path, jnd_csv *out);
JND_EXPERIMENTAL jnd_status jnd_csv_parse(const char *name, const char *text, size_t n, jnd_csv *out);
JND_EXPERIMENTAL void jnd_csv_free(jnd_csv *csv);
/* Index of a column by name, or -1. */
JND_EXPERIMENTAL int jnd_csv_column(const jnd_csv *csv, const char *name);
/* Parses a cell as a number; NaN for "NaN"/"NA"/"". Returns 0 if not a number. */
JND_EXPERIMENTAL int jnd_csv_number(const char *cell, double *out);

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
JND_EXPERIMENTAL void jnd_heatmap_defaults(jnd_heatmap_params *p);

/* Draws the heatmap figure. ref holds the reference's file signal (0..1,
 * 1–4 channels, as jnd_image_read gives); jnd_map has its size. out is
 * allocated: 3 channels, sRGB-encoded 0..1, for jnd_image_write_png. */
JND_EXPERIMENTAL jnd_status jnd_heatmap_draw(const jnd_heatmap_params *p, const jnd_image *ref, const jnd_image *jnd_map,
                            jnd_image *out);

/* jnd_heatmap_draw with the defaults and the given top of the scale
 * (max_jnd <= 0: auto). */
JND_EXPERIMENTAL jnd_status jnd_heatmap(const jnd_image *ref, const jnd_image *jnd_map, double max_jnd, jnd_image *out);

/* Writes n bytes to path through a temporary file in the same folder and a
 * rename, so path is either the old file or the complete new one. */
JND_EXPERIMENTAL jnd_status jnd_write_file_atomic(const char *path, const void *data, size_t n);

/* Creates folder path and any missing parents (like mkdir -p); an existing
 * folder is fine. JND_ERR_IO "PATH: cannot create the folder (reason)". */
JND_EXPERIMENTAL jnd_status jnd_make_dirs(const char *path);

/* ---- The output writer: never over an input, all or nothing ----
 *
 * Every file a run writes goes out through one jnd_output (docs/outputs.md):
 *
 *     jnd_output *w;  jnd_output_open(&w);
 *     jnd_output_add_input(w, "model.gltf");             // and what it references
 *     const char *dir;                                   // where the run writes
 *     if (jnd_output_add_dir(w, "out", &dir) != JND_OK) { ...refused: nothing written }
 *     ... the run writes into dir ...
 *     if (ok) s = jnd_output_commit(w);                  // publishes everything
 *     jnd_output_free(w);                                // without a commit: removes it all
 *
 * Paths are resolved as the system will: relative to the working folder,
 * through symlinks, `.` and `..`; an existing file's identity is its device
 * and inode. Register every input before the outputs (an input registered
 * later is still checked against the outputs so far). */
typedef struct jnd_output jnd_output;

/* A writer for one run. *out is owned by the caller (jnd_output_free). */
jnd_status jnd_output_open(jnd_output **out);

/* Registers a file the run reads. "-", NULL, a name that is not an existing
 * regular file (builtin:..., a file the reader will report missing) are
 * ignored. JND_ERR_ARG when an output registered before it is this file or
 * a folder that holds it. */
jnd_status jnd_output_add_input(jnd_output *w, const char *path);

/* Registers an output file and makes its staging area: *staged (owned by w,
 * valid until jnd_output_free) is where the run writes it — PATH.jnd-partial-
 * PID beside it, or inside the staging of a registered output folder that
 * holds it. Folders missing on the way are created (and removed again on
 * abort). "-" (standard output) is allowed: *staged = "-". Refused with one
 * line naming both paths (JND_ERR_ARG) when the path is an input (directly,
 * through a symlink or a hard link), another output of the run, lies inside
 * an output file, or holds an output registered earlier; JND_ERR_IO when its
 * folder is not writable. Nothing is left behind on refusal. A file the run
 * leaves unwritten is not published. */
jnd_status jnd_output_add_file(jnd_output *w, const char *path, const char **staged);

/* Registers an output folder: the run writes into *staged, a sibling folder
 * PATH.jnd-partial-PID (or a folder inside the staging of an enclosing
 * output folder). Refused like jnd_output_add_file, and also when the folder
 * holds any input (`-o .` beside the input: publishing could replace it) or
 * is an existing file. Register a folder before the outputs inside it. */
jnd_status jnd_output_add_dir(jnd_output *w, const char *path, const char **staged);

/* Only the refusals of jnd_output_add_dir against the inputs registered so
 * far, for a folder that is not staged (jnd batch's folder, shared by
 * shards and resumed: each asset's outputs there are published whole by
 * the batch). Makes nothing. */
jnd_status jnd_output_check_dir(jnd_output *w, const char *path);

/* Publishes every output, by rename. A new folder is renamed into place
 * whole. An existing folder is never removed: the staged files are moved
 * into it one by one; when it carries the marker an earlier jnd run left
 * (".jnd-output", the list of the files that run wrote), the files that list
 * names and this run did not write are removed; the user's other files stay.
 * Each published folder gets the marker. JND_ERR_IO when a rename fails
 * (then free the writer: what is left staged is removed). */
jnd_status jnd_output_commit(jnd_output *w);

/* Removes every staged file and folder and the folders the writer created;
 * an earlier run's outputs are untouched. Nothing after a commit. */
void jnd_output_abort(jnd_output *w);

/* Aborts unless committed, and frees w (NULL is fine). */
void jnd_output_free(jnd_output *w);

/* ---- The task shape ----
 *
 * Every task is one call of one shape (docs/architecture.md):
 *
 *     jnd_status jnd_<task>_run(const char *input, const jnd_<task>_params *p,
 *                               const char *out_dir, jnd_<task>_result **out);
 *
 * It reads input and what input references, writes its assets, pictures and
 * its report out_dir/<task>.json through one output writer (never over an
 * input, all or nothing), and returns the result with the report's text
 * (the JSON the command line prints with --json). Each params struct has a
 * jnd_run_options `run` for what every task shares. */
typedef struct {
  int map_size;              /* side of the built-in asset's maps, pixels (2048) */
  const char *report_path;   /* also write the report here (NULL: none); "-" is left to the caller,
                                who prints the result's report */
  int timings;               /* wall-clock seconds in the report (it then differs run to run; 0) */
  /* NULL or called with each warning about the input (one line, no "jnd:") */
  void (*warning)(void *user, const char *message);
  void *warning_user;
} jnd_run_options;

/* Fills o with the defaults above. */
void jnd_run_options_defaults(jnd_run_options *o);

/* ------------------------------------------------------------------------ */
/* Display model (004 §3.1, first stage)                                    */
/* ------------------------------------------------------------------------ */

/* The viewing task: how the viewer compares TEST with REF, and so what P
 * predicts (docs/model.md "Viewing task"). The contrast bands see the same
 * patterns in either task; the tasks differ in how a change of the mean
 * luminance and colour over large areas (the baseband) is seen. */
typedef enum {
  JND_TASK_SIDE_BY_SIDE = 0, /* the default: the two images at different places (side by side, or
                                one after the other with a gap), looked at in turn for as long as
                                the viewer likes. A large uniform change is seen only by comparing
                                colours across space: at most its CIEDE2000 ΔE00 over
                                side_by_side_de00 JND (colorimetry's large-field threshold) */
  JND_TASK_FLICKER = 1       /* the two at the same place, toggled back and forth (FLIP's
                                "flipping", an LOD switch in place, a psychophysical interval):
                                a change of the mean is a transient at the same retinal place,
                                seen through the CSF like any pattern */
} jnd_viewing_task;

/* "side-by-side" or "flicker". */
const char *jnd_viewing_task_name(jnd_viewing_task t);
/* The task named s ("side-by-side" or "flicker"); JND_ERR_ARG naming both otherwise. */
jnd_status jnd_viewing_task_parse(const char *s, jnd_viewing_task *t);

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
  jnd_viewing_task task; /* how the viewer compares the two images (side by side by default);
                            a comparison given as a temporal modulation (jnd_diff_inputs.temporal_hz)
                            is a flicker whatever this says */
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

/* Checks every quantity of d, as a display is accepted (jnd_model_create;
 * jnd_display_apply checks the luminances it uses): ppd in [1, 1000]; peak
 * in [0.01, 100000] cd/m²; 0 <= black < peak; ambient in [0, 200000] lux;
 * reflectivity in [0, 1]; exr_scale in [1e-9, 1e9] cd/m² per unit; the
 * geometry finite and not negative, a diagonal with a distance and a
 * resolution; a known task; a terminated name. NaN and infinities fail
 * every range. JND_ERR_ARG with one line, "display NAME: what is wrong". */
jnd_status jnd_display_check(const jnd_display *d);

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
/* The vision model (004 §3.1–3.2)                                          */
/* ------------------------------------------------------------------------ */

typedef struct {
  jnd_display display;
  double sensitivity;        /* multiplier on the achromatic CSF (fitted, docs/model.md) */
  double sens_rg;            /* multiplier on the red–green CSF (fitted) */
  double sens_yv;            /* multiplier on the yellow–violet CSF (fitted) */
  double minkowski;          /* exponent across bands and channels (2.4, 004 §3.2) */
  double masking_slope;      /* growth of the discrimination threshold with a masker's contrast,
                                log-log (0.6, Legge 1981; 004's printed transducer: 0.3);
                                docs/model.md "Masking" */
  double masking_cross;      /* weight of the other two channels' maskers in each channel's masker,
                                0..1 (1: one normalisation pool over A, a, b, as ColorVideoVDP's
                                cross-channel masking; 0: each channel masks only itself, as 004);
                                docs/model.md "Masking" */
  double masking_band_oct;   /* frequency tuning of the masking pool: each band's masker adds the
                                next coarser band's with weight 2^-(d/h)^2, d the octaves between
                                their peaks and h this half-width at half height (1: contrast
                                masking's tuning, Legge & Foley 1980; 0: each band masks only
                                itself, as 004); docs/model.md "Masking" */
  double min_band_cpd;       /* bands are added while their peak is >= this (004: 0.5 cpd;
                                see docs/model.md for the default) */
  double summation_area_deg2; /* local probability summation over Rovamo et al.'s (1993) critical
                                area A0 / (1 + (rho/f0)^2) deg² around each pixel: this is A0
                                (0: none, as 004); docs/model.md */
  double summation_f0_cpd;   /* f0 of that area, cycles/degree */
  double summation_beta;     /* exponent of that summation */
  double summation_chroma_f0_cpd; /* f0 of the red–green and yellow–violet channels' own critical
                                area A0 / (1 + (rho/f0)^2) (0: the achromatic f0 and one window
                                for the three channels); docs/model.md "Area summation" */
  double summation_chroma_beta; /* exponent of the chromatic channels' summation (0: summation_beta) */
  double eye_velocity_dps;   /* fixational eye movements: sensitivity to static content is the best
                                over retinal velocities [v, v + this] (0: v only, as 004) */
  double chroma_sat_td;      /* retinal illuminance (trolands) where the chromatic square-root
                                law turns into Weber's law (0: pure square root, as 004) */
  double rg_cutoff_cpd;      /* red–green CSF centre cut-off (Kelly 1983 form, docs/model.md) */
  double yv_cutoff_cpd;      /* yellow–violet CSF centre cut-off */
  double chroma_tail;        /* exponent q of the chromatic centre's spatial fall, exp(-(rho/cutoff)^q) */
  double chroma_temporal_hz; /* temporal cut-off of the chromatic CSFs' centre, Hz */
  double kelly_c2;           /* velocity scale c2 of the achromatic CSF (004: 1.7; docs/model.md) */
  double flicker_gain;       /* sensitivity to a flicker's amplitude relative to a travelling
                                wave's (jnd_diff_inputs.temporal_hz; docs/model.md "Time") */
  double ecc_e2_deg;         /* eccentricity where cortical magnification has halved, degrees */
  double ecc_achromatic;     /* sensitivity falls as (1 + ecc/e2)^-this, achromatic channel */
  double ecc_rg, ecc_yv;     /* the same for the red–green and yellow–violet channels */
  double ecc_freq;           /* and as exp(-this · rho · ecc), per cpd·degree (Geisler & Perry) */
  double side_by_side_de00;  /* the side-by-side task (display.task): the CIEDE2000 difference of two
                                large uniform fields side by side that is one JND (1.0: CIE 142-2001,
                                docs/model.md "Viewing task") */
  double beta;               /* psychometric slope (3.5, 000 eq. 4) */
  double fps;                /* frames per second, to turn motion maps into deg/s */
  int has_gaze;              /* 1: gaze_x/gaze_y give the fixation point */
  double gaze_x, gaze_y;     /* pixels; may lie outside the image */
  int threads;               /* 0: OpenMP's default */
} jnd_model_params;

/* Fills p with the defaults: standard-fhd display and the fitted constants. */
void jnd_model_defaults(jnd_model_params *p);

/* One of the model's constants that human threshold data may set
 * (`jnd csf --fit`, docs/model.md). Fits are maximum a posteriori: each
 * constant has a log-normal prior centred on a published or physiological
 * value, so that a constant no fitted data constrain returns to it. */
typedef struct {
  const char *name;          /* the jnd_model_params field */
  const char *what;          /* one line, with units */
  double prior;              /* centre of the prior */
  double prior_sd;           /* its width, natural-log units */
  double lo, hi;             /* bounds */
  const char *source;        /* where the prior comes from */
  int held;                  /* 1: a fit keeps it at its prior unless asked to fit it
                                (jnd_csf_options.fit_mask), because one data set alone
                                would set it for all the others (docs/model.md) */
} jnd_model_constant;

/* The fittable constants: fills list[0..max) (list may be NULL) and returns
 * how many there are. The entries are static. */
JND_EXPERIMENTAL int jnd_model_constants(const jnd_model_constant **list, int max);
/* The index of a constant by name, or -1. */
JND_EXPERIMENTAL int jnd_model_constant_find(const char *name);
/* Constant k of p (NaN for a bad k). */
JND_EXPERIMENTAL double jnd_model_constant_get(const jnd_model_params *p, int k);
/* Sets constant k of p; JND_ERR_ARG outside its bounds. */
JND_EXPERIMENTAL jnd_status jnd_model_constant_set(jnd_model_params *p, int k, double value);

/* A model instance: caches the per-display tables (band peak frequencies,
 * CSF look-up tables). Reusable for any number of comparisons; not for
 * concurrent use from several threads. */
typedef struct jnd_model jnd_model;

jnd_status jnd_model_create(const jnd_model_params *p, jnd_model **out);
void jnd_model_free(jnd_model *m);

/* The parameters the model was created with. */
const jnd_model_params *jnd_model_get_params(const jnd_model *m);

/* Moves the fixation point of m (pixels of the images it will compare; it
 * may lie outside them) or, with has_gaze 0, removes it so that every pixel
 * is foveal. Each pixel's eccentricity is the angle between it and the
 * fixation point on a flat screen seen from the distance params.display.ppd
 * implies. The CSF tables do not depend on the fixation point, so one model
 * serves any number of gaze positions (gaze tables, a per-view gaze). */
void jnd_model_set_gaze(jnd_model *m, int has_gaze, double gaze_x, double gaze_y);

/* The model's sensitivity at eccentricity ecc_deg relative to the fovea, for
 * a pattern of spatial frequency rho_cpd in channel ch (0 achromatic,
 * 1 red–green, 2 yellow–violet), from p's constants:
 *   (1 + ecc/ecc_e2_deg)^−γ_ch · exp(−ecc_freq · rho · ecc),
 * γ_ch = ecc_achromatic, ecc_rg or ecc_yv (Rovamo & Virsu's cortical
 * magnification, Geisler & Perry's acuity loss; docs/model.md
 * "Eccentricity"). 1 at the fovea; what jnd_model_diff applies per band and
 * pixel when a fixation point is set. */
JND_EXPERIMENTAL double jnd_eccentricity_factor(const jnd_model_params *p, int ch, double rho_cpd, double ecc_deg);

/* Optional per-pixel inputs of a comparison; any field may be NULL / 0. */
typedef struct {
  const jnd_image *motion;   /* 2 channels: screen displacement in pixels per frame
                                (needs params.fps); goes through the eye-movement model */
  const jnd_image *weights;  /* 1 channel: multiplies the difference map (004 §3.2) */
  double retinal_dps;        /* > 0: every pixel moves on the retina at this speed (deg/s),
                                bypassing the eye-movement model (psychophysics with fixation) */
  const jnd_image *motion_test; /* the test image's own displacement, when it differs from the
                                reference's (004 §3: each frame has its own map; NULL: `motion`
                                serves both; `motion` NULL here means a static reference) */
  double temporal_hz;        /* > 0: the change is seen as a temporal modulation at this frequency
                                (Hz) under fixation — a flicker, a counterphase grating, or the
                                transient of an LOD switch — rather than as a static difference:
                                each band's CSF is taken at this temporal frequency (Kelly's
                                spatio-temporal surface, docs/model.md "Time"). Overrides motion,
                                motion_test and retinal_dps. */
} jnd_diff_inputs;

/* JND map of two images of absolute linear RGB in cd/m² (as jnd_display_apply
 * gives), same size, 3 channels. jnd_out is allocated: 1 channel, in units of
 * just-noticeable differences (1 = one JND). ref and test are not modified. */
jnd_status jnd_model_diff(jnd_model *m, const jnd_image *ref, const jnd_image *test,
                          const jnd_diff_inputs *in, jnd_image *jnd_out);

/* The same, using ref and test as scratch space: their pixels are destroyed
 * and they are freed. The low-memory path for large images. */
JND_EXPERIMENTAL jnd_status jnd_model_diff_consume(jnd_model *m, jnd_image *ref, jnd_image *test,
                                  const jnd_diff_inputs *in, jnd_image *jnd_out);

/* The same for images in CIE XYZ (cd/m²), for stimuli defined colorimetrically. */
JND_EXPERIMENTAL jnd_status jnd_model_diff_xyz(jnd_model *m, const jnd_image *ref_xyz, const jnd_image *test_xyz,
                              const jnd_diff_inputs *in, jnd_image *jnd_out);

/* Probability of detection from JND (000 eq. 4): 1 − exp(ln 0.5 · jnd^beta). */
double jnd_probability(double jnd, double beta);

/* The JND a probability corresponds to (the inverse of jnd_probability). */
JND_EXPERIMENTAL double jnd_probability_inverse(double p, double beta);

/* The peak frequency of each contrast pyramid band of the model, cycles per
 * degree (finest first); returns the number of bands (at most max). */
JND_EXPERIMENTAL int jnd_model_band_peaks(const jnd_model *m, double *cpd, int max);

/* CIELAB and CIE ΔE*94 (Fairchild 2004): a colorimetric yardstick beside the
 * model, 004 §5.1's "maximum ΔE*94" baseline. L*a*b* is relative to the
 * display's white (full-scale RGB: peak + reflected ambient, D65). */

/* Converts an image of absolute linear RGB in cd/m² (3 channels, as
 * jnd_display_apply gives) in place to CIE 1976 L*, a*, b* planes. */
JND_EXPERIMENTAL jnd_status jnd_lab_from_linear(const jnd_display *d, jnd_image *img);

/* ΔE*94 of two L*a*b* colours with the graphic-arts weights (kL = kC = kH =
 * 1, K1 = 0.045, K2 = 0.015); ref's chroma sets S_C and S_H, so the
 * difference is not symmetric. */
JND_EXPERIMENTAL double jnd_delta_e94(const float ref[3], const float test[3]);

/* CIEDE2000 ΔE00 of two L*a*b* colours (CIE 142-2001, kL = kC = kH = 1, as
 * Sharma, Wu & Dalal 2005 give it): symmetric; 1 is about the
 * just-noticeable difference of large uniform fields side by side. */
JND_EXPERIMENTAL double jnd_delta_e00(const double lab1[3], const double lab2[3]);

/* One colour of absolute CIE XYZ (cd/m²) as L*a*b* relative to the
 * display's white (as jnd_lab_from_linear). */
void jnd_lab_of_xyz(const jnd_display *d, const double xyz[3], double lab[3]);

/* Per-pixel ΔE*94 of two images of absolute linear RGB in cd/m² (same size,
 * 3 channels); out is allocated (1 channel). max (may be NULL) receives the
 * largest value. ref and test are not modified. */
JND_EXPERIMENTAL jnd_status jnd_delta_e94_map(const jnd_display *d, const jnd_image *ref, const jnd_image *test, jnd_image *out,
                             double *max);

/* ------------------------------------------------------------------------ */
/* Pooling and psychometrics (000 §6–§7, §9)                                */
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

/* Which side of its chord a curve bends to: a cumulative curve that rises
 * fast then flattens lies ABOVE its chord (pca's energy, 001); an error
 * curve that stays flat then rises sharply lies BELOW it (lod's Pareto
 * curve, 003 §3). */
typedef enum { JND_KNEE_ABOVE = 0, JND_KNEE_BELOW } jnd_knee_side;

/* The knee of the curve (x[i], y[i]), i = 0..n−1, x monotone: with both axes
 * scaled to 0..1 between the first and the last point, the point farthest
 * from the chord joining them on the given side ("maximum distance to the
 * chord"). Points whose distance is within the fraction tie (0..1; 0: exact
 * ties only) of the largest count as equally far, and the first of them
 * wins. Returns its index; 0 when no point lies strictly on that side of the
 * chord (a straight line, or a curve bent the other way) or n < 3; −1 for
 * n < 1 or a value that is not finite. See src/pool/knee.c. */
JND_EXPERIMENTAL int jnd_knee(const double *x, const double *y, int n, jnd_knee_side side, double tie);

/* The one-sided Clopper–Pearson upper bound on a binomial proportion: the
 * largest u with P(X <= k | n, u) >= 1 − confidence (1 when k = n). */
JND_EXPERIMENTAL double jnd_binomial_upper(int k, int n, double confidence);

/* The cross-population psychometric function of 000 eq. 1 over texture
 * resolution r (pixels): P_det(r) = 1 − Θ(x; µ, σ), Θ the cumulative normal,
 * x = r (domain 0, pixels, as 000) or x = log2 r (domain 1, octaves). */
typedef struct {
  double mu, sigma;          /* in the domain's units (pixels or log2 pixels) */
  int log2_domain;           /* 0: x = r; 1: x = log2 r */
  double rmse;               /* root mean squared error of the fit in probability */
} jnd_psychometric;

/* P_det at resolution r (pixels) for f. */
JND_EXPERIMENTAL double jnd_psychometric_eval(const jnd_psychometric *f, double r);

/* The resolution (pixels) where P_det = p (0 < p < 1). */
JND_EXPERIMENTAL double jnd_psychometric_resolution(const jnd_psychometric *f, double p);

/* Fits µ and σ (σ > 0) of 000 eq. 1 to n >= 2 points (r[i] pixels > 0,
 * p[i] in 0..1) by least squares on probability: a small grid over (µ, log σ)
 * refined by Nelder–Mead from a probit-analysis start. Detection must fall as r grows; data that never
 * change (all 0 or all 1) give the nearest step function (σ small, µ just
 * outside the data's range). log2_domain picks the domain (see above).
 * JND_ERR_ARG for n < 2 or values out of range. */
JND_EXPERIMENTAL jnd_status jnd_psychometric_fit(const double *r, const double *p, int n, int log2_domain,
                                jnd_psychometric *out);

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
  const char *path;          /* the file it was read from (the caller's string; NULL: defaults),
                                set by jnd_calibration_load; a task's run protects and reports it */
} jnd_calibration;

/* Fills c with the identity calibration above. */
void jnd_calibration_defaults(jnd_calibration *c);

/* Reads a calibration file written by jnd_calibration_save / `jnd
 * calibrate` (JSON with "calibration": {"percentile", "scale", "bias",
 * "beta", ...}). JND_ERR_IO / JND_ERR_FORMAT "PATH: problem". */
jnd_status jnd_calibration_load(const char *path, jnd_calibration *c);

/* Writes c as JSON to path (atomic). */
JND_EXPERIMENTAL jnd_status jnd_calibration_save(const char *path, const jnd_calibration *c);

/* The calibrated pooled probability of a JND map: JND → max(0, scale·JND +
 * bias) → P (eq. 4, c->beta) → c->percentile over the pixels where mask >
 * 0.5 (mask NULL: every pixel). NaN when no pixel counts. */
JND_EXPERIMENTAL double jnd_calibration_pool(const jnd_calibration *c, const jnd_image *jnd_map, const jnd_image *mask);

/* Summarises a JND map as jnd_diff_summarise does, but through the
 * calibration: the JND statistics are of the transformed map, the P map uses
 * c->beta and p_detect is its c->percentile. */
JND_EXPERIMENTAL jnd_status jnd_diff_summarise_calibrated(const jnd_image *jnd_map, const jnd_calibration *c,
                                         jnd_diff_stats *stats);

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
JND_EXPERIMENTAL const char *jnd_map_slot_name(jnd_map_slot slot);
JND_EXPERIMENTAL jnd_map_kind jnd_map_slot_kind(jnd_map_slot slot);

/* Loads a glTF 2.0 (.gltf with external or embedded buffers, .glb) or OBJ +
 * MTL file with assimp: triangulated, node transforms applied, tangents
 * computed where the file has none (docs/render.md). Levels of detail a glTF
 * file has as MSFT_lod nodes become the scene's levels 1.. (docs/lod.md;
 * jnd_scene_lod_count), level 0 selected. A texture file that is
 * missing or unreadable is not an error: the slot falls back to its factor
 * and a warning is recorded (jnd_scene_warning). A malformed model, or one
 * without triangles, is JND_ERR_FORMAT "PATH: problem"; a missing model
 * JND_ERR_IO. *out is owned by the caller (jnd_scene_free). */
jnd_status jnd_scene_load(const char *path, jnd_scene **out);

/* The files the asset at path is made of, for the output writer
 * (jnd_output_add_input): path itself, then what it references — a glTF's
 * buffers and images given by URI (resolved beside the model; data: URIs
 * and GLB chunks are inside it), an OBJ's mtllib files and the texture maps
 * they name. Files are listed whether or not they exist; a file that does
 * not parse lists only itself (the importer reports it). *files and its
 * strings are the caller's (jnd_asset_files_free). JND_ERR_NOMEM only. */
jnd_status jnd_asset_files(const char *path, char ***files, int *count);
void jnd_asset_files_free(char **files, int count);
/* The unit of an asset's lengths, for labels: "m" for glTF and GLB (metres
 * by the glTF specification), "object units" for OBJ and the built-in
 * assets, which carry none. */
JND_EXPERIMENTAL const char *jnd_asset_length_unit(const char *path);

/* Parameters of the built-in procedural asset. */
typedef struct {
  int map_size;          /* side of the square texture maps, pixels (default 2048) */
  int shape;             /* 0: rounded box (default), 1: sphere */
  uint64_t seed;         /* seed of the procedural detail (default 1) */
  int parts;             /* objects, each with its own material and maps (1..8; default 1) */
  int ground;            /* 1: they stand on a plain ground plane (material "ground", no maps) */
} jnd_builtin_params;

/* Fills p with the defaults above. */
JND_EXPERIMENTAL void jnd_builtin_defaults(jnd_builtin_params *p);

/* Makes the built-in asset needing no files: a rounded box of side 2 (or a
 * sphere of radius 1) in object units, centred at the origin, with one
 * material "builtin" carrying baseColor (fine albedo detail), normal (from
 * a height field), metallicRoughness (roughness variation) and occlusion
 * maps of map_size² pixels. With parts = N > 1: N boxes and spheres in
 * turn on a grid 2.6 units apart, materials "part0".."partN-1", each with
 * its own four maps (finer or coarser detail, other tints). With ground: a
 * horizontal square under them. p may be NULL (defaults). */
jnd_status jnd_scene_builtin(const jnd_builtin_params *p, jnd_scene **out);

/* Parses a built-in asset's name into p (other fields kept): "builtin", or
 * "builtin:" and a comma list of box, sphere, parts=N, ground (e.g.
 * "builtin:sphere,ground", "builtin:parts=6"). Returns 1 for such a name,
 * 0 for any other name (a file), −1 for a malformed option. */
JND_EXPERIMENTAL int jnd_builtin_parse(const char *name, jnd_builtin_params *p);

/* Opens a model by name, the one way every command does: a built-in asset
 * (jnd_builtin_parse; maps of map_size² pixels, 0 for the default) or a
 * file (jnd_scene_load). *out is the caller's (jnd_scene_free). */
jnd_status jnd_scene_open(const char *name, int map_size, jnd_scene **out);

/* Frees a scene and all its maps; safe on NULL. A renderer that drew it
 * forgets it on its next rendering of another scene. */
void jnd_scene_free(jnd_scene *s);

/* The path the scene came from ("builtin" for the procedural asset). */
JND_EXPERIMENTAL const char *jnd_scene_path(const jnd_scene *s);

/* Counts: meshes (after triangulation), triangles, materials. */
JND_EXPERIMENTAL int jnd_scene_mesh_count(const jnd_scene *s);
size_t jnd_scene_triangle_count(const jnd_scene *s);
JND_EXPERIMENTAL int jnd_scene_material_count(const jnd_scene *s);
JND_EXPERIMENTAL const char *jnd_scene_material_name(const jnd_scene *s, int material);

/* The bounding sphere of the scene (object units): centre[3] and radius. */
JND_EXPERIMENTAL void jnd_scene_bounds(const jnd_scene *s, double centre[3], double *radius);

/* The bounding sphere of what stands on the ground: without a ground plane
 * in the scene (a mesh that is flat, horizontal, lowest and wider than
 * everything else), the same as jnd_scene_bounds. ground (may be NULL)
 * receives the ground's material index, or −1 when there is none. Views are
 * framed on this sphere (docs/render.md). */
JND_EXPERIMENTAL void jnd_scene_subject_bounds(const jnd_scene *s, double centre[3], double *radius, int *ground);

/* Warnings recorded while loading (missing textures, ...): count, and the
 * i-th one-line message (owned by the scene). */
JND_EXPERIMENTAL int jnd_scene_warning_count(const jnd_scene *s);
JND_EXPERIMENTAL const char *jnd_scene_warning(const jnd_scene *s, int i);

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
  int image;             /* the image of the file the map samples, as the index of the first map
                            that samples it (i itself when no earlier map does): maps sharing an
                            image (a packed occlusion-roughness-metal image, a texture two
                            materials use) have the same index, and a GPU holds it once */
} jnd_map_info;

/* Number of texture maps (material slots that have a texture), and the
 * description of map i (0 ≤ i < count), in material order then slot order. */
JND_EXPERIMENTAL int jnd_scene_map_count(const jnd_scene *s);
JND_EXPERIMENTAL jnd_status jnd_scene_map_info(const jnd_scene *s, int i, jnd_map_info *info);

/* The index of the map called name ("MATERIAL/SLOT"), or -1. Material names
 * that repeat get "#N" appended in file order (docs/render.md). */
JND_EXPERIMENTAL int jnd_scene_map_find(const jnd_scene *s, const char *name);

/* Replaces map i for subsequent renderings by the original resampled to
 * w × h pixels (any size ≥ 1, not only powers of two) with
 * jnd_resample_map. w, h equal to the original restore it exactly. */
JND_EXPERIMENTAL jnd_status jnd_scene_map_resize(jnd_scene *s, int i, int w, int h);

/* Replaces map i by a copy of img (the caller keeps img), in the slot's
 * encoding: values 0..1, sRGB-encoded for colour slots, (v + 1) / 2 for
 * normals; 1–4 channels, any size. */
JND_EXPERIMENTAL jnd_status jnd_scene_map_set(jnd_scene *s, int i, const jnd_image *img);

/* Restores map i to the file's version. */
JND_EXPERIMENTAL void jnd_scene_map_restore(jnd_scene *s, int i);

/* A copy of map i as used now (caller frees it); orig = 1 for the file's version. */
JND_EXPERIMENTAL jnd_status jnd_scene_map_get(const jnd_scene *s, int i, int orig, jnd_image *out);

/* Resamples a texture map to w × h pixels with a separable Lanczos-3 filter
 * (000 §4), widened by the scale factor when shrinking so that it
 * antialiases. Colour maps (values sRGB-encoded 0..1) are filtered in linear
 * light and re-encoded, with alpha filtered as is; normal maps are decoded
 * to vectors, filtered and renormalised; data maps are filtered as plain
 * values. Results are clamped to 0..1. Edges are clamped (wrap = 0) or
 * wrapped (wrap = 1, for tiling maps). out is allocated (caller frees). */
JND_EXPERIMENTAL jnd_status jnd_resample_map(const jnd_image *in, int w, int h, jnd_map_kind kind, int wrap,
                            jnd_image *out);

/* ------------------------------------------------------------------------ */
/* Levels of detail (scene)                                                 */
/* ------------------------------------------------------------------------ */
/* A scene can hold a chain of levels of detail: level 0 is the file's meshes;
 * level k > 0 is a simpler version of every mesh, made with meshoptimizer
 * (jnd_scene_lod_build) or taken from another file or a glTF MSFT_lod node
 * (jnd_scene_lod_add, jnd_scene_load). Mesh i of every level has mesh i's
 * material. One level is in use at a time (jnd_scene_lod_select): the
 * renderer draws it, and uploads a mesh again only when its level changed,
 * so a task can measure level after level with one renderer. Typical use:
 *
 *     jnd_scene *s;  jnd_scene_load("bunny.obj", &s);
 *     jnd_lod_params lp;  jnd_lod_defaults(&lp);          // error targets 1/4096 .. 1/16
 *     jnd_scene_lod_build(s, &lp);
 *     for (int k = 0; k < jnd_scene_lod_count(s); k++) {
 *       jnd_lod_level_info li;  jnd_scene_lod_info(s, k, &li);
 *       jnd_scene_lod_select(s, k);                        // the next jnd_render draws level k
 *       ...
 *     }
 *     jnd_scene_lod_select(s, 0);
 * See docs/lod.md. */

/* How a level was made. */
typedef enum {
  JND_LOD_INPUT = 0,      /* level 0: the file's meshes */
  JND_LOD_SIMPLIFIED,     /* meshopt_simplify, keeping the mesh's topology and attribute seams */
  JND_LOD_SLOPPY,         /* at least one mesh needed the fallback meshopt_simplifySloppy, which
                             ignores topology and seams (docs/lod.md says when) */
  JND_LOD_IMPORTED        /* from another file or a glTF MSFT_lod node */
} jnd_lod_method;

/* One level of a chain. */
typedef struct {
  size_t triangles;        /* of all meshes */
  size_t vertices;         /* distinct vertices its triangles use */
  double target_error;     /* the error target that made it, relative to the scene's extent
                              (0: level 0; NaN: imported, or made for a triangle ratio) */
  double target_ratio;     /* the triangle ratio that made it (NaN: made for an error target) */
  double error;            /* meshoptimizer's result error relative to the scene's extent (the
                              largest side of the bounding box of level 0, meshopt_simplifyScale's
                              unit), the largest over the meshes; a level simplified from a
                              simpler one carries the sum of both steps' errors, an upper bound
                              (docs/lod.md). 0 for level 0, NaN for imported levels */
  double error_abs;        /* the same in object units */
  jnd_lod_method method;
  int sloppy_meshes;       /* meshes of this level made with meshopt_simplifySloppy */
  char source[256];        /* where an imported level came from ("FILE" or "FILE#node N") */
} jnd_lod_level_info;

/* Parameters of a chain made with meshoptimizer (0.18: meshopt_simplify with
 * a target error and no target count; docs/lod.md). */
typedef struct {
  const double *errors;    /* error targets relative to the scene's extent (0.01 = 1% of the largest
                              side of its bounding box), ascending; NULL: the default list, 1/4096,
                              1/2048, ... 1/16 (9 levels) */
  int nerrors;
  const double *ratios;    /* used when errors is NULL and ratios is not: triangle ratios (0..1),
                              descending, each level aiming at ratio × the mesh's triangles */
  int nratios;
  int lock_border;         /* −1 (default): lock the open borders of every mesh when the scene has
                              more than one mesh (so that meshes that meet do not part); 0: never;
                              1: always (meshopt_SimplifyLockBorder) */
  int allow_sloppy;        /* 1 (default): where meshopt_simplify cannot collapse any further edge
                              before a level's target (its topology or seams stop it),
                              meshopt_simplifySloppy makes that mesh's level if it gets fewer
                              triangles within the target; 0: never */
  int slab_triangles;      /* 0 (default): 262144. A mesh with more triangles is cut into slabs of
                              about this many, simplified in parallel with their cuts locked and
                              joined before its level is made (docs/lod.md); only level 1 is then
                              made from the input */
  int threads;             /* 0: OpenMP's default; the chain is the same for every count */
} jnd_lod_params;

/* Fills p with the defaults above. */
JND_EXPERIMENTAL void jnd_lod_defaults(jnd_lod_params *p);

/* Replaces the scene's levels 1.. by a chain made from level 0 with
 * meshoptimizer, one level per target (a target that gives no fewer
 * triangles than the level before it adds no level). Attribute seams (uv
 * and vertex colour) are kept as meshopt_simplify keeps them; normals are
 * taken back per corner from the input's vertices (hard edges stay hard
 * where the surface still bends there). Each level is simplified from the
 * coarsest earlier level whose target is at most a quarter of its own (from
 * level 0 for the first ones; when a mesh has more than slab_triangles,
 * only level 1 is, in parallel slabs), its error the sum of the steps'
 * errors (an upper bound). Level 0 is selected on return. JND_ERR_FORMAT "PATH:
 * problem" for a scene whose triangles all have zero area; JND_ERR_ARG for
 * bad targets. */
JND_EXPERIMENTAL jnd_status jnd_scene_lod_build(jnd_scene *s, const jnd_lod_params *p);

/* Appends the meshes of another scene as the next level (an artist's LOD
 * file): its meshes are matched to this scene's by material name (all of a
 * material's triangles become that mesh's level; a mesh with no match is
 * empty at that level). level is consumed (freed) whatever the outcome;
 * source names it in jnd_lod_level_info. JND_ERR_ARG "SOURCE: ..." when it
 * has a material this scene lacks. */
JND_EXPERIMENTAL jnd_status jnd_scene_lod_add(jnd_scene *s, jnd_scene *level, const char *source);

/* Where the chain a task measures comes from (jnd lod, jnd pop). */
typedef struct {
  const jnd_lod_params *chain;    /* how a chain is made; NULL: jnd_lod_defaults */
  int rebuild;                    /* 1: make one even when the file has MSFT_lod levels (0) */
  const char *const *level_paths; /* levels from other files, finest first (jnd_scene_load), as
                                     levels 1.. instead of a made chain; NULL */
  int nlevel_paths;
} jnd_lod_chain_params;

/* Gives a scene just opened (jnd_scene_open) the chain a task measures, the
 * one way every command does: the level files of p (jnd_scene_lod_add), else
 * the file's own MSFT_lod levels (unless rebuild), else a chain made with
 * meshoptimizer (jnd_scene_lod_build). *source is then "levels", "file" or
 * "made" (static strings); name is the model's name for messages. p may be
 * NULL (a file's levels, or a chain with the defaults). JND_ERR_ARG for
 * level files given to a file that has levels; JND_ERR_FORMAT "NAME: ..."
 * when the chain has one level (nothing simpler could be made). */
JND_EXPERIMENTAL jnd_status jnd_scene_lod_chain(jnd_scene *s, const char *name, const jnd_lod_chain_params *p, const char **source);

/* Number of levels (1: the file's meshes only), and the description of level k. */
int jnd_scene_lod_count(const jnd_scene *s);
JND_EXPERIMENTAL jnd_status jnd_scene_lod_info(const jnd_scene *s, int level, jnd_lod_level_info *out);

/* Makes level k (0 ≤ k < count) the one in use: jnd_scene_triangle_count
 * and jnd_render see it. The renderer notices which meshes changed and
 * uploads only those again. */
JND_EXPERIMENTAL jnd_status jnd_scene_lod_select(jnd_scene *s, int level);

/* The level in use. */
JND_EXPERIMENTAL int jnd_scene_lod_selected(const jnd_scene *s);

/* Makes level k the one in use for one mesh only (a level per object: a
 * gaze-contingent or per-object LOD); jnd_scene_lod_select sets them all
 * again. jnd_scene_lod_selected keeps naming the last level selected for
 * the whole scene. JND_ERR_ARG for a mesh or level out of range. */
JND_EXPERIMENTAL jnd_status jnd_scene_lod_select_mesh(jnd_scene *s, int mesh, int level);

/* The level mesh is drawn at now (-1 for a mesh out of range). */
JND_EXPERIMENTAL int jnd_scene_lod_mesh_level(const jnd_scene *s, int mesh);

/* Writes the scene with every level of detail as one binary glTF 2.0 file
 * (atomically): node 0 holds level 0 (a primitive per scene mesh) and the
 * MSFT_lod extension listing nodes 1.., which hold the other levels; only
 * node 0 is in the glTF scene, so a reader without MSFT_lod shows level 0.
 * coverage (NULL: none) gives jnd_scene_lod_count values written as node
 * 0's extras.MSFT_screencoverage: level k is shown while the object covers
 * more than coverage[k] of the screen's height (the last value: below it
 * nothing is drawn). Meshes are in object units with the file's node
 * transforms applied; materials are written from the scene's (factors,
 * alpha, double-sidedness, uv sets, KHR_texture_transform), maps as 8-bit
 * PNGs of the maps in use. jnd_scene_load reads the levels back. */
JND_EXPERIMENTAL jnd_status jnd_scene_write_lod_glb(const jnd_scene *s, const char *path, const double *coverage);

/* The bytes level `level` takes as jnd_scene_write_lod_glb stores it and a
 * GPU holds it: per mesh, the vertices its triangles use times the float
 * attributes written for it (POSITION and NORMAL; a uv set only where one
 * of its material's maps samples it, TANGENT only with a normal map,
 * COLOR_0 where a colour is not white) plus 32-bit indices. Textures are
 * not included. */
JND_EXPERIMENTAL jnd_status jnd_scene_lod_bytes(const jnd_scene *s, int level, size_t *bytes);

/* The name a written chain takes from its model (OUT/model/STEM.glb, by jnd
 * lod and jnd gaze): the file's base name without its extension, ':', ','
 * and '=' made '_' ("builtin:box,parts=3" → "builtin_box_parts_3"). */
JND_EXPERIMENTAL void jnd_model_stem(const char *model_path, char *out, size_t n);

/* How far a level's surface lies from level 0's, in object units: points
 * sampled on level 0 uniformly by area (stratified, seeded), each taken to
 * the nearest point of the level's surface (003 eq. 1's l^p(T_i, S2)). */
typedef struct {
  int samples;
  double mean;             /* mean distance */
  double rms;              /* root mean square (p = 2) */
  double max;              /* largest sampled distance (a one-sided Hausdorff estimate) */
} jnd_surface_distance;

/* Samples `samples` points on level 0 (seed fixes them) and measures their
 * distance to level `level` (a bounding-volume hierarchy over its
 * triangles; exact point–triangle distances). Deterministic whatever the
 * thread count. JND_ERR_FORMAT when level 0 has no area. */
JND_EXPERIMENTAL jnd_status jnd_scene_lod_distance(const jnd_scene *s, int level, int samples, uint64_t seed,
                                  jnd_surface_distance *out);

/* ------------------------------------------------------------------------ */
/* Renderer and views                                                       */
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
  int pixel_shading;        /* 1: shade once per pixel (GL's MSAA: supersamples coverage only);
                               0 (default): shade every sample, so a pixel is the mean of the image
                               over its area, as a display pixel is (docs/render.md) */
  int anisotropy;           /* maximum anisotropy (default 8) */
  const char *env_path;     /* equirectangular .hdr/.exr environment; NULL: the built-in studio */
  const char *platform;     /* NULL/"auto", "device" or "surfaceless" (also $JND_EGL_PLATFORM) */
} jnd_renderer_params;

/* Fills p with the defaults above (512 × 512, 4 samples shaded each, anisotropy 8, studio). */
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
JND_EXPERIMENTAL const char *jnd_renderer_description(const jnd_renderer *r);

/* Changes the output size (pixels) for the next renderings. */
JND_EXPERIMENTAL jnd_status jnd_renderer_resize(jnd_renderer *r, int width, int height);

/* The output size (pixels) of the next renderings. */
JND_EXPERIMENTAL void jnd_renderer_size(const jnd_renderer *r, int *width, int *height);

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
  int unlit;                 /* 1: colour is the material's base colour (factor × map × vertex
                                colour) × exposure, without any light (003 §4.1) */
  unsigned outputs;          /* JND_OUT_* (default colour) */
  int shade_prev;            /* 1 (with has_prev): each pixel of this pose is shaded as its surface
                                point was in the previous pose: placed by prev_model, seen from
                                prev_camera's eye, under the same lights and environment (004 §4's
                                flicker input); coverage, depth and motion stay this pose's */
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
JND_EXPERIMENTAL void jnd_frame_free(jnd_frame *f);

/* Renders scene as seen from view into frame (allocated; previous contents
 * are not freed). The scene's meshes and textures are uploaded on first use
 * and kept while the same scene is rendered; maps changed since (resize,
 * set, restore) are uploaded again. */
jnd_status jnd_render(jnd_renderer *r, const jnd_scene *scene, const jnd_view *view,
                      jnd_frame *frame);

/* Display transform: linear RGB × 1 → sRGB-encoded 0..1 (clamped), for PNG. */
JND_EXPERIMENTAL jnd_status jnd_render_to_srgb(const jnd_image *linear, jnd_image *out);

/* How views are sampled around an object. */
#define JND_ELEVATION_MIN_DEG (-60.0)  /* default band of camera elevations without a ground plane */
#define JND_ELEVATION_MAX_DEG 75.0
typedef struct {
  int count;                 /* number of views (default 8) */
  uint64_t seed;             /* seed of the rotation of the point set and of the lights (default 1) */
  double coverage;           /* fraction of the image height the bounding sphere fills (default 0.8) */
  double distance;           /* > 0: camera distance from the centre in object units, overriding coverage */
  double fov_y_deg;          /* vertical field of view, degrees (default 45) */
  double aspect;             /* width / height of the image (default 1) */
  double min_elevation_deg;  /* lowest camera elevation, degrees; NaN (default): −60, or +10 when the
                                scene has a ground plane (jnd_scene_subject_bounds) */
  double max_elevation_deg;  /* highest (default 75) */
  int lights;                /* directional key lights sampled per view (default 1) */
  double light_intensity;    /* their illuminance (default 2) */
} jnd_view_sampling;

/* Fills p with the defaults above. */
void jnd_view_sampling_defaults(jnd_view_sampling *p);

/* Fills views[0..count-1] (caller-allocated) with cameras on a sphere around
 * what stands on the ground (jnd_scene_subject_bounds; the whole scene when
 * it has no ground plane): a Fibonacci spiral over the allowed band of
 * elevations, rotated about +Y by a seeded angle, looking at the centre;
 * each gets p->lights directional lights from the seeded generator, coming
 * from above and from the camera's side. Deterministic in p. Every other
 * field is from jnd_view_defaults. */
jnd_status jnd_views_sample(const jnd_scene *scene, const jnd_view_sampling *p, jnd_view *views);

/* A set of views and how they are rendered: what every rendering command
 * takes (`--views --seed --size --coverage/--distance --fov --lights
 * --cameras`, docs/render.md). */
typedef struct {
  jnd_view_sampling sampling;  /* sampled views (jnd_view_sampling_defaults; aspect comes from render) */
  const jnd_view *cameras;     /* explicit views instead (NULL: sampled); a view with nlights < 0
                                  gets the sampled lights of its index */
  int ncameras;
  const char *cameras_path;    /* or a cameras file (jnd_views_read), read by jnd_view_set_make
                                  when cameras is NULL; a task's run protects and reports it */
  jnd_renderer_params render;  /* image size, MSAA, anisotropy, environment, EGL platform */
} jnd_view_set;

/* Fills vs with the defaults of jnd_view_sampling_defaults and jnd_renderer_defaults. */
void jnd_view_set_defaults(jnd_view_set *vs);

/* The views of a set for scene: *out is allocated (free it), *count views. */
jnd_status jnd_view_set_make(const jnd_scene *scene, const jnd_view_set *vs, jnd_view **out, int *count);

/* Views from JSON text (what `jnd render --cameras` reads): a list of views,
 * or {"views": [...]}; each view is a camera {"eye", "target" (default
 * centre), "up" (default +Y), "fov_y_deg" or "fov" (default fov_y_deg),
 * "znear", "zfar"} or {"camera": {...}, "prev": {...} (the previous frame's
 * camera, for motion vectors), "lights": [{"type": "directional" | "point" |
 * "spot", "position", "direction", "color", "intensity", "range",
 * "inner_deg", "outer_deg"}]}. A view without "lights" gets nlights = −1 (the
 * caller fills them). *out is allocated (free it); name is used in errors. */
JND_EXPERIMENTAL jnd_status jnd_views_parse(const char *name, const char *text, size_t n, const double centre[3], double fov_y_deg,
                           jnd_view **out, int *count);

/* Reads a cameras file (at most 64 MiB of JSON as jnd_views_parse takes)
 * for scene: "target" defaults to the centre of jnd_scene_subject_bounds.
 * JND_ERR_IO / JND_ERR_FORMAT "PATH: problem". *out is allocated (free it). */
jnd_status jnd_views_read(const char *path, const jnd_scene *scene, double fov_y_deg, jnd_view **out, int *count);

/* The camera distance (object units) at which a sphere of radius r fills
 * fraction coverage of the image height with vertical field of view fov. */
JND_EXPERIMENTAL double jnd_camera_distance_for_coverage(double radius, double coverage, double fov_y_deg);

/* ------------------------------------------------------------------------ */
/* The judge: one rendered judgement for every task (000 §6, §9)            */
/* ------------------------------------------------------------------------ */
/* Every decision is the same loop: render the asset from a set of views,
 * show the frames as a display shows them, compare each with the reference
 * rendering in the vision model, pool per view over the object, and apply
 * the criterion "at most a fraction q of the views above P = p". The judge
 * is that loop, once. It is made from a scene (its state at creation is the
 * reference), a view set, a display and the model's parameters, a
 * calibration (JND transform and pooling percentile) and the criterion. It
 * renders and keeps each view's reference once; asked about the scene's
 * current state, it returns each view's P, the criterion and, on request,
 * the JND map, the frame and a heatmap. A state it has judged on a view is
 * never rendered again. When only maps changed, only the pixels of the
 * materials using them are rendered again (the rest is the reference's),
 * which equals a full rendering. See docs/judge.md.
 *
 *     jnd_judge_params jp;  jnd_judge_defaults(&jp);          // 8 views, 384², p93, p 0.2, q 0.1
 *     jnd_judge *j;  jnd_judge_create(scene, &jp, &j);         // renders the references
 *     jnd_scene_map_resize(scene, 0, 256, 256);                // a candidate state
 *     double P[8];  jnd_judgement r;
 *     jnd_judge_eval(j, 0, 8, 0, P, &r);                       // r.criterion.pass, P per view
 *     jnd_judge_free(j);
 *
 * Scene states. The judge holds no state of its own to set: a state is the
 * scene as it is when jnd_judge_eval is called, compared with the scene as
 * it was when the judge was made (or at jnd_judge_set_reference). The
 * caller puts the scene into the state to judge, asks, and puts it back:
 *   - a map's size or content: jnd_scene_map_resize / jnd_scene_map_set,
 *     back with jnd_scene_map_restore;
 *   - a mesh level: build or add levels of detail (jnd_scene_lod_build,
 *     jnd_scene_lod_add), then jnd_scene_lod_select(scene, k) for every
 *     mesh or jnd_scene_lod_select_mesh(scene, mesh, k) for one object;
 *     back with level 0. Such a state is rendered whole (depth and
 *     coverage move); the views and the crop stay the reference's;
 *   - a distance: views at that distance added with jnd_judge_add_views
 *     (their references are rendered with the reference's maps and
 *     levels, whatever the scene holds then), judged as a range (first, n)
 *     of jnd_judge_eval;
 *   - a gaze point: a judge made with model.has_gaze, moved with
 *     jnd_judge_set_gaze (pixels of the frame; every pixel's eccentricity
 *     is measured from it);
 *   - motion (popping): views with a previous pose (jnd_view.has_prev); the
 *     reference's motion goes into the model;
 *   - two renderings against each other (level k − 1 against level k, at a
 *     fixation point, as a change at a temporal frequency): jnd_pair_judge
 *     below, which shows frames as this judge does (jnd_judge_show).
 * A state is recognised by the content of its maps and the level (version)
 * of each mesh, so a size or level set again is answered from memory.
 */

/* The view criterion's parameters (000 §9). */
typedef struct {
  double p;              /* a view is above when its pooled P > p (0.2) */
  double q;              /* a state passes when at most a fraction q of the views are above (0.1) */
  double confidence;     /* confidence of the reported upper bound on the fraction above p (0.9) */
} jnd_criterion;

/* Fills c with 000 §9's criterion: p = 0.2, q = 0.1; confidence 0.9. */
void jnd_criterion_defaults(jnd_criterion *c);

typedef struct jnd_judge jnd_judge;

typedef struct {
  jnd_view_set views;          /* the views (8 sampled) and their rendering (384 × 384, 4× MSAA) */
  jnd_model_params model;      /* display and model constants (jnd_model_defaults); threads 0 on a
                                  CPU rasteriser (llvmpipe) means 1, as the rasteriser needs the cores */
  jnd_calibration calibration; /* JND transform and pooling percentile (identity, p93; 000 §6–§7) */
  jnd_criterion criterion;     /* p 0.2, q 0.1 (000 §9) */
  int partial;                 /* 1 (default): re-render only the pixels of materials whose maps
                                  changed; 0: render every view whole (same results, slower) */
  jnd_renderer *renderer;      /* NULL (default): the judge opens its own renderer with
                                  views.render. Otherwise it renders with this one, borrowed (it
                                  must outlive the judge and is not freed), sized to views.render's
                                  width and height before each rendering; the renderer's own
                                  samples, environment and platform apply. Judges of one scene at
                                  several window sizes then share one context, environment and
                                  uploaded scene. */
  void (*progress)(void *user, int renderings); /* NULL or called after each rendering */
  void *progress_user;
} jnd_judge_params;

/* Fills p with the defaults above. */
void jnd_judge_defaults(jnd_judge_params *p);

/* Makes a judge for scene, whose state now is the reference: samples (or
 * takes) the views, opens a renderer (or borrows p->renderer) and the
 * vision model, and renders each view's reference. The scene must outlive
 * the judge; the caller changes its maps between judgements. JND_ERR_GL
 * without an OpenGL context, JND_ERR_ARG for bad parameters. *out is the
 * caller's (jnd_judge_free). */
jnd_status jnd_judge_create(jnd_scene *scene, const jnd_judge_params *p, jnd_judge **out);

/* Frees the judge (not the scene); safe on NULL. */
void jnd_judge_free(jnd_judge *j);

/* Adds n more views (e.g. held-out views from another seed, or the same
 * views at another distance): their references are rendered now, in the
 * reference state (the scene's maps are put back for it and restored).
 * *first (may be NULL) receives the index of the first. */
jnd_status jnd_judge_add_views(jnd_judge *j, const jnd_view *views, int n, int *first);

/* Takes the scene's current state as the new reference: every view's
 * reference is rendered again and everything judged is forgotten. */
jnd_status jnd_judge_set_reference(jnd_judge *j);

/* Moves the fixation point (pixels of the rendered image; 002's eccentricity
 * is measured from it) of a judge made with model.has_gaze: what was judged
 * is forgotten, the references are kept. With a fixation point the judge
 * compares whole frames, not crops, so that the point means the same in
 * every view. JND_ERR_ARG for a judge made without one. */
jnd_status jnd_judge_set_gaze(jnd_judge *j, int has_gaze, double x, double y);

/* A fixation point for view v alone (002: the object seen at an
 * eccentricity): (x, y) in pixels of v's rendered frame (may lie outside
 * it); every pixel's eccentricity is measured from it on a flat screen at
 * the display's pixels per degree. has_gaze 0 removes it: the view follows
 * the judge's point again (jnd_judge_set_gaze, which sets every view's, or
 * none). Works on any judge: without model.has_gaze the views keep their
 * crops and the point is carried into the crop. What was judged on v is
 * forgotten when the point moves, the other views' judgements kept.
 * JND_ERR_ARG for a view out of range or a point not finite. */
jnd_status jnd_judge_set_view_gaze(jnd_judge *j, int v, int has_gaze, double x, double y);

/* View v's object seen ecc_deg degrees (0..90) out: its fixation point
 * placed ecc_deg to the left of the centre of the object's bounding box in
 * the reference (jnd_judge_set_view_gaze), as 002's observers fixate; the
 * point is written to *x, *y (either may be NULL). */
jnd_status jnd_judge_set_view_eccentricity(jnd_judge *j, int v, double ecc_deg, double *x, double *y);

/* Views held, and view v as rendered (owned by the judge). */
int jnd_judge_view_count(const jnd_judge *j);
const jnd_view *jnd_judge_view(const jnd_judge *j, int v);

/* What a judgement found on a range of views. */
typedef struct {
  int views;                       /* n, the views asked about */
  int judged;                      /* views whose P is known: n, or fewer when decided early */
  jnd_criterion_result criterion;  /* over the n views; views not judged count as P = 0, so
                                      when decided early the statistic is a lower bound and
                                      pass is 0 */
} jnd_judgement;

/* Flags of jnd_judge_eval. */
enum {
  JND_JUDGE_DECIDE = 1   /* stop once the state fails: views are judged in the order most likely to
                            fail first (most pixels of the changed materials), the rest get NaN */
};

/* Judges the scene's current state on views [first, first + n): the pooled
 * probability of detection of each view into p[0..n) (caller's; NaN for a
 * view not judged), and the criterion into out (may be NULL). P of a view
 * is its JND map (the state against the reference, both cropped to the
 * object's bounding box and shown on the display), through the
 * calibration, pooled with its percentile over the object's pixels (mask
 * > 0.5, without a ground plane); 0 when nothing of the object is seen. */
jnd_status jnd_judge_eval(jnd_judge *j, int first, int n, unsigned flags, double *p, jnd_judgement *out);

/* Images of view v in the current state, each allocated when asked for
 * (NULL: not wanted), all of the crop around the object: the JND map (1
 * channel), the frame as shown (sRGB-encoded 0..1, 3 channels), the
 * object mask (1 channel) and the heatmap of the JND map over the
 * reference (jnd_heatmap, 1 JND full scale). crop (may be NULL) receives
 * x, y, w, h of the crop in the rendered image. */
jnd_status jnd_judge_view_images(jnd_judge *j, int v, jnd_image *jmap, jnd_image *frame, jnd_image *mask,
                                 jnd_image *heatmap, int crop[4]);

/* Where the difference of the current state is in view v (which must have
 * been judged in this state): counts[m] (caller's, one per material) gets
 * the number of the object's pixels of material m whose P exceeds the
 * criterion's p (material from the reference's pixel centres). */
JND_EXPERIMENTAL jnd_status jnd_judge_material_counts(jnd_judge *j, int v, int *counts);

/* The finest mip level map `map` is sampled at in the references of views
 * [first, first + n) (000 §4's bound; fractional), or −1 if never. */
JND_EXPERIMENTAL double jnd_judge_mip_min(const jnd_judge *j, int map, int first, int n);

/* What a judge has done so far. */
typedef struct {
  int references;          /* reference renderings (with depth, mask and mip levels) */
  int renderings;          /* renderings of judged states: whole frames */
  int partial_renderings;  /* renderings of judged states: only the changed materials' pixels */
  int view_judgements;     /* views judged (rendered or known to be unchanged) */
  int states;              /* distinct states judged */
  int reused;              /* view judgements answered from what was judged before */
} jnd_judge_counts;
JND_EXPERIMENTAL void jnd_judge_get_counts(const jnd_judge *j, jnd_judge_counts *out);

/* "GL_RENDERER (platform)" of the judge's renderer. */
const char *jnd_judge_renderer(const jnd_judge *j);

/* The display path: the one place where a rendering becomes what the
 * viewer sees. linear (3 channels, linear RGB as jnd_render gives it, over
 * black) is composed over a grey background of linear value `background`
 * by its coverage (1 channel 0..1; NULL: shown as rendered, background
 * unused), the pixels where grey[q] != 0 (may be NULL) shown as that grey
 * alone; then clamped, sRGB-encoded (the display signal) and through
 * display d to absolute linear RGB in cd/m² (004 §3.1, the model's first
 * stage). cdm2 is allocated; srgb (may be NULL) receives the display
 * signal (allocated). Every judge shows frames through it. */
jnd_status jnd_judge_show(const jnd_display *d, const jnd_image *linear, const jnd_image *coverage,
                          double background, const unsigned char *grey, jnd_image *cdm2, jnd_image *srgb);

/* Two frames against each other: the judge for renderings made elsewhere
 * (two levels of detail in one view, the switch from level k − 1 to k,
 * the same object seen at several eccentricities). It holds the vision
 * model for a run: one model per pixels-per-degree and per caller working
 * at the same time (a model is one caller's while it compares), made on
 * first use and kept, so that a table of thousands of pairs makes as many
 * models as it has threads, not one per pair. Safe to call from several
 * threads at once; the JND map does not depend on which model answered. */
typedef struct jnd_pair_judge jnd_pair_judge;

/* How a pair is seen: per call. */
typedef struct {
  double ppd;                /* pixels per degree of the frames (0: the model's display's) */
  int has_gaze;              /* 1: a fixation point at (gaze_x, gaze_y), pixels of the frames (may
                                lie outside); each pixel is seen at its own eccentricity from it */
  double gaze_x, gaze_y;
  double temporal_hz;        /* > 0: the change from a to b is a temporal modulation at this
                                frequency (a level switching, a flicker: jnd_diff_inputs.temporal_hz);
                                0: a static difference */
  double background;         /* linear grey behind the frames where their coverage is < 1 */
  const unsigned char *grey; /* NULL, or per pixel: shown as the background grey in both frames */
} jnd_pair_view;

/* Makes a pair judge for the model's constants and display (model.display.ppd
 * is the default pixels per degree; has_gaze and the fixation point are
 * taken per call). No model is made until the first comparison. *out is
 * the caller's (jnd_pair_judge_free). */
jnd_status jnd_pair_judge_create(const jnd_model_params *model, jnd_pair_judge **out);

/* Frees the pair judge and its models; safe on NULL. */
void jnd_pair_judge_free(jnd_pair_judge *j);

/* The JND map of frame b against frame a (each linear RGB as rendered, 3
 * channels, with its coverage, 1 channel, or NULL), both shown with
 * jnd_judge_show over v->background and v->grey, compared by the model at
 * v's pixels per degree, fixation point and temporal frequency. jmap is
 * allocated (1 channel, the frames' size). JND_ERR_ARG when sizes differ. */
jnd_status jnd_pair_judge_compare(jnd_pair_judge *j, const jnd_image *a, const jnd_image *cov_a,
                                  const jnd_image *b, const jnd_image *cov_b, const jnd_pair_view *v,
                                  jnd_image *jmap);

/* How many vision models the pair judge has made so far. */
JND_EXPERIMENTAL int jnd_pair_judge_models(const jnd_pair_judge *j);

/* ------------------------------------------------------------------------ */
/* Tasks: frames of an asset (`jnd render`)                                 */
/* ------------------------------------------------------------------------ */

/* A change to the asset's texture maps before rendering (docs/render.md):
 * the maps named by `map` (MATERIAL/SLOT, "*" for every material, or a bare
 * "*") replaced by an image file, or resampled with Lanczos-3 by a factor or
 * to a size. */
typedef struct {
  const char *map;           /* the pattern */
  const char *file;          /* an image file instead (PNG/JPEG in the slot's encoding; NULL: a scale) */
  double factor;             /* resample by this factor (with w = 0) */
  int w, h;                  /* resample to w × h (w > 0) */
} jnd_map_edit;

/* What jnd_render_run writes per view (jnd_render_params.outputs). */
enum {
  JND_RENDER_COLOR = 1,      /* view_NNN.png, 8-bit sRGB */
  JND_RENDER_DEPTH = 2,      /* view_NNN_depth.png, 16-bit, depth / depth_scale */
  JND_RENDER_MASK = 4,       /* view_NNN_mask.png, 8-bit coverage */
  JND_RENDER_MOTION = 8,     /* view_NNN_motion.png, 16-bit RGB, 0.5 + d / (2 motion_scale) */
  JND_RENDER_MIP = 16,       /* view_NNN_mip.png, 16-bit RGBA, (level + 1) / 64 */
  JND_RENDER_EXR = 32        /* also the linear EXRs of the others */
};

typedef struct {
  jnd_view_set views;        /* the views (sampled, or cameras / cameras_path) and the rendering (512²) */
  int lod;                   /* the level of detail rendered (0: the finest) */
  int strict;                /* 1: a warning about the asset (a texture that cannot be loaded) is an error */
  double env_intensity;      /* multiplier on the environment (1; 0 turns IBL off) */
  double env_rotation_deg;   /* rotation of the environment about +Y (0) */
  double exposure;           /* multiplier on linear radiance before the display transform (1) */
  int background_env;        /* 1: the environment behind the object (0: black) */
  const jnd_light *lights;   /* fixed lights instead of the sampled ones (NULL) */
  int nlights;               /* <= JND_MAX_LIGHTS */
  double motion_orbit_deg;   /* a sampled view's previous pose for motion: orbited by this (0.5) */
  unsigned outputs;          /* JND_RENDER_* (COLOR | MASK) */
  const jnd_map_edit *edits; /* applied in order before rendering */
  int nedits;
  /* NULL or called after each view with line NULL */
  void (*progress)(void *user, const char *line, int done, int total);
  void *progress_user;
  jnd_run_options run;       /* the builtin's map side, the report's copy, timings, warnings */
} jnd_render_params;

/* Fills p with the defaults above. */
void jnd_render_defaults(jnd_render_params *p);

typedef struct {
  int views;                 /* the views rendered */
  size_t triangles;          /* the level's */
  char renderer[160];        /* "GL_RENDERER (platform)" */
  double load_s, renderer_s, render_s; /* wall-clock seconds: loading, the renderer, the frames */
  char *report;              /* the report's JSON text, as written to out_dir/views.json */
} jnd_render_result;

/* The task (`jnd render`): opens model (glTF, GLB, OBJ or builtin[:...]),
 * applies the edits, renders every view and writes into out_dir, through
 * one output writer (nothing over an input; all or nothing), the outputs
 * asked for and views.json (the report). *out is allocated
 * (jnd_render_result_free). Bad input: one error "FILE: problem", nothing
 * written. */
jnd_status jnd_render_run(const char *model, const jnd_render_params *p, const char *out_dir,
                          jnd_render_result **out);

/* Frees what jnd_render_run returned (NULL is fine). */
void jnd_render_result_free(jnd_render_result *r);

/* ------------------------------------------------------------------------ */
/* Tasks: images                                                            */
/* ------------------------------------------------------------------------ */

/* The built-in example pair (no files needed): a synthetic sRGB reference
 * (gradients, gratings, edges, colour, texture) and a test with four known
 * distortions, one per quadrant — 3×3 blur (top left), 1% noise (top right), a
 * colour shift (bottom left), a faint 1% luminance step (bottom right).
 * Both are allocated: w × h × 3, sRGB-encoded 0..1. w, h >= 64. */
JND_EXPERIMENTAL jnd_status jnd_example_pair(int w, int h, jnd_image *ref, jnd_image *test);

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
JND_EXPERIMENTAL jnd_status jnd_csf_context_create(const jnd_model_params *base, jnd_csf_context **out);
JND_EXPERIMENTAL void jnd_csf_context_free(jnd_csf_context *ctx);

/* The model's sensitivity (1 / threshold RMS cone contrast) for a stimulus:
 * the contrast where the max-pooled probability of detection is 0.5, found in
 * log contrast. The context's constants are used; the display's ppd is
 * replaced by one suited to the stimulus (docs/csf.md). detail may be NULL. */
JND_EXPERIMENTAL jnd_status jnd_csf_threshold(jnd_csf_context *ctx, const jnd_csf_stimulus *s, double *sensitivity,
                             jnd_csf_detail *detail);

/* The sampling chosen for a stimulus: pixels per degree, half-extent and edge taper in degrees. */
JND_EXPERIMENTAL void jnd_csf_sampling(const jnd_csf_stimulus *s, double *ppd, double *half_deg, double *taper_deg);

/* One row of a castleCSF-format threshold data set, resolved into a stimulus. */
typedef struct {
  jnd_csf_stimulus st;
  double measured;        /* measured sensitivity, 1 / threshold RMS cone contrast */
  double col_dir_id, bkg_id;
  int dataset;            /* index into jnd_csf_data.datasets */
  int line;               /* line of the CSV (the header is line 1) */
  int use;                /* 1: the row can be predicted */
  const char *skip;       /* why not, when use is 0 (a static string) */
  int derived_direction;  /* 1: its colour direction is not listed in the colour file but derived
                             from the data set's published definition (docs/csf.md) */
} jnd_csf_row;

typedef struct {
  int nrows;
  jnd_csf_row *rows;      /* one per CSV row, in order */
  int ndatasets;
  char **datasets;        /* data set names in order of first appearance */
  jnd_csv table;          /* the CSV itself, for writing its columns back out */
} jnd_csf_data;

/* Reads castleCSF's data_aggregated.csv format (columns listed in docs/csf.md)
 * with its colour directions (col_dir_id, L_delta, M_delta, S_delta) and
 * backgrounds (bkg_id, L, M, S). A row whose direction or background is not
 * listed is an error ("DATA: line N: ..."), except the directions kong2018
 * and hansen2009 define in their publications, which are derived
 * (docs/csf.md) and flagged. Rows that cannot be predicted (unknown stimulus,
 * no sensitivity, no size) get use = 0 and a reason. Free with
 * jnd_csf_data_free. */
JND_EXPERIMENTAL jnd_status jnd_csf_data_read(const char *data, const char *colors, const char *backgrounds, jnd_csf_data *out);
JND_EXPERIMENTAL void jnd_csf_data_free(jnd_csf_data *d);

/* What jnd_csf_evaluate does besides predicting. */
typedef struct {
  int fit;                   /* 1: fit the constants on the rows first (maximum a posteriori) */
  int cross_validate;        /* 1: leave-one-data-set-out: each data set predicted with the
                                constants fitted on the others */
  int search_every;          /* fits use every N-th row of each data set (1: all); the reported
                                predictions always use every row */
  int max_iterations;        /* Levenberg–Marquardt iterations of a fit (default 40) */
  int fit_mask_set;          /* 1: fit_mask says which constants to fit; 0: all not held */
  unsigned long long fit_mask; /* bit k: jnd_model_constants()[k] */
  double prior_weight_db;    /* the priors weigh as much as one row off by this × (constant −
                                prior) / prior_sd, in dB, against every row of the data: a fit
                                on every N-th row weighs its rows N times (default 4·√2, the
                                defaults' 4 dB against every second row) */
  int threads;               /* 0: OpenMP's default; results do not depend on it */
  void (*progress)(void *user, const char *stage, int done, int total); /* may be NULL */
  void *user;
  const char *const *folds;  /* with cross_validate: only these data sets' folds (NULL: every
                                data set); each fold is the same, the pooled cross-validated
                                figure covers only these sets. A name not in the data: error */
  int nfolds;
} jnd_csf_options;

JND_EXPERIMENTAL void jnd_csf_options_defaults(jnd_csf_options *o);

/* RMS of 20 log10(predicted / measured) over a set of rows, dB, and its
 * mean, the bias (> 0: the model is too sensitive; the spread about the
 * bias is sqrt(rmse² − bias²)). NaN: no rows. */
typedef struct {
  int rows, static_rows;     /* static: t_frequency = 0 */
  double rmse_db, rmse_db_static;        /* with the constants predictions used */
  double cv_rmse_db, cv_rmse_db_static;  /* leave-one-data-set-out (NaN without it) */
  double bias_db, cv_bias_db;            /* mean error over all the rows, training and cross-validated */
} jnd_csf_score;

#define JND_MAX_CONSTANTS 32

typedef struct {
  int nrows;
  double *predicted;         /* per row of the data: predicted sensitivity (NaN: not used) */
  double *predicted_cv;      /* per row: predicted by the constants fitted without its data
                                set (NaN without cross-validation) */
  int ndatasets;
  jnd_csf_score *dataset;    /* per data set of the data */
  jnd_csf_score pooled;
  jnd_model_params params;   /* the constants the predictions used (fitted when asked) */
  int nconstants;            /* jnd_model_constants() */
  int fitted[JND_MAX_CONSTANTS];     /* 1: constant k was fitted */
  double sd_ln[JND_MAX_CONSTANTS];   /* its posterior standard deviation, natural-log units */
  double *fold_value;        /* ndatasets × nconstants: the constants fitted without each data set
                                (NaN for a data set with no rows); NULL without cross-validation */
  double fold_sd_ln[JND_MAX_CONSTANTS]; /* spread of ln(constant) across the folds */
  double search_rmse_db;     /* the fit's objective at its end: RMS over the search rows, dB */
  int model_passes;          /* passes over the search rows, a measure of cost */
} jnd_csf_result;

/* Predicts every used row of d (jnd_csf_row.use) with the constants of
 * base, after fitting them when o->fit, and scores the predictions per data
 * set and pooled; with o->cross_validate also leave-one-data-set-out. The
 * procedure and its cost: docs/model.md, "Fitting and cross-validation".
 * r's arrays are allocated; free with jnd_csf_result_free. */
JND_EXPERIMENTAL jnd_status jnd_csf_evaluate(const jnd_csf_data *d, const jnd_model_params *base, const jnd_csf_options *o,
                            jnd_csf_result *r);
JND_EXPERIMENTAL void jnd_csf_result_free(jnd_csf_result *r);

/* `jnd csf` as one call (the task shape, docs/architecture.md): reads a
 * castleCSF-format CSV with its colour directions and backgrounds, selects
 * rows, predicts (and fits, cross-validates) with jnd_csf_evaluate, and
 * writes through one output writer (nothing over an input; all or nothing)
 * the rows with their predictions as a CSV (out_csv, NULL: none) and the
 * report's copy (run.report_path). */
typedef struct {
  jnd_model_params model;    /* the constants predictions start from (jnd_model_defaults) */
  jnd_csf_options options;   /* fit, cross-validation, threads, progress (jnd_csf_options_defaults) */
  const char *colors;        /* colour directions (NULL: color_directions.csv beside the data) */
  const char *backgrounds;   /* backgrounds (NULL: backgrounds.csv beside the data) */
  const char *const *datasets; /* only rows of these data sets (NULL: every data set) */
  int ndatasets;
  int static_only;           /* 1: skip rows with t_frequency > 0 */
  int every;                 /* only every N-th row (1) */
  jnd_run_options run;       /* the report's copy (map_size, timings unused) */
} jnd_csf_run_params;

/* Fills p with the defaults above. */
void jnd_csf_run_defaults(jnd_csf_run_params *p);

typedef struct {
  jnd_csf_data data;         /* the rows read, with .use and .skip as the selection left them */
  jnd_csf_result eval;       /* predictions and scores */
  char *report;              /* the report's JSON text */
} jnd_csf_run_result;

/* The task (`jnd csf`). *out is allocated (jnd_csf_run_result_free). Bad
 * input: one error "FILE: problem", nothing written. */
jnd_status jnd_csf_run(const char *data, const jnd_csf_run_params *p, const char *out_csv,
                       jnd_csf_run_result **out);

/* Frees what jnd_csf_run returned (NULL is fine). */
void jnd_csf_run_result_free(jnd_csf_run_result *r);

/* `jnd diff` as a call: applies the model's display to two decoded files
 * (infos from jnd_image_read; alpha composited over the display's black),
 * compares them and summarises. ref and test are consumed (freed) to keep
 * memory low. jnd_out may be NULL when only the statistics are wanted. */
jnd_status jnd_diff_files(jnd_model *m, jnd_image *ref, const jnd_image_info *ref_info,
                          jnd_image *test, const jnd_image_info *test_info,
                          const jnd_diff_inputs *in, const jnd_pooling *pool,
                          jnd_image *jnd_out, jnd_diff_stats *stats);

/* `jnd diff`'s parameters (docs/model.md). A comparison has two inputs and
 * writes named files (no folder), so its run takes both and the paths are
 * here. */
typedef struct {
  jnd_model_params model;    /* the model and its display (jnd_model_defaults) */
  jnd_pooling pool;          /* the pooling of P (p93; jnd_pooling_parse) */
  const char *calibration_path; /* a calibration (jnd_calibration_load): its beta and percentile (NULL) */
  const char *motion_path;   /* a 2-channel motion map, pixels per frame (NULL) */
  const char *weights_path;  /* a weight map, first channel (NULL) */
  const char *map_path;      /* write the JND map here as EXR (NULL: none) */
  const char *heatmap_path;  /* write the heatmap here as PNG (NULL: none) */
  double heatmap_max;        /* the heatmap's top, JND (0: its default) */
  double fail_above;         /* report whether p_detect exceeds this (< 0: not asked; -1) */
  int exr_scale_given;       /* 1: the display's exr_scale was chosen (no warning about a relative EXR) */
  jnd_run_options run;       /* the report's copy, timings, warnings (map_size unused) */
} jnd_diff_params;

/* Fills p with the defaults above. */
void jnd_diff_defaults(jnd_diff_params *p);

typedef struct {
  jnd_diff_stats stats;
  int width, height;
  int above;                 /* p_detect > fail_above (when asked) */
  char pooling[32];          /* the pooling's name */
  double total_s;            /* wall-clock seconds */
  char *report;              /* the report's JSON text, as the run wrote it to run.report_path */
} jnd_diff_result;

/* The task (`jnd diff`): reads ref and test (PNG, JPEG, HDR, EXR), compares
 * them on the display and writes, through one output writer (nothing over
 * an input; all or nothing), the map, the heatmap and the report's copy
 * asked for. *out is allocated (jnd_diff_result_free) with the report's
 * text. Bad input: one error "FILE: problem", nothing written. */
jnd_status jnd_diff_run(const char *ref, const char *test, const jnd_diff_params *p, jnd_diff_result **out);

/* Frees what jnd_diff_run returned (NULL is fine). */
void jnd_diff_result_free(jnd_diff_result *r);

/* ------------------------------------------------------------------------ */
/* Tasks: texture resolution (000)                                          */
/* ------------------------------------------------------------------------ */
/* Which texture resolution nobody notices (Wolski et al. 2019, 000 §4–§9):
 * every map of an asset is shrunk to candidate sizes, the asset is rendered
 * from sampled views, each view is compared with the full-resolution
 * rendering, and the smallest maps are kept for which at most a fraction q
 * of the views have a pooled probability of detection above p. Also: memory
 * accounting of maps with their mip chains (000 Table 2). The rendered
 * judgement is the judge's (above). See docs/texres.md. */

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
JND_EXPERIMENTAL const char *jnd_tex_format_name(jnd_tex_format f);

/* Bytes of a w × h texture in format f; with mips = 1, of its full mip chain
 * (levels down to 1 × 1, each side halved and rounded down, at least 1; block
 * formats round each level up to whole blocks). */
JND_EXPERIMENTAL size_t jnd_texture_bytes(jnd_tex_format f, int w, int h, int mips);

/* The block format engines usually pick for a slot: baseColor BC7 (BC1 for
 * channels <= 3 is smaller but BC7 is the quality default), normal BC5,
 * occlusion BC4, metallicRoughness BC1, emissive BC1. */
JND_EXPERIMENTAL jnd_tex_format jnd_slot_block_format(jnd_map_slot slot, int channels);

/* Parameters of a texture resolution search. */
typedef struct {
  jnd_judge_params judge;    /* views (8 sampled at 384²), display, model, calibration, criterion p, q */
  int verify_views;          /* M held-out views for a check of the choice (0: none) */
  double margin;             /* the choice must pass with P threshold p·(1 − margin) on its views,
                                so that it holds on views it was not chosen on (docs/texres.md
                                "Held-out views"; default 0.5) */
  int confirm_rounds;        /* then up to this many fresh sets of as many views must agree: a set
                                where the choice fails joins the choice's views and the choice
                                grows (default 2; 0: none) */
  int min_size;              /* floor of the power-of-two candidates, pixels (32) */
  const int *sizes;          /* explicit candidate sizes (longer side, pixels) or NULL */
  int nsizes;
  const char *maps;          /* NULL: every map; else a comma list of MATERIAL/SLOT names or
                                bare slot names (that slot of every material) to search;
                                the others stay at their size */
  int level;                 /* the mesh level judged with the maps (0): the reference stays level 0
                                with the file's maps; every candidate state draws this level of the
                                scene's chain (jnd budget searches textures under each level) */
  jnd_judge *judge_shared;   /* NULL (default): the search makes its own judge (and renders the
                                references). Otherwise borrowed, not freed: a judge of this scene made
                                in the reference state (level 0, the file's maps) with judge.views —
                                its first views are the search's — and the criterion p·(1 − margin)
                                the search decides with; the search adds its confirmation and
                                held-out views to it. Searches under several levels then render the
                                references once and share every state judged (jnd budget). counts
                                are then the judge's so far, not this search's alone */
  int matrix;                /* baseColor × normal matrix of each material that has both
                                (000 Fig. 13), an illustration: 0 (default) none; 1 the candidates
                                down to each map's first failure on its own; 2 every candidate */
  /* NULL or called after each rendering (line NULL) and at the end of each
   * stage with a one-line summary of it; done counts renderings, total is
   * an estimate */
  void (*progress)(void *user, const char *line, int done, int total);
  void *progress_user;
  jnd_run_options run;       /* the run's report copy, timings, warnings (jnd_texres_run) */
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
                                with only this map at candidate k; NaN where not evaluated; a
                                lower bound where series_partial is set */
  unsigned char series_partial[JND_TEXRES_MAX_CAND]; /* 1: judged until it failed, not on every view */
  jnd_psychometric fit;      /* 000 eq. 1 fitted to series (log2 domain) */
  int fit_ok;
  double fit_res;            /* continuous resolution at P = p (longer side, pixels) */
  int fit_cand[2];           /* rounded up to a candidate */
  int image;                 /* the image it samples: index into the result's images */
} jnd_texres_map;

/* One image of the file as a GPU holds it: every map (slot) that samples it
 * shares it — a packed occlusion-roughness-metal image, a texture several
 * materials use — so it is counted once, with its mip chain, and kept at one
 * size: the largest any of its maps needs (docs/texres.md "Memory"). */
typedef struct {
  int first_map;             /* the first map (index into the result's maps) that samples it */
  int nmaps;                 /* how many maps sample it */
  int orig[2], chosen[2];    /* width, height in pixels */
  jnd_tex_format block_format; /* the format its slots need together: the one with the most
                                bytes per texel among its maps' jnd_slot_block_format */
  size_t bytes_before[JND_TEX_FORMATS], bytes_after[JND_TEX_FORMATS]; /* with mip chains */
} jnd_texres_image;

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
  int nviews;                /* the choice's views: the first set and each confirmation set judged */
  double *view_p;            /* pooled P per view of the chosen combination */
  int *view_judge;           /* the judge's index of each (owned): with judge_shared the other
                                searches' views lie between the sets (jnd_judge_view_images) */
  jnd_criterion_result views; /* the criterion (p, q) over them, with its upper bound */
  double choice_p;           /* the threshold the choice was made with: p·(1 − margin) */
  int verify_views;          /* M (0: not run) */
  double *verify_p;          /* pooled P per held-out view */
  jnd_criterion_result verify; /* the criterion (p, q) over the held-out views */
  int worst_view;            /* the view with the highest P (choice), an index of view_p */
  jnd_image worst_heatmap;   /* its heatmap (jnd_heatmap), sRGB 0..1 */
  int nmatrix;
  jnd_texres_matrix *matrix; /* owned */
  int nimages;
  jnd_texres_image *images;  /* owned: the unique images the maps sample */
  size_t before_bytes[JND_TEX_FORMATS], after_bytes[JND_TEX_FORMATS]; /* every unique image once,
                                with its mip chain */
  size_t block_before_bytes, block_after_bytes; /* each image in its block_format */
  double ppd;                /* the display's pixels per degree */
  int evaluations;           /* states judged */
  int renderings;            /* all renderings: references, whole frames, partial re-renders */
  jnd_judge_counts counts;   /* the judge's counts, in detail */
  char renderer[160];
  /* set by jnd_texres_run only */
  char *report;              /* the report's JSON text, as written to out_dir/texres.json */
  int passes;                /* the choice passes the criterion (and the held-out views) */
} jnd_texres_result;

/* The task (`jnd texres`): reads model (glTF, GLB, OBJ or builtin[:...]),
 * runs jnd_texres_search on it and writes into out_dir, through one output
 * writer (nothing over an input; all or nothing): texres.json (the report),
 * worst_view.png, matrix_N.png, and model/ (a glTF/GLB copy pointing at the
 * resized maps) or maps/ (OBJ, builtin: the resized maps as PNG). *out is
 * allocated (jnd_texres_result_free) with the report's text; it is set also
 * when the choice fails the criterion (passes = 0, JND_OK). Bad input: one
 * error "FILE: problem", nothing written. */
jnd_status jnd_texres_run(const char *model, const jnd_texres_params *p, const char *out_dir,
                          jnd_texres_result **out);

/* Frees what jnd_texres_run returned (NULL is fine). */
void jnd_texres_result_free(jnd_texres_result *r);

/* The search of docs/texres.md on scene (loaded by the caller; its maps are
 * left at the chosen sizes on return, level 0 selected) with a judge on its views: mip-usage
 * bound, per-map series from the bound down searched by bisection
 * (detection never falls as a map shrinks), coordinate descent over the maps
 * until the combination passes, the optional matrices, and the
 * verification on held-out views. Writes nothing. out owns arrays
 * (jnd_texres_result_clear). JND_ERR_ARG for a scene without texture maps
 * or an unknown map name. */
JND_EXPERIMENTAL jnd_status jnd_texres_search(jnd_scene *scene, const jnd_texres_params *p, jnd_texres_result *out);

/* Frees a result's arrays; safe on a zeroed struct. */
JND_EXPERIMENTAL void jnd_texres_result_clear(jnd_texres_result *r);

/* A picture of matrix t of a result (000 Fig. 13): the criterion statistic
 * for every pair of sizes (columns the first map's, rows the second's, the
 * longer side in pixels) with axis titles, each cell's value and a colour
 * legend of P, the chosen pair outlined; below it the same per view. out is
 * allocated (3 channels, sRGB 0..1) for jnd_image_write_png. */
JND_EXPERIMENTAL jnd_status jnd_texres_matrix_figure(const jnd_texres_result *r, int t, jnd_image *out);

/* Writes a copy of the glTF/GLB model at src_path under out_dir whose maps
 * are the scene's maps at the sizes in use now (jnd_scene_map_get of each
 * resized map, encoded as the file had it: PNG or JPEG), and which points
 * at them; unchanged maps and buffers are copied. A .glb stays one .glb
 * file; a .gltf gets its images and buffers as files beside it. The model
 * file's name is kept. The input is never modified. out_path (NULL or
 * caller's, n bytes) receives the written model's path. */
JND_EXPERIMENTAL jnd_status jnd_texres_write_model(const jnd_scene *scene, const char *src_path, const char *out_dir,
                                  char *out_path, size_t n);

/* ------------------------------------------------------------------------ */
/* Tasks: calibration to measured thresholds (000 §6–§7)                    */
/* ------------------------------------------------------------------------ */
/* Retunes the pooling percentile and a linear transform of the JND map to
 * threshold data (docs/calibrate.md); the result is a jnd_calibration
 * (above, under pooling). */

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
JND_EXPERIMENTAL jnd_status jnd_calib_percentiles(const jnd_image *jnd_map, const jnd_image *mask, double *out);

typedef struct {
  int folds;                 /* k of k-fold cross-validation by scene (5; at most the scenes) */
  double beta;               /* psychometric slope (3.5) */
  double threshold_p;        /* P at which threshold resolutions are compared (0.2) */
  double bias_min, bias_max; /* exhaustive bias range, JND (−2 .. 2) */
  int bias_steps;            /* grid steps over it (21) */
  double scale_min, scale_max; /* scale range (0.05 .. 20), searched in log */
} jnd_calibrate_params;

/* Fills p with the defaults above. */
JND_EXPERIMENTAL void jnd_calibrate_defaults(jnd_calibrate_params *p);

/* What a calibration fit found. */
typedef struct {
  jnd_calibration cal;       /* fitted on all scenes */
  double mae_px;             /* training error on all scenes, pixels */
  int folds;
  double fold_mae_px[32];    /* held-out error of each fold, pixels */
  double cv_mae_px;          /* mean held-out absolute error over scenes, pixels */
  double *errors_px;         /* per scene: predicted − measured threshold, held out (pixels);
                                owned, jnd_calibrate_result_clear */
  double *predicted_px;      /* per scene: predicted threshold with the final calibration */
  int nscenes;
  double pct_mae_px[JND_CALIB_NPCT]; /* best training error per percentile */
  char *report;              /* jnd_calibrate_run: the report's JSON text (the calibration file) */
} jnd_calibrate_result;

/* The model's JND percentiles 90..99 of map `map` (MATERIAL/SLOT) of scene
 * at nres sizes (longer side in pixels, aspect kept; the other maps as they
 * are), over the object's pixels of the judge's views together, each
 * against the rendering with the file's map (the judge's JND maps, before
 * any calibration): the image series of `jnd calibrate` for an asset. out
 * holds nres × JND_CALIB_NPCT doubles (caller's). The map is restored on
 * return. */
JND_EXPERIMENTAL jnd_status jnd_calib_series_percentiles(jnd_scene *scene, const char *map, const int *sizes, int nres,
                                        const jnd_judge_params *p, double *out);

/* Fits percentile (90..99), scale and bias minimising the mean absolute
 * error between predicted and measured threshold resolution (at P =
 * threshold_p) over the scenes, 000 §6–§7.1: per percentile, an exhaustive
 * search over bias with the best scale for each (golden section in log
 * scale), then a local refinement; the predicted threshold of a scene is
 * read from 000 eq. 1 fitted to the calibrated pooled P over its series,
 * in pixels as 000. Then k-fold cross-validation by scene (000 §7.3).
 * Deterministic. out owns arrays (jnd_calibrate_result_free). */
JND_EXPERIMENTAL jnd_status jnd_calibrate_fit(const jnd_calib_scene *scenes, int n, const jnd_calibrate_params *p,
                             jnd_calibrate_result *out);

/* Frees the arrays of a result; safe on a zeroed struct. */
JND_EXPERIMENTAL void jnd_calibrate_result_clear(jnd_calibrate_result *r);

/* What `jnd calibrate` takes besides the thresholds. */
typedef struct {
  jnd_calibrate_params fit;  /* folds, slope, threshold P, search ranges (jnd_calibrate_defaults) */
  jnd_judge_params judge;    /* how an asset's series is rendered and judged: 4 views at 256²,
                                the display, the model (its beta is fit.beta) */
  const char *pairs;         /* a CSV of image pairs (scene, resolution, reference, test; paths
                                relative to it) for the scenes without a model column (NULL) */
  const int *sizes;          /* an asset's series: these sizes (longer side, pixels); NULL: the
                                CSV's resolutions, else 11 steps from the map's size to 1/6 of it */
  int nsizes;
  const char *histogram;     /* also this PNG of the held-out errors (000 Fig. 9/11; NULL) */
  /* NULL or called after each scene's series (line NULL, then its summary) */
  void (*progress)(void *user, const char *line, int done, int total);
  void *progress_user;
  jnd_run_options run;       /* the report's copy, timings, map size of builtin assets */
} jnd_calibrate_run_params;

/* Fills p with the defaults above. */
void jnd_calibrate_run_defaults(jnd_calibrate_run_params *p);

/* The task (`jnd calibrate`): reads the measured thresholds (CSV: scene, and
 * mu and sigma or resolution and rate; model and map columns for assets,
 * relative to the CSV), measures the model's JND percentiles over each
 * scene's series (rendered assets, or p->pairs), fits (jnd_calibrate_fit)
 * and writes out_path — the calibration file every --calibration reads, which
 * is also the report — and p->histogram, through one output writer (never
 * over an input, including the files the tables name; all or nothing).
 * *out is allocated (jnd_calibrate_result_free) with the report's text in
 * report. Bad input: one error "FILE: problem", nothing written. */
jnd_status jnd_calibrate_run(const char *thresholds_csv, const jnd_calibrate_run_params *p, const char *out_path,
                             jnd_calibrate_result **out);

/* Frees what jnd_calibrate_run returned (NULL is fine). */
void jnd_calibrate_result_free(jnd_calibrate_result *r);

/* The picture of 000 Fig. 9/11: how many scenes' held-out errors
 * (r->errors_px, predicted − measured) fall in each 32-pixel bin centred on
 * a multiple of 32 (the end bins, ±512, hold everything beyond), as bars on
 * labelled axes with the mean absolute error in the title. out is a canvas
 * (sRGB 0..1) the caller frees. JND_ERR_ARG without scenes. */
JND_EXPERIMENTAL jnd_status jnd_calibrate_histogram(const jnd_calibrate_result *r, jnd_image *out);

/* ------------------------------------------------------------------------ */
/* Point of Imperceptibility of a level-of-detail chain (003)              */
/* ------------------------------------------------------------------------ */
/* Wu, Agu & Lindsay (2007), 003: per target screen, an error for every level
 * of a chain — the object-space term (1 − F2/F1) × the area-weighted L2
 * distance between the surfaces plus the screen-space term E_p of the level
 * rendered on a large virtual screen M1 and minified to the screen M2
 * (eq. 1), and that times the perceptual term M_p, the difference of the
 * lit renderings' Haar bands weighted by the Mannos–Sakrison CSF (eqs.
 * 3–4) — and the knee of each Pareto curve as the Point of
 * Imperceptibility; the same for each texture map over its mip chain
 * (003 §4.3). Beside it, two rules of thumb. What 003 leaves open and how it
 * is decided here: docs/lod.md. Typical use:
 *
 *     jnd_scene *s;  jnd_scene_load("bunny.obj", &s);
 *     jnd_scene_lod_build(s, NULL);                       // the chain
 *     jnd_poi_params pp;  jnd_poi_defaults(&pp);          // 4 screens, 2 views
 *     jnd_poi_result r;  jnd_poi_analyse(s, &pp, &r);
 *     for (int i = 0; i < r.nscreens; i++)
 *       printf("%s: level %d\n", r.screens[i].screen.name, r.screens[i].poi_level);
 *     jnd_poi_result_free(&r);  jnd_scene_free(s);
 */

/* A target screen: its resolution and the pixels per degree its viewer sees. */
typedef struct {
  char name[32];
  int width_px, height_px;
  double ppd;
} jnd_poi_screen;

/* Fills s from "PRESET" (a display preset with a pixel size: standard-fhd,
 * standard-4k, phone, laptop), "WxH" (pixels; ppd of a 24" 16:9-class
 * screen at 60 cm, see docs/lod.md) or "WxH@PPD". JND_ERR_ARG otherwise
 * (vr has no pixel size: give WxH@PPD). */
JND_EXPERIMENTAL jnd_status jnd_poi_screen_parse(const char *spec, jnd_poi_screen *s);

/* The most views a rendering command takes, the CLI's --views limit in every
 * command: also the most of 003's views (jnd_poi_params.views) and of the
 * perceptual step's views per distance (jnd_lod_switch_params.judge). */
#define JND_VIEWS_MAX 4096

typedef struct {
  const jnd_poi_screen *screens; /* target screens (NULL: standard-fhd, standard-4k, phone, laptop) */
  int nscreens;
  int views;                 /* views averaged (2; 003 used one, and proposes several; at most
                                JND_VIEWS_MAX) */
  uint64_t seed;             /* view and light sampling seed (1) */
  double coverage;           /* fraction of each screen's height the bounding sphere fills (0.5) */
  double fov_y_deg;          /* vertical field of view (45) */
  int lights;                /* directional key lights of the lit renderings (1) */
  double virtual_scale;      /* the virtual screen M1 shows the object this many times larger
                                than the largest screen does (1.5) ... */
  int max_virtual_px;        /* ... but at most this many pixels a side (4096) */
  int anisotropy;            /* renderer anisotropy of the M1 renderings (4) */
  int surface_samples;       /* points sampled on level 0 for the object-space term (65536) */
  double meshopt_pixels;     /* meshoptimizer's rule: the coarsest level whose result error covers
                                at most this many pixels (1) */
  double pixel_error;        /* the fixed pixel-error rule: the coarsest level whose measured largest
                                deviation covers at most this many pixels (0.5) */
  int textures;              /* 1 (default): also each texture map over its mip chain (003 §4.3) */
  int min_texture_px;        /* the mip chain stops at this longer side (8) */
  const char *env_path;      /* environment of the lit renderings (NULL: the studio) */
  const char *platform;      /* EGL platform (NULL: auto) */
  void (*progress)(void *user, const char *stage, int done, int total); /* NULL or per step */
  void *progress_user;
} jnd_poi_params;

/* Fills p with the defaults above. */
JND_EXPERIMENTAL void jnd_poi_defaults(jnd_poi_params *p);

/* One level on one screen's Pareto curve. Every term is dimensionless. */
typedef struct {
  double object;             /* eq. 1's object-space term: (1 − F2/F1) × the RMS distance from level
                                0's surface to this level's, over the scene's extent */
  double e_p;                /* eq. 2 (p = 2) of the unlit renderings: RGB RMSE in 1/256 steps over the
                                screen's W × H pixels, RMS over the views */
  double m_p;                /* eq. 4 of the lit renderings, mean over the views */
  double error;              /* eq. 1: object + e_p (unlit) */
  double error_lit;          /* eq. 3: error × m_p */
  double meshopt_px;         /* meshoptimizer's error on this screen, pixels (measured max for imported levels) */
  double deviation_px;       /* the measured largest deviation on this screen, pixels */
} jnd_poi_point;

typedef struct {
  jnd_poi_screen screen;
  double object_px;          /* the bounding sphere's diameter on this screen, pixels */
  int m2_px;                 /* the side of the screen region that holds it (M2), pixels */
  int nlevels;
  jnd_poi_point *curve;      /* nlevels; owned */
  int poi_level;             /* knee of error_lit: 003's Point of Imperceptibility (eq. 3) */
  int poi_level_unlit;       /* knee of error (eq. 1) */
  int meshopt_level;         /* the coarsest level meshoptimizer's rule allows */
  int pixel_level;           /* the coarsest level the fixed pixel-error rule allows */
} jnd_poi_screen_result;

/* A texture map over its mip chain (003 §4.3): E_p and M_p only. */
typedef struct {
  int map;                   /* scene map index */
  char name[128];            /* MATERIAL/SLOT */
  int nlevels;
  int (*size)[2];            /* nlevels × (width, height); owned */
  int nscreens;
  double *e_p, *m_p;         /* nscreens × nlevels (screen-major); owned */
  double *error;             /* e_p × m_p: eq. 3 without the object-space term */
  int *poi_level;            /* per screen: knee of error */
  int *poi_level_ep;         /* per screen: knee of e_p alone */
} jnd_poi_texture;

typedef struct {
  int nlevels;
  jnd_lod_level_info *levels;        /* owned */
  jnd_surface_distance *distance;    /* per level, from level 0; owned */
  double extent, radius;             /* scene extent (largest bounding-box side) and sphere radius */
  int nscreens;
  jnd_poi_screen_result *screens;    /* owned */
  int ntextures;
  jnd_poi_texture *textures;         /* owned */
  int virtual_px;                    /* side of the virtual screen M1 */
  int views, renderings;
  char renderer[160];
} jnd_poi_result;

/* Runs 003's analysis on the scene's chain (it needs at least two levels:
 * jnd_scene_lod_build or imported ones). Renders every level unlit and lit
 * from p->views views on one virtual screen and minifies to each target;
 * deterministic whatever the thread count. Level 0 is selected on return.
 * out owns arrays (jnd_poi_result_free). JND_ERR_ARG for a scene with one
 * level; JND_ERR_GL without a renderer. */
JND_EXPERIMENTAL jnd_status jnd_poi_analyse(jnd_scene *scene, const jnd_poi_params *p, jnd_poi_result *out);

/* Frees a result's arrays; safe on a zeroed struct. */
JND_EXPERIMENTAL void jnd_poi_result_free(jnd_poi_result *r);

/* The Pareto plot of screen i: both curves (each over its largest value)
 * against triangles (log axis), 003's knees, the rules of thumb and, when
 * perceptual >= 0, the perceptual choice (jnd_lod_switch_analyse's level)
 * marked. out is allocated (3 channels, sRGB 0..1) for jnd_image_write_png. */
JND_EXPERIMENTAL jnd_status jnd_poi_pareto_plot(const jnd_poi_result *r, int screen, int perceptual, jnd_image *out);

/* The perceptual choice and the switch distances of a chain on one screen,
 * through the judge (docs/lod.md, docs/judge.md): level 0 is the reference;
 * a level passes at a camera distance when 000 §9's criterion (p, q) holds
 * on views sampled at that distance, each rendered at the screen's own pixel
 * scale (the central part of the screen that holds the object; where the
 * object is larger than max_px, on a screen scaled down until it fits, with
 * as many fewer pixels per degree) and judged on the screen's display.
 * Procedure:
 *  1. the viewing condition: the distance at which the bounding sphere fills
 *     `coverage` of the screen's height (or `distance`);
 *  2. the perceptual level: the coarsest level that passes there, levels
 *     tried coarsest first (a failing level costs a view or two);
 *  3. switch distances: for level k = 1, 2, ... the nearest distance, from
 *     level k − 1's on, at which it passes: by bisection on a geometric grid
 *     of distances from the viewing condition's out to where the sphere
 *     fills far_coverage of the height, ratio 1 + tolerance between grid
 *     points (P falls with distance). Starting from the finer level's
 *     distance makes them monotone by construction; a level that fails at
 *     the far end gets INFINITY, and so do the coarser ones;
 *  4. popping (pop, default on): for each level k shown somewhere, the
 *     nearest distance, from where 3 and level k − 1's switch distance
 *     allow level k on, at which the switch from level k − 1 to k, rendered
 *     on the same views with the chosen motion (default static), does not
 *     pop: the largest R over the views below pop_rating_limit
 *     (jnd_pop_switch_distance, 004 §3.2);
 *  5. the switch distance of level k: the farthest of 3's, 4's and level
 *     k − 1's, so still monotone; switch_by says which decided.
 * Typical use (levels made or imported first):
 *
 *     jnd_lod_switch_params sp;  jnd_lod_switch_defaults(&sp);
 *     jnd_poi_screen scr;  jnd_poi_screen_parse("phone", &scr);
 *     jnd_lod_switch_result r;  jnd_lod_switch_analyse(scene, &scr, &sp, &r);
 *     // r.perceptual_level, r.switch_distance[k], r.switch_coverage[k]
 *     jnd_lod_switch_result_free(&r);
 */
typedef struct {
  jnd_judge_params judge;    /* views (count 4, at most JND_VIEWS_MAX; seed, fov 45, lights;
                                coverage and distance are set below), MSAA, environment, model constants, calibration, criterion;
                                the display and the rendering size come from the screen;
                                judge.renderer lends every distance's judge (and popping) one
                                renderer, NULL: one is opened per call */
  double coverage;           /* viewing condition of the perceptual choice: the sphere fills this
                                fraction of the screen's height (0.5, as 003's analysis) ... */
  double distance;           /* ... or, when > 0, this camera distance (object units: metres in glTF) */
  double far_coverage;       /* the farthest distance searched: the sphere fills this fraction of the
                                screen's height there (0.02) */
  double tolerance;          /* ratio between neighbouring distances of the search, minus 1 (0.1):
                                a switch distance is within a factor 1 + tolerance of the true one */
  int max_px;                /* largest rendering side, pixels (512): at a distance where the object is
                                larger, it is judged on a screen scaled down until it fits (fewer
                                pixels per degree); wherever it fits, at the screen's own scale */
  int pop;                   /* 1 (default): level k is also never shown nearer than where the switch
                                from level k − 1 stops popping (004 §3.2, jnd_pop_switch_distance: the
                                largest R over the same views below pop_rating_limit), searched from
                                the viewing condition out to far_coverage; 0: the criterion only */
  int pop_motion;            /* the switch's motion, a jnd_pop_motion_kind: JND_POP_ORBIT (0, default),
                                JND_POP_OBJECT or JND_POP_PAN ... */
  double pop_speed;          /* ... at this speed, degrees per second (0, default: static) */
  double pop_rating_limit;   /* R of "rarely visible" (1, 004 §3.2) */
} jnd_lod_switch_params;

/* Fills p with the defaults above (the judge's: jnd_judge_defaults, 4 views). */
JND_EXPERIMENTAL void jnd_lod_switch_defaults(jnd_lod_switch_params *p);

/* What decided a level's switch distance. */
typedef enum {
  JND_LOD_SWITCH_REFERENCE = 0, /* level 0: distance 0 */
  JND_LOD_SWITCH_CRITERION,     /* (a): the criterion against level 0 (also on a tie with (b)) */
  JND_LOD_SWITCH_POP,           /* (b): popping of the switch from the level before */
  JND_LOD_SWITCH_FINER,         /* the finer level's distance (monotone by construction) */
} jnd_lod_switch_by;

/* "reference", "criterion", "popping", "finer level". */
JND_EXPERIMENTAL const char *jnd_lod_switch_by_name(jnd_lod_switch_by b);

typedef struct {
  jnd_poi_screen screen;
  int nlevels;
  double view_distance;      /* the viewing condition: camera distance, object units */
  double view_coverage;      /* and the fraction of the screen's height the sphere fills there */
  int window_px;             /* side of the renderings at the viewing condition (each distance of the
                                search has its own: the object's diameter plus margins, at most max_px) */
  double scale;              /* 1, or < 1 where the object at the viewing condition would not fit
                                max_px: the screen's pixels and pixels per degree times scale (each
                                distance has its own: 1 wherever the object fits, switch_scale) */
  int perceptual_level;      /* the coarsest level that passes at the viewing condition (0: none) */
  double *statistic;         /* per level at the viewing condition: the criterion's statistic (the
                                (floor(q·n) + 1)-th largest P; a lower bound when decided early), NaN
                                where not judged; 0 for level 0. Owned */
  double *p_max;             /* per level: the largest P of the views judged there (NaN: none). Owned */
  double *switch_distance;   /* per level: from which camera distance it may be shown (0 for level 0;
                                INFINITY: not even at the far end). Owned */
  double *switch_coverage;   /* per level: the fraction of the screen's height the sphere fills at that
                                distance (1 for level 0 ... 0 for INFINITY). Owned */
  /* switch_distance[k] is the farthest of its two components and of level k − 1's switch distance
   * (monotone), lod_switch_combine: */
  double *switch_distance_criterion; /* (a) where level k passes the criterion against level 0 (the
                                search of step 3; INFINITY: never). Owned */
  double *switch_scale;      /* the screen's scale level k was judged at there: 1 where the object fits
                                max_px at that distance (the screen's own pixels per degree), else
                                below 1 (NaN: level 0, or never). Owned */
  double *switch_distance_pop; /* (b) where the switch from level k − 1 to k stops popping (pop on),
                                searched from where (a) and level k − 1's switch distance allow level
                                k on (nearer it cannot decide): that distance when the switch does not
                                pop there, INFINITY when it pops even at the far end; NaN where not
                                searched (level 0, pop off, or level k never shown by (a) or by a
                                finer level). Owned */
  double *pop_max_rating;    /* the largest R over the views measured at switch_distance_pop (at the
                                far end for INFINITY; −INFINITY: no popping region; NaN: not
                                searched). Owned */
  jnd_lod_switch_by *switch_by; /* what decided switch_distance[k]. Owned */
  int pop_evaluations;       /* distances at which switches were rendered and predicted */
  int distances;             /* distances at which views were rendered (a judge, window and scale each) */
  int judgements;            /* judge evaluations (a level at a distance) */
  jnd_judge_counts counts;   /* the judges' counts, summed over the distances */
} jnd_lod_switch_result;

/* Runs the procedure above on scene's chain (at least two levels) for one
 * screen. Level 0 is selected on return. Deterministic for given
 * parameters. out owns arrays (jnd_lod_switch_result_free). JND_ERR_ARG for
 * bad parameters or a single level, JND_ERR_GL without a renderer. */
JND_EXPERIMENTAL jnd_status jnd_lod_switch_analyse(jnd_scene *scene, const jnd_poi_screen *screen, const jnd_lod_switch_params *p,
                                  jnd_lod_switch_result *out);

/* Frees a result's arrays; safe on a zeroed struct. */
JND_EXPERIMENTAL void jnd_lod_switch_result_free(jnd_lod_switch_result *r);

/* The fraction of the image height a sphere of radius r fills from camera
 * distance d with vertical field of view fov (the inverse of
 * jnd_camera_distance_for_coverage); 0 for an infinite distance. */
JND_EXPERIMENTAL double jnd_coverage_at_distance(double radius, double distance, double fov_y_deg);

/* `jnd lod`'s parameters: the chain (made with meshoptimizer, or the one
 * the file has as MSFT_lod, or levels from other files), 003's analysis per
 * screen, and with `perceptual`, per screen the perceptual choice and the
 * switch distances through the judge (jnd_lod_switch_analyse), the model's
 * MSFT_screencoverage then from the first screen's switch distances
 * (docs/lod.md). */
typedef struct {
  jnd_lod_params chain;      /* how a chain is made */
  int rebuild;               /* 1: make a chain even when the file has MSFT_lod levels (0) */
  const char *const *level_paths; /* levels from other files, finest first: used as levels 1.. instead */
  int nlevel_paths;
  int analyse;               /* 1 (default): 003's analysis; 0: the chain and the model only */
  jnd_poi_params poi;        /* the analysis (jnd_poi_defaults) */
  int perceptual;            /* 1 (default): the perceptual choice and switch distances per screen
                                (with analyse; the screens, seed, fov, lights, environment and
                                platform are poi's) */
  jnd_lod_switch_params sw;  /* their parameters (jnd_lod_switch_defaults; coverage is poi's) */
  int threads;               /* screens judged at once by the perceptual step, each on a thread with
                                a renderer of its own (0: OpenMP's default, the cores); with 2 or
                                more, 003's analysis runs on the calling thread beside them; the
                                report is the same for every count */
  void (*progress)(void *user, const char *stage, int done, int total); /* also the analysis's */
  void *progress_user;
  jnd_run_options run;       /* map side of "builtin[:...]" (512 here), the report's copy, timings,
                                warnings (jnd_lod_run) */
} jnd_lod_run_params;

/* Fills p with the defaults above. */
void jnd_lod_run_defaults(jnd_lod_run_params *p);

typedef struct {
  jnd_scene *scene;          /* the asset with its chain, level 0 selected (owned) */
  const char *chain_source;  /* "made" (meshoptimizer), "file" (MSFT_lod), "levels" (other files) */
  int analysed;
  jnd_poi_result poi;        /* when analysed */
  jnd_lod_switch_result *sw; /* when perceptual: one per screen of poi (owned) */
  int nsw;
  double coverage[64];       /* MSFT_screencoverage written, one per level (jnd_scene_write_lod_glb) */
  char coverage_rule[256];   /* how they were chosen, naming the screen (the first of poi's) */
  double load_s, chain_s, analysis_s, write_s; /* wall-clock seconds of each stage (for timings) */
  double load_cpu_s, chain_cpu_s, analysis_cpu_s; /* user + system seconds of all threads */
  /* set by jnd_lod_run only */
  char model_path[4600];     /* the GLB written: out_dir/model/NAME.glb */
  int nplots;
  char plots[16][96];        /* pareto_SCREEN.png names, one per screen, under out_dir */
  size_t memory_before_bytes, memory_after_bytes; /* level 0 and the first screen's perceptual
                                choice as written (jnd_scene_lod_bytes; 0 without it) */
  char *report;              /* the report's JSON text, as written to out_dir/lod.json */
} jnd_lod_result;

/* The task (`jnd lod`): loads model (glTF/GLB/OBJ, or builtin[:...]), gets
 * its chain, runs the analysis (jnd_lod_analyse) and writes into out_dir,
 * through one output writer (nothing over an input; all or nothing):
 * lod.json (the report), model/NAME.glb (every level, MSFT_lod with
 * MSFT_screencoverage) and pareto_SCREEN.png per screen. *out is allocated
 * (jnd_lod_result_free) with the report's text. Bad input: one error
 * "FILE: problem", nothing written. */
jnd_status jnd_lod_run(const char *model, const jnd_lod_run_params *p, const char *out_dir,
                       jnd_lod_result **out);

/* Frees what jnd_lod_run returned (NULL is fine). */
void jnd_lod_result_free(jnd_lod_result *r);

/* The chain and the analysis of jnd_lod_run, and the model's screen
 * coverages: loads model_path, gets its chain, runs 003's analysis and the
 * perceptual step. Writes nothing. out is the caller's
 * (jnd_lod_result_clear). */
JND_EXPERIMENTAL jnd_status jnd_lod_analyse(const char *model_path, const jnd_lod_run_params *p, jnd_lod_result *out);

/* Frees the scene, the analysis and the report; safe on a zeroed struct. */
JND_EXPERIMENTAL void jnd_lod_result_clear(jnd_lod_result *r);

/* ------------------------------------------------------------------------ */
/* Tasks: texture-set PCA (001)                                             */
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
JND_EXPERIMENTAL jnd_status jnd_texset_from_images(const jnd_image *maps, const char *const *names, int n,
                                  const char *channels, jnd_texset *out);

/* Reads n map files (PNG, JPEG, HDR, EXR) and builds the set as above; map
 * names are the file stems less their shared prefix. Errors name the file:
 * "PATH: problem". */
JND_EXPERIMENTAL jnd_status jnd_texset_read(const char *const *paths, int n, const char *channels, jnd_texset *out);

/* Frees the planes and zeroes the struct; safe on a zeroed struct. */
JND_EXPERIMENTAL void jnd_texset_free(jnd_texset *set);

/* Rebuilds map `map` as its file had it (file_channels channels, the set's
 * size) from channels, a w × h × C image in the set's channel order (the set
 * itself or a reconstruction): identical copies are filled from their
 * source, constant channels with their value, channels --channels left out
 * with 0. out is allocated. */
JND_EXPERIMENTAL jnd_status jnd_texset_map_image(const jnd_texset *set, const jnd_image *channels, int map, jnd_image *out);

/* Parses per-channel importance weights (001 "Input channel weighting"):
 * "albedo=2,height=0.75"; a key is a map name (all its channels) or a
 * channel name ("albedo.g"). weights[c] for c < set->c is filled: 1 where
 * not named. Weights must be > 0. JND_ERR_ARG for an unknown name. */
JND_EXPERIMENTAL jnd_status jnd_texset_parse_weights(const jnd_texset *set, const char *spec, double *weights);

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
JND_EXPERIMENTAL jnd_status jnd_pca_analyse(const jnd_texset *set, const double *weights, jnd_pca *out);

/* The contribution matrix |S·Tᵀ| of 001: out[k·C + c] = sqrt(energy_k) ·
 * |basis[c·C + k]|, how much input channel c feeds component k. out holds
 * C·C doubles (caller's). */
JND_EXPERIMENTAL void jnd_pca_contribution(const jnd_pca *pca, double *out);

/* A picture of the contribution matrix: a row per input channel (named
 * from set; NULL: numbered), a column per component (1 = the most energy,
 * with its share of the energy), each cell coloured and labelled with its
 * contribution, and a colour legend. out is allocated (3 channels, sRGB
 * 0..1) for jnd_image_write_png. */
JND_EXPERIMENTAL jnd_status jnd_pca_contribution_plot(const jnd_pca *pca, const jnd_texset *set, jnd_image *out);

/* How the components are stored. */
typedef struct {
  int components;                        /* K: components kept, 0..C */
  int scale[JND_PCA_MAX_CHANNELS];       /* component k at 1/2^scale[k] of the size
                                            (0 full, 1 half, ... JND_PCA_MAX_SCALE);
                                            box-filtered down, Lanczos-3 up */
  int bits[JND_PCA_MAX_CHANNELS];        /* 8 or 16; 0 = float, no quantisation */
} jnd_pca_encoding;

/* All C components at full resolution with 8 bits. */
JND_EXPERIMENTAL void jnd_pca_encoding_default(const jnd_pca *pca, jnd_pca_encoding *e);

/* Storage of an encoding of a w × h set in bytes: Σ_k pixels_k · bits_k / 8
 * (float counts 4 bytes) plus the float32 reconstruction matrix. */
JND_EXPERIMENTAL size_t jnd_pca_storage_bytes(const jnd_pca_encoding *e, int c, int w, int h);

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
JND_EXPERIMENTAL jnd_status jnd_pca_encode(const jnd_texset *set, const jnd_pca *pca, const jnd_pca_encoding *e,
                          jnd_pca_encoded *out);

/* Reconstructs the set (w × h × C, allocated in out) from components comp
 * (K images, 0..1, any of the sizes 1/2^s; NULL = enc->comp), e.g. after
 * block compression. */
JND_EXPERIMENTAL jnd_status jnd_pca_reconstruct(const jnd_pca_encoded *enc, const jnd_image *comp, jnd_image *out);

/* Per-channel PSNR (dB, peak 1) of a reconstruction (w × h × C) against the
 * set; mse may be NULL. */
JND_EXPERIMENTAL jnd_status jnd_texset_psnr(const jnd_texset *set, const jnd_image *recon, double *psnr_db, double *mse);

/* Frees the component images; safe on a zeroed struct. */
JND_EXPERIMENTAL void jnd_pca_encoded_free(jnd_pca_encoded *enc);

/* The smallest encoding (K, per-component scale in 0..max_scale, bits 8 or
 * 16) whose every channel reaches min_psnr_db. Candidates are ranked with
 * an additive error model (components are decorrelated: a channel's MSE is
 * Σ_k basis[c][k]²·D_k / weight_c², D_k measured per component and option),
 * then the best is encoded for real and checked; out is that encoding.
 * JND_ERR_ARG when even all components at 16 bits miss the target. */
JND_EXPERIMENTAL jnd_status jnd_pca_choose_psnr(const jnd_texset *set, const jnd_pca *pca, double min_psnr_db,
                               int max_scale, jnd_pca_encoding *out);

/* Rendered visibility (001 + the judge): the material of a model is
 * rendered from sampled views with its maps replaced by a reconstruction of
 * the set, against the set itself (the reference), and each view's P is the
 * judge's (pooled over the object, calibrated, as texres's). An encoding
 * passes the judge's criterion: at most a fraction q of the views with
 * P > p. See docs/pca.md "Rendered visibility". Typical use:
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
  jnd_judge_params judge;     /* views (8 sampled at 384², at most JND_PCA_MAX_VIEWS), display,
                                 model, calibration (pooling) and criterion (p 0.2, q 0.1): the
                                 same judgement as every task's */
  int builtin_map_size;       /* map side of the "builtin" asset, pixels (2048) */
} jnd_pca_render_params;

/* Fills p with the defaults above. */
JND_EXPERIMENTAL void jnd_pca_render_defaults(jnd_pca_render_params *p);

/* A model's material, an open renderer, the vision model and the sampled
 * views, kept for any number of measurements. Not thread-safe. */
typedef struct jnd_pca_render jnd_pca_render;

/* Loads model_path (jnd_scene_open: glTF/GLB/OBJ or a built-in asset) and
 * finds material (JND_ERR_ARG "PATH: no material 'NAME' (...)" listing
 * them). The judge (renderer, model, views) is made when a set is bound.
 * *out is the caller's (jnd_pca_render_free). */
JND_EXPERIMENTAL jnd_status jnd_pca_render_open(const char *model_path, const char *material, const jnd_pca_render_params *p,
                               jnd_pca_render **out);

/* Frees everything open; safe on NULL. */
JND_EXPERIMENTAL void jnd_pca_render_free(jnd_pca_render *r);

/* "GL_RENDERER (platform)" of the renderer in use. */
JND_EXPERIMENTAL const char *jnd_pca_render_description(const jnd_pca_render *r);

/* The material's own maps (the file's versions) as a texture set, maps
 * named after their slots ("baseColor", "normal", ...), with the channels
 * the shader reads: metallicRoughness G and B, occlusion R (channels, as in
 * jnd_texset_from_images, overrides per slot name); the other maps keep
 * their informative channels. slots[i] receives map i's slot (caller's,
 * JND_PCA_MAX_MAPS). orig_bytes (may be NULL) receives the bytes of the
 * distinct original images at 8 bits per channel (a glTF image packing
 * occlusion with metal-roughness counts once). JND_ERR_ARG when the material
 * has no texture maps. */
JND_EXPERIMENTAL jnd_status jnd_pca_render_material_set(const jnd_pca_render *r, const char *channels, jnd_texset *set,
                                       jnd_map_slot *slots, size_t *orig_bytes);

/* The slot a map name suggests: an exact slot name, else by words (case
 * ignored): "emissive"/"emission" → emissive; "normal" → normal;
 * "metal"/"rough"/"orm" → metallicRoughness; "occlusion", "ao" (whole word)
 * → occlusion; "basecolor"/"base_color"/"albedo"/"diffuse"/"color"/"colour"
 * → baseColor. Returns 0 when none fits. */
JND_EXPERIMENTAL int jnd_pca_slot_guess(const char *name, jnd_map_slot *slot);

/* Binds map i of set to slot slots[i] of the material (that slot must have
 * a texture in the model), and makes the judge whose reference is every
 * view with the set's own values in those slots (maps resampled to the
 * set's size go back to their file's size): JND_ERR_GL without an OpenGL
 * context. The set must outlive the binding's use. */
JND_EXPERIMENTAL jnd_status jnd_pca_render_bind(jnd_pca_render *r, const jnd_texset *set, const jnd_map_slot *slots);

/* Pooled probability of detection per view and the criterion. */
typedef struct {
  int views;
  double p[JND_PCA_MAX_VIEWS];   /* pooled P of each view, 0..1 */
  int above;                     /* views with P > p */
  int allowed;                   /* views allowed above: floor(q · views) */
  double p_criterion;            /* the (allowed + 1)-th largest P: passes iff <= max_p */
  int pass;                      /* above <= allowed */
} jnd_pca_visibility;

/* Judges every view with the bound maps rebuilt from channels (w × h × C
 * in the set's channel order: a reconstruction, e.g. jnd_pca_reconstruct)
 * against the reference. The maps stay replaced until the next call. */
JND_EXPERIMENTAL jnd_status jnd_pca_render_measure(jnd_pca_render *r, const jnd_image *channels, jnd_pca_visibility *out);

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
JND_EXPERIMENTAL jnd_status jnd_pca_choose_rendered(jnd_pca_render *r, const jnd_texset *set, const jnd_pca *pca, int max_scale,
                                   jnd_pca_encoding *out, jnd_pca_visibility *vis, jnd_pca_search_log *log);

/* The simple call: opens model_path with the defaults, binds the set's maps
 * to the slots their names suggest (jnd_pca_slot_guess), measures enc and
 * returns the criterion statistic (jnd_pca_visibility.p_criterion). */
JND_EXPERIMENTAL jnd_status jnd_pca_rendered_visibility(const jnd_texset *set, const jnd_pca_encoded *enc,
                                       const char *model_path, const char *material,
                                       double *p_detect);

/* Block compression (001 "Caveats"). 8-bit texels; blocks of 4 × 4 texels,
 * the image edge replicated into partial blocks. BC1: 8 bytes a block, RGB
 * as two RGB565 endpoints and 2-bit indices (4-colour mode); BC4: 8 bytes,
 * one channel as two 8-bit endpoints and 3-bit indices; BC5: two BC4. */
typedef enum { JND_BC1 = 1, JND_BC4 = 4, JND_BC5 = 5 } jnd_bc_format;

/* Bytes a w × h texture takes in format f. */
JND_EXPERIMENTAL size_t jnd_bc_size(jnd_bc_format f, int w, int h);

/* Encodes channels [first, first+n) of img (values 0..1, n = 3 for BC1,
 * 1 for BC4, 2 for BC5) into blocks (jnd_bc_size bytes, caller's). BC1 fits
 * the principal axis of each block then refines the endpoints by least
 * squares; BC4 starts from the block's min/max and refines likewise. */
JND_EXPERIMENTAL jnd_status jnd_bc_encode(jnd_bc_format f, const jnd_image *img, int first, uint8_t *blocks);

/* Decodes blocks into channels [first, first+n) of img (already allocated
 * w × h, values 0..1 on the 8-bit grid). */
JND_EXPERIMENTAL jnd_status jnd_bc_decode(jnd_bc_format f, const uint8_t *blocks, jnd_image *img, int first);

/* The set as it comes back from block compression, w × h × C in out
 * (allocated): JND_PCA_BC_PCA_BC4 / _BC1 compress the components of enc as
 * jnd_pca_block_compression does and reconstruct; JND_PCA_BC_PLAIN
 * compresses the maps themselves (enc unused, may be NULL). bytes (may be
 * NULL) receives the compressed size. */
typedef enum { JND_PCA_BC_PCA_BC4 = 0, JND_PCA_BC_PCA_BC1, JND_PCA_BC_PLAIN } jnd_pca_bc_variant;
JND_EXPERIMENTAL jnd_status jnd_pca_block_compressed(const jnd_texset *set, const jnd_pca_encoded *enc, jnd_pca_bc_variant v,
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
JND_EXPERIMENTAL jnd_status jnd_pca_block_compression(const jnd_texset *set, const jnd_pca_encoded *enc,
                                     jnd_pca_bc_report *out);

/* `jnd pca` as one call: which rule chooses the encoding (docs/pca.md). */
typedef enum {
  JND_PCA_RULE_AUTO = 0,     /* RENDERED with a model, else ENERGY */
  JND_PCA_RULE_RENDERED,     /* the cheapest encoding whose rendering passes the judge's criterion */
  JND_PCA_RULE_ENERGY,       /* the fewest components holding a fraction of the total variance
                                (full size, 8 bits) */
  JND_PCA_RULE_PSNR,         /* the smallest storage whose every channel reaches psnr_db */
  JND_PCA_RULE_COMPONENTS    /* as given: components, scale, bits */
} jnd_pca_rule;

typedef struct {
  const char *const *maps;   /* map files (PNG, JPEG, HDR, EXR); none: the model material's own maps */
  int nmaps;
  const char *channels;      /* per-map channel picks "normal=rg,..." (NULL: the informative ones) */
  const char *weights;       /* importance weights "albedo=2,..." (NULL: all 1) */
  const char *model;         /* the model of a rendered measurement (glTF/GLB/OBJ/builtin; NULL: none) */
  const char *material;      /* its material using the set */
  const char *const *slots;  /* "FILE=SLOT": the slot a map file replaces (default: from its name) */
  int nslots;
  jnd_pca_render_params render; /* the judgement: views, display, calibration, criterion */
  jnd_pca_rule rule;         /* AUTO */
  double energy;             /* ENERGY: fraction of the total variance kept (0.99) */
  double psnr_db;            /* PSNR: the floor, dB */
  int max_scale;             /* PSNR, RENDERED: coarsest component size 1/2^max_scale (2) */
  int components;            /* COMPONENTS: K (−1: all) */
  int scale[JND_PCA_MAX_CHANNELS]; /* COMPONENTS: per component, the last repeating (none: 0) */
  int nscale;
  int bits[JND_PCA_MAX_CHANNELS];  /* COMPONENTS: 8 or 16 per component, the last repeating (none: 8) */
  int nbits;
  int block_compression;     /* 1 (default): PSNR, and P with a model, under block compression */
  /* NULL or called with a one-line summary at the end of each stage */
  void (*progress)(void *user, const char *line, int done, int total);
  void *progress_user;
  int write_maps;            /* jnd_pca_run: also the maps rebuilt from the encoding, as PNG (0) */
  jnd_run_options run;       /* jnd_pca_run: the report's copy, timings, warnings */
} jnd_pca_params;

/* Fills p with the defaults above. */
void jnd_pca_defaults(jnd_pca_params *p);

/* One packed component texture of a choice, as a GPU holds it. */
typedef struct {
  int width, height, channels, bits; /* channels: 1 (R), 2 (RG), 3 (stored RGBA) or 4; 8 or 16 bits */
  size_t bytes;                      /* with its mip chain */
  int comp[4];                       /* the components in its channels R, G, B, A */
} jnd_pca_texture_info;

typedef struct {
  jnd_texset set;                          /* the set (owned) */
  char labels[JND_PCA_MAX_MAPS][160];      /* per map: its file, or MATERIAL/SLOT */
  double weights[JND_PCA_MAX_CHANNELS];
  jnd_pca pca;
  jnd_pca_rule rule;                       /* the rule applied (AUTO resolved) */
  jnd_pca_encoded enc;                     /* the chosen encoding, encoded (owned) */
  jnd_pca_encoded enc_float;               /* the same K at full size without quantisation (owned) */
  int has_bc;
  jnd_pca_bc_report bc;
  size_t original_bytes;                   /* the baseline: the distinct original images at 8 bits
                                              per channel as their files have them */
  /* memory as a GPU holds it (docs/pca.md "Memory"): before, each unique
   * source image once as RGBA8 with its mip chain (texres's headline);
   * after, each packed component texture with its mip chain at its texels'
   * bytes (1 channel R, 2 RG, 3 or 4 RGBA; 8 or 16 bits) */
  int image_of[JND_PCA_MAX_MAPS];          /* per map: its unique image (index into images) */
  int nimages;
  struct {
    int first_map;                         /* the first map that samples it */
    int width, height;
    size_t bytes;                          /* RGBA8 + mips */
  } images[JND_PCA_MAX_MAPS];
  int ntextures;
  jnd_pca_texture_info textures[JND_PCA_MAX_CHANNELS]; /* components_N.png, in order: the packing
                                                          (jnd_pca_pack's rule), decided once */
  size_t gpu_before_bytes, gpu_after_bytes;
  int rendered;                            /* 1: measured on the model */
  jnd_map_slot slots[JND_PCA_MAX_MAPS];
  char renderer[160];
  jnd_pca_visibility vis;                  /* the chosen encoding, judged (with a model) */
  jnd_pca_visibility vis_bc[3];            /* pca_bc4, pca_bc1, plain_bc */
  size_t bytes_bc[3];
  jnd_pca_search_log *log;                 /* RENDERED: what was tried (owned) */
  double seconds[6];                       /* read, decomposition, choice, encoding, block
                                              compression, rendering */
  char *report;                            /* jnd_pca_run: the report's JSON text (pca.json) */
} jnd_pca_result;

/* The task (`jnd pca`): jnd_pca_choose on the set — the map files
 * p->maps, or with model (glTF/GLB/OBJ/builtin; NULL: none) the material
 * p->material's own maps, rendered for the rule RENDERED (model replaces
 * p->model) — then into out_dir, through one output writer (nothing over an
 * input; all or nothing): the components packed as components_N.png, the
 * contribution plot, with p->write_maps the rebuilt maps, and pca.json.
 * *out is allocated (jnd_pca_result_free) with the report's text. Bad
 * input: one error "FILE: problem", nothing written. */
jnd_status jnd_pca_run(const char *model, const jnd_pca_params *p, const char *out_dir, jnd_pca_result **out);

/* Frees what jnd_pca_run returned (NULL is fine). */
void jnd_pca_result_free(jnd_pca_result *r);

/* The choice alone: reads the set, analyses it, chooses the encoding by the
 * rule, encodes it, measures block compression and, with a model, the
 * judge's P of the encoding and of its block-compressed variants. Writes
 * nothing. out owns its arrays (jnd_pca_result_clear). Errors name the file
 * or option. */
JND_EXPERIMENTAL jnd_status jnd_pca_choose(const jnd_pca_params *p, jnd_pca_result *out);

/* Frees a result's arrays; safe on a zeroed struct. */
JND_EXPERIMENTAL void jnd_pca_result_clear(jnd_pca_result *r);

/* One texture of packed components, as an engine samples them. */
typedef struct {
  jnd_image image;           /* 1–4 channels (R, G, B, A), values 0..1 */
  int bits;                  /* 8 or 16 */
  int ncomp, comp[4];        /* the components in its channels */
} jnd_pca_texture;

/* Packs the components of enc into textures: components of one size and
 * bit depth, in order, four to an RGBA texture (the last of a group may
 * have 1–3 channels). tex (caller's, JND_PCA_MAX_CHANNELS entries) receives
 * *n textures; the caller frees their images. */
JND_EXPERIMENTAL jnd_status jnd_pca_pack(const jnd_pca_encoded *enc, jnd_pca_texture *tex, int *n);

/* ------------------------------------------------------------------------ */
/* Tasks: one budget for the whole asset (texture sizes and LOD chain)      */
/* ------------------------------------------------------------------------ */
/* `jnd budget` (docs/budget.md): the texture sizes and the levels of detail
 * chosen together on the judge, with one cost — the textures' GPU memory
 * (unique images, their mip chains, the block formats of
 * jnd_slot_block_format) plus the finest level's triangles × an exchange
 * rate in bytes. The chain and its popping-free switch distances are
 * jnd_lod_analyse's; per mesh level up to lod's perceptual one, the texture
 * sizes are texres's search with that level drawn (jnd_texres_params.level);
 * a ladder of uniform texture scales per level gives the Pareto front of
 * (memory, triangles, statistic) and budget mode's candidates; each coarser
 * level is checked on held-out views at its switch distance with its maps
 * capped at the mips that distance samples (000 §4). Typical use:
 *
 *     jnd_budget_params bp;  jnd_budget_defaults(&bp);    // cheapest unnoticed
 *     bp.memory_bytes = 8 << 20;  bp.triangles = 20000;   // or: least noticed within a budget
 *     jnd_budget_result *r;  jnd_budget_run("helmet.glb", &bp, "out", &r);
 *     // r->chosen, r->separate, r->candidates (r->ncandidates), out/model/helmet.glb
 *     jnd_budget_result_free(r);
 */

typedef struct {
  jnd_texres_params texres;  /* the texture search and the judge of every candidate: views (their
                                coverage is set to lod.poi.coverage, the one viewing condition),
                                display, model, calibration, criterion (p, q), margin, held-out views */
  jnd_lod_run_params lod;    /* the chain, the screens and the switch distances (jnd_lod_analyse with
                                the perceptual step; the model's MSFT_screencoverage is the first
                                screen's) */
  double bytes_per_triangle; /* the exchange rate of a triangle in bytes; 0 (default): level 0's own,
                                its vertex and index bytes as written (jnd_scene_lod_bytes) over its
                                triangles, so that the cost is the GPU bytes of textures and mesh */
  double memory_bytes;       /* budget mode: the most texture bytes (0: no bound) ... */
  double triangles;          /* ... and the most triangles of the finest level (0: no bound); with
                                either, the candidate within both with the lowest statistic */
  int verify_views;          /* held-out views at each coarser level's switch distance (4) */
  void (*progress)(void *user, const char *line, int done, int total); /* NULL or per stage */
  void *progress_user;
  jnd_run_options run;       /* map side of "builtin[:...]" (512), the report's copy, timings, warnings */
} jnd_budget_params;

/* Fills p with the defaults above (texres's and lod's own; 003's texture
 * analysis off, lod's map side 512). */
void jnd_budget_defaults(jnd_budget_params *p);

/* One candidate: a finest level and a size per map. */
typedef struct {
  int level;                 /* the chain's level drawn nearest (levels finer than it are dropped) */
  int scale;                 /* −1: sizes of texres's search at that level; −2: the separately chosen
                                (texres at level 0 with lod's perceptual level); −3: cheaper encodings per image
                                (docs/budget.md): in cheapest-unnoticed mode the cheapest of those,
                                in budget mode a candidate over the memory budget with as few images
                                encoded as bring it within; s ≥ 0:
                                every map at its original halved s times (not below min_size) */
  int (*sizes)[2];           /* per scene map: width, height in pixels (owned) */
  jnd_tex_format *formats;   /* per scene map: its image's encoding on the GPU (owned): the slots'
                                block format (jnd_slot_block_format), or BC1 where the encoding
                                search chose it (scale −3) */
  int *packed;               /* per scene map: the principal components its material is packed in
                                (001, pca's encoding, components in BC4/BC5 with mips), or 0 (owned;
                                scale −3, and −2 where `jnd pca`'s own choice is taken) */
  jnd_pca_encoding *layouts; /* per scene material: the layout of a packed material's components
                                (their scales and bits) where `jnd pca` chose it (scale −2 and the
                                candidates made from it); components 0: K components at full size
                                and 8 bits, budget's own search (owned) */
  size_t memory_bytes;       /* the textures: unique images, their formats, mip chains */
  size_t triangles;          /* of the level */
  double cost;               /* memory_bytes + triangles × the exchange rate */
  double statistic;          /* the criterion's statistic (the (⌊q·n⌋ + 1)-th largest pooled P) on the
                                judge's views at the viewing condition */
  int pass;                  /* statistic ≤ p there */
  int searched_pass;         /* scale −1: texres's search passed (its margin, confirmation, held-out
                                views); −2 (and −3 in budget mode): the statistic is at most
                                p·(1 − margin); −3 in cheapest-unnoticed mode: that and the
                                confirmation rounds; else 0 */
  int pareto;                /* not dominated in (memory, triangles, statistic) */
  int inferred;              /* 1: a ladder state not rendered, as the one before it (one halving
                                fewer, same level) had statistic 1 and detection never falls as a
                                map shrinks: its statistic is 1 */
  int held_out_fail;         /* cheapest-unnoticed mode: chosen, then seen on its held-out views at
                                some level's switch distance, so dropped for the next cheapest
                                (docs/budget.md step 6); 0 otherwise */
} jnd_budget_candidate;

/* `jnd pca`'s own choice for one material, the separately chosen
 * candidate's third part (docs/budget.md "The separate choice"). */
typedef enum {
  JND_BUDGET_PCA_SHARED = 0,  /* not offered: another material samples one of its images */
  JND_BUDGET_PCA_NONE,        /* pca's rendered search found no encoding that passes */
  JND_BUDGET_PCA_DEARER,      /* chosen, not taken: at texres's sizes its components take at least
                                 the material's images' bytes */
  JND_BUDGET_PCA_TAKEN        /* taken: the material's maps at texres's sizes packed in its layout */
} jnd_budget_pca_status;

typedef struct {
  int material;              /* scene material */
  int maps;                  /* its maps (0: none, not listed) */
  jnd_budget_pca_status status;
  jnd_pca_encoding encoding; /* pca's choice (status DEARER, TAKEN) */
  double statistic;          /* its criterion statistic on pca's own views (NaN: none) */
  size_t components_bytes;   /* at texres's sizes, BC4/BC5 with mips (status DEARER, TAKEN) */
  size_t images_bytes;       /* the material's images at texres's sizes, slots' block formats */
} jnd_budget_pca;

/* A level of the written chain, from its switch distance on. */
typedef struct {
  int level;                 /* the chain's level */
  double switch_distance;    /* first screen, object units (0: the finest written) */
  double switch_coverage;    /* the sphere's projected diameter over the screen's height there */
  int (*sizes)[2];           /* per map: the chosen size capped at the mips that distance samples
                                (000 §4's bound; what a streaming engine holds; owned) */
  size_t texture_bytes, geometry_bytes, triangles; /* held while only this level is shown */
  int views;                 /* held-out views judged at the switch distance (0: not verified) */
  double statistic;          /* the criterion's statistic there (NaN: not verified) */
  int pass;
} jnd_budget_level;

typedef struct {
  int mode;                  /* 0 cheapest unnoticed, 1 least noticed within the budget */
  double bytes_per_triangle; /* the rate used */
  int nmaps;
  char (*map_names)[128];    /* owned */
  int ncandidates;
  jnd_budget_candidate *candidates; /* owned: every candidate judged */
  int chosen, separate;      /* indices into candidates */
  int nlevels;
  jnd_budget_level *levels;  /* owned: the written chain, finest first */
  int nseparate_levels;
  jnd_budget_level *separate_levels; /* owned: the separate candidate's chain, verified as levels is */
  jnd_lod_result lod;        /* the chain and switch distances (its scene holds the chosen maps) */
  jnd_texres_result texres;  /* texres's search at level 0 (the separately chosen sizes) */
  int npca;
  jnd_budget_pca *pca;       /* owned, per scene material: `jnd pca`'s own choice (the separate one) */
  int passes;                /* the choice passes at the viewing condition and at every switch distance */
  int separate_taken;        /* cheapest-unnoticed mode: the choice is the separate candidate, cheaper
                                than the joint one (or the joint one seen) and unnoticed at p on the
                                judge's views and on held-out views at every switch distance, though
                                over texres's margin (docs/budget.md step 7) */
  int joint;                 /* the joint search's own choice (after step 6): chosen, or the candidate
                                the separate one replaced */
  double search_s, verify_s; /* wall-clock seconds */
  /* set by jnd_budget_run only */
  char model_path[4600];     /* the GLB written: out_dir/model/NAME.glb */
  char *report;              /* the report's JSON text, as written to out_dir/budget.json */
} jnd_budget_result;

/* The task (`jnd budget`): reads model (glTF, GLB, OBJ or builtin[:...]),
 * searches as above and writes into out_dir, through one output writer
 * (nothing over an input; all or nothing): budget.json (the report),
 * model/NAME.glb (the chosen levels, MSFT_lod with MSFT_screencoverage, the
 * maps at the chosen sizes) and pareto.png. *out is allocated
 * (jnd_budget_result_free). Bad input — a budget below 0, an asset without
 * maps or without triangles, a budget no candidate meets (the message
 * names the smallest memory and triangles possible) — is one error "FILE:
 * problem", JND_ERR_ARG, nothing written. */
jnd_status jnd_budget_run(const char *model, const jnd_budget_params *p, const char *out_dir,
                          jnd_budget_result **out);

/* Frees what jnd_budget_run returned (NULL is fine). */
void jnd_budget_result_free(jnd_budget_result *r);

/* The search alone (writes nothing): the chain and its analysis, the
 * candidates, the choice and the levels' verification. out is the
 * caller's (jnd_budget_result_clear). */
JND_EXPERIMENTAL jnd_status jnd_budget_search(const char *model, const jnd_budget_params *p, jnd_budget_result *out);

/* Frees a result's arrays; safe on a zeroed struct. */
void jnd_budget_result_clear(jnd_budget_result *r);

/* pareto.png: memory against statistic of every candidate, the Pareto
 * front, the choice and the separately chosen marked. out is allocated (3
 * channels, sRGB 0..1). */
JND_EXPERIMENTAL jnd_status jnd_budget_pareto_plot(const jnd_budget_result *r, const jnd_criterion *c, jnd_image *out);

/* ------------------------------------------------------------------------ */
/* Popping (Schwarz & Stamminger 2009, 004 §3.2, §4, §5.2)                  */
/* ------------------------------------------------------------------------ */
/* Will a level switch pop? The frame where the switch happens is given
 * twice: rendered with the new level (the actual frame) and with the
 * previous one (what the viewer expects). Both go through the vision model
 * with each pixel's retinal velocity; the difference map, scaled down by
 * optional weights (disocclusion, flicker, the caller's), is aggregated
 * into popping regions — seeds where the colours differ and the map is at
 * least 2 JND, grown over the eight neighbours while at least 2 JND — each
 * with its Minkowski sum Σ and rating R = ln(0.375 Σ) / ln 2.25 (R < 1:
 * rarely visible, R > 3: easily). Coverage, rating and detection scores
 * summarise a frame (004 §5.2). See docs/pop.md. Typical use:
 *
 *     jnd_pop_inputs in = {0};
 *     in.actual.color = &new_cdm2;   in.actual.displacement = &motion;
 *     in.expected.color = &old_cdm2; in.expected.displacement = &motion;
 *     jnd_pop_params pp;  jnd_pop_defaults(&pp);
 *     jnd_pop_result r;
 *     if (jnd_pop_predict(model, &in, &pp, &r) == JND_OK)
 *         printf("%d regions, max R %.2f, detection score %d\n", r.nregions, r.max_rating, r.detection_score);
 *     jnd_pop_result_free(&r);
 */

/* One of the two frames. Every image is w × h, the colour's size. */
typedef struct {
  const jnd_image *color;        /* 3 channels: absolute linear RGB, cd/m² (jnd_display_apply) */
  const jnd_image *displacement; /* 2 channels (more are ignored): screen position in this frame
                                    minus position in the previous frame, pixels (x right, y
                                    down), as the renderer's motion output; NULL: static */
  const jnd_image *depth;        /* 1 channel: depth (distance along the view axis) of each
                                    pixel's surface point as the previous frame's camera saw it;
                                    this frame's own depth approximates it when motion along the
                                    view axis is small against depth_tolerance. 0: nothing there
                                    (infinitely far). NULL: no disocclusion weight */
  const jnd_image *prev_depth;   /* 1 channel: the previous frame's depth map, rendered with this
                                    frame's level (needed with depth) */
} jnd_pop_frame;

typedef struct {
  jnd_pop_frame actual;          /* the frame with the new level (004: "actually rendered") */
  jnd_pop_frame expected;        /* the same frame with the previous level (004: "predicted") */
  const jnd_image *weights;      /* 1 channel, 0..1: multiplies the difference map (004 §3.2); NULL */
  const jnd_image *prev_color;   /* flicker (004 §4): the previous frame as shown, 3 channels cd/m² */
  const jnd_image *prev_shading; /* flicker: the expected frame's pixels shaded with the previous
                                    frame's camera and lights, 3 channels cd/m² (with prev_color) */
  const jnd_image *mask;         /* 1 channel: > 0.5 on the object, the pixels coverage counts;
                                    NULL: the whole frame */
} jnd_pop_inputs;

typedef struct {
  double threshold_jnd;          /* seeds and growth: at least this many JND (2, 004 §3.2) */
  double minkowski;              /* exponent of a region's sum Σ (2.4, 004 §3.2) */
  double depth_tolerance;        /* disocclusion: a point counts as seen in the previous frame when
                                    its depth is at most (1 + this) × the previous depth (0.01) */
  double flicker_ratio_lo;       /* flicker: ΔE*94(previous shading, previous frame) / ΔE*94(levels)
                                    from which a pixel starts to count as flickering (0.5) */
  double flicker_ratio_hi;       /* ... and counts fully (1: "roughly as large", 004 §4) */
  double flicker_motion_lo_px;   /* displacement (pixels/frame) from which the flicker test is
                                    trusted less (2) ... */
  double flicker_motion_hi_px;   /* ... and not at all ("unless the displacement is large", 4) */
  int top_regions;               /* the rating score is the mean R of this many best regions (3) */
  double coverage_small;         /* coverage fraction from which the score is "small" (0.01), */
  double coverage_large;         /* "large" (0.05) */
  double coverage_huge;          /* and "huge" (0.25) */
  double rating_low;             /* mean R from which the rating score is "low" (1), */
  double rating_high;            /* "high" (2) */
  double rating_very_high;       /* and "very high" (3) */
  int picture;                   /* 1: make result.picture (004 Fig. 4); default 1 */
  int threads;                   /* 0: OpenMP's default; results do not depend on it */
} jnd_pop_params;

/* Fills p with the defaults above (docs/pop.md says why each). */
JND_EXPERIMENTAL void jnd_pop_defaults(jnd_pop_params *p);

typedef enum { JND_COVERAGE_TINY = 0, JND_COVERAGE_SMALL, JND_COVERAGE_LARGE, JND_COVERAGE_HUGE } jnd_pop_coverage;
typedef enum { JND_RATING_VERY_LOW = 0, JND_RATING_LOW, JND_RATING_HIGH, JND_RATING_VERY_HIGH } jnd_pop_rating;

/* One popping region. */
typedef struct {
  size_t pixels;
  double sigma;                  /* Minkowski sum (exponent 2.4) of its JND values */
  double rating;                 /* R = ln(0.375 Σ) / ln 2.25 */
  double jnd_max;                /* its largest JND */
  int bbox[4];                   /* x0, y0, x1, y1, inclusive, pixels */
  int first[2];                  /* its first pixel in raster order (x, y) */
} jnd_pop_region;

/* What a weight did: present when it was given or computed. */
typedef struct {
  int present;
  double mean;                   /* over the frame */
  double min;
  size_t below_half;             /* pixels weighted below 0.5 */
} jnd_pop_weight_stats;

typedef struct {
  int w, h;
  int nregions;
  jnd_pop_region *regions;       /* sorted by rating, highest first (ties: first pixel); owned */
  int32_t *labels;               /* w × h: index into regions, −1 outside every region; owned */
  jnd_image jnd;                 /* the weighted difference map, JND, 1 channel */
  jnd_image weights;             /* the combined weight map (1 channel); empty without weights */
  double jnd_max;                /* largest value of jnd */
  double max_rating;             /* largest R; NaN without regions */
  size_t object_pixels;          /* the pixels coverage counts (mask, or all) */
  size_t covered_pixels;         /* of those, the pixels in regions */
  double coverage;               /* covered / object pixels */
  jnd_pop_coverage coverage_score;
  double rating_top;             /* mean R of the top_regions best regions; NaN without regions */
  jnd_pop_rating rating_score;
  int detection_score;           /* 1..5, jnd_pop_detection_score */
  double max_delta_e94;          /* 004 §5.1's baseline: the largest ΔE*94 between the two frames */
  jnd_pop_weight_stats disocclusion, flicker, user;
  jnd_image picture;             /* params.picture: the actual frame in grey with the regions
                                    coloured by R and a legend, sRGB 0..1 (jnd_image_write_png) */
  struct {                       /* wall-clock seconds of the steps (they differ run to run): */
    double read_s;               /* reading and checking files (jnd_pop_files), the display */
    double weights_s;            /* seeds, ΔE*94 and the weights */
    double model_s, regions_s, picture_s;
  } timings;
} jnd_pop_result;

/* The predictor on two frames (004 §3.2, §4, §5.2): checks the inputs (sizes,
 * channels; weights and masks in 0..1, depths >= 0, finite), computes the
 * disocclusion and flicker weights where their inputs are given, the JND
 * map of expected (reference) against actual (test) with each frame's
 * retinal velocity and the weights, the regions, their ratings and the
 * scores. The model supplies the display and fps. out is filled (owned:
 * jnd_pop_result_free). JND_ERR_ARG "INPUT: problem" for bad inputs. The
 * same bits whatever the thread count. */
JND_EXPERIMENTAL jnd_status jnd_pop_predict(jnd_model *m, const jnd_pop_inputs *in, const jnd_pop_params *p, jnd_pop_result *out);

/* Frees a result's arrays and images; safe on a zeroed struct. */
JND_EXPERIMENTAL void jnd_pop_result_free(jnd_pop_result *r);

/* The frames of a user: files for jnd_pop_predict's inputs. Colour images
 * (actual, expected, prev_color, prev_shading) are PNG/JPEG/HDR/EXR and go
 * through the model's display; displacement and depth maps must be
 * OpenEXR (float values: pixels, depth units); weights and mask may be any
 * format (first channel, 0..1). NULL: not given. */
typedef struct {
  const char *actual, *expected;             /* required */
  const char *displacement;                  /* the actual frame's; also the expected frame's
                                                unless displacement_expected is given */
  const char *displacement_expected;
  const char *depth, *depth_expected;        /* jnd_pop_frame.depth of each frame */
  const char *prev_depth, *prev_depth_expected; /* jnd_pop_frame.prev_depth of each frame */
  const char *weights, *prev_color, *prev_shading, *mask;
} jnd_pop_paths;

/* Reads the files (in parallel), checks them — "PATH: problem" for a file
 * that is unreadable, of another size than actual, with NaN, a weight
 * outside 0..1, ... (JND_ERR_IO / JND_ERR_FORMAT / JND_ERR_ARG) — applies
 * the display and runs jnd_pop_predict. */
JND_EXPERIMENTAL jnd_status jnd_pop_files(jnd_model *m, const jnd_pop_paths *paths, const jnd_pop_params *p, jnd_pop_result *out);

/* A sequence of frames (docs/pop.md, "Sequences"): the paths of a
 * jnd_pop_paths hold a frame-number field, %d or %0Nd (%% for a %), that
 * each frame's number fills in, e.g. "new_%04d.png" → new_0007.png for
 * frame 7; a path without a field (a mask) serves every frame. NEW and
 * EXPECTED must have one. */
#define JND_POP_MAX_FRAMES 100000
typedef struct {
  int first, last;               /* frame numbers, inclusive, 0 <= first <= last */
  void (*progress)(void *user, const char *stage, int done, int total); /* per frame; NULL */
  void *progress_user;
} jnd_pop_sequence_params;

/* Fills p with the defaults: frame 0 only, no progress. */
JND_EXPERIMENTAL void jnd_pop_sequence_defaults(jnd_pop_sequence_params *p);

/* One frame's row of the table. */
typedef struct {
  int frame;                     /* its number */
  int nregions;
  double max_rating;             /* NaN without regions */
  double rating_top;             /* NaN without regions */
  double coverage;
  jnd_pop_coverage coverage_score;
  jnd_pop_rating rating_score;
  int detection_score;
  double max_delta_e94;
  double jnd_max;
} jnd_pop_frame_row;

typedef struct {
  jnd_pop_frame_row *rows;       /* one per frame, in frame order; owned */
  int nrows;
  int worst;                     /* index into rows of the worst frame: the highest max R (a frame with
                                    regions before one without), then the higher detection score,
                                    then the earlier frame */
  jnd_pop_result worst_result;   /* that frame's whole result (regions, labels, maps, picture) */
} jnd_pop_sequence_result;

/* jnd_pop_files on every frame first..last of the patterns, in order (the
 * same bits whatever the thread count). A missing or bad file, or a frame
 * of another size than the first: JND_ERR_IO / FORMAT / ARG "PATH: problem",
 * and out is empty. A pattern with a % other than one %d / %0Nd field and
 * %%: JND_ERR_ARG. out is the caller's (jnd_pop_sequence_free). */
JND_EXPERIMENTAL jnd_status jnd_pop_sequence(jnd_model *m, const jnd_pop_paths *patterns, const jnd_pop_sequence_params *sp,
                            const jnd_pop_params *p, jnd_pop_sequence_result *out);

/* Frees a sequence result; safe on a zeroed struct. */
JND_EXPERIMENTAL void jnd_pop_sequence_free(jnd_pop_sequence_result *r);

/* Writes pattern with its frame-number field (%d or %0Nd) filled in with
 * frame (>= 0) and %% as %, into out (size bytes). Returns 1 when the
 * pattern had a field, 0 when it had none (out is the pattern, %% as %),
 * −1 for a malformed pattern, a negative frame or too small a buffer. */
JND_EXPERIMENTAL int jnd_frame_path(const char *pattern, int frame, char *out, size_t size);

/* R = ln(0.375 Σ) / ln 2.25 (004 §3.2). */
JND_EXPERIMENTAL double jnd_pop_rating_of(double sigma);

/* The score levels of a coverage fraction and of a mean R under p's thresholds. */
JND_EXPERIMENTAL jnd_pop_coverage jnd_pop_coverage_level(const jnd_pop_params *p, double coverage);
JND_EXPERIMENTAL jnd_pop_rating jnd_pop_rating_level(const jnd_pop_params *p, double rating_top);

/* The detection score 1..5 of 004 §5.2's rule table, completed
 * monotonically (docs/pop.md): non-decreasing in both scores, with 004's
 * examples tiny + low → 1, small + high → 3, huge + high → 5. */
JND_EXPERIMENTAL int jnd_pop_detection_score(jnd_pop_coverage c, jnd_pop_rating r);

/* "tiny", "small", "large", "huge" and "very low", "low", "high", "very high". */
JND_EXPERIMENTAL const char *jnd_pop_coverage_name(jnd_pop_coverage c);
JND_EXPERIMENTAL const char *jnd_pop_rating_name(jnd_pop_rating r);

/* ---- Popping of rendered switches: frames from assets, switch decisions ---- */
/* jnd renders the switching frame itself: the scene's level `level` (what
 * the viewer expects) and level + 1 (the new one) at the same frame of a
 * motion, with motion vectors and depth for this and the previous frame,
 * and runs jnd_pop_predict on them. The switch decisions bisect over the
 * camera distance for the nearest distance at which every view's largest R
 * stays below 1 (docs/pop.md). Typical use (what `jnd lod` can call):
 *
 *     jnd_pop_motion mo;  jnd_pop_motion_defaults(&mo);  mo.speed = 30;  // orbit 30 °/s
 *     jnd_pop_switch_params sp;  jnd_pop_switch_defaults(&sp);
 *     jnd_pop_switch sw;
 *     jnd_pop_switch_distance(model, renderer, scene, views, nviews, &mo, k, &pp, &sp, &sw);
 *     // level k may replace level k − 1 from sw.distance (object units) on
 */

/* How the camera or the object moves (frames at the model's fps). */
typedef enum {
  JND_POP_ORBIT = 0,       /* the camera circles the view's target about +Y; speed in °/s
                              (positive: counter-clockwise seen from above) */
  JND_POP_TRANSLATE,       /* the camera (eye and target) travels along direction; speed in m/s */
  JND_POP_OBJECT,          /* the object spins about +Y through the view's target; speed in °/s */
  JND_POP_PAN              /* the camera turns in place about +Y through its eye; speed in °/s
                              (every point sweeps the screen at about that rate, at any distance) */
} jnd_pop_motion_kind;

typedef struct {
  jnd_pop_motion_kind kind;
  double speed;            /* °/s (ORBIT, OBJECT) or m/s (TRANSLATE); 0: static (default) */
  double direction[3];     /* TRANSLATE: direction of travel in the camera's frame (x right, y up,
                              z towards the viewer); default 1, 0, 0 (to the right) */
  double unit_m;           /* metres per object unit (1: glTF's metres) */
} jnd_pop_motion;

/* Orbit, 0 °/s, direction +x, 1 m per unit. */
JND_EXPERIMENTAL void jnd_pop_motion_defaults(jnd_pop_motion *m);

/* The view at time t seconds along the motion that starts at view (t = 0):
 * camera (and model matrix for JND_POP_OBJECT) moved; the rest copied. */
JND_EXPERIMENTAL void jnd_pop_motion_pose(const jnd_view *view, const jnd_pop_motion *m, double t, jnd_view *out);

/* Renders the switch from level to level + 1 of scene (0 <= level, level + 1
 * < jnd_scene_lod_count) at frame `frame` of the motion starting at view
 * (frame f is at time f / fps, the model's fps; the previous frame one
 * frame earlier): actual = level + 1, expected = level, both with the
 * renderer's motion vectors and depth; the previous frame's depth of both
 * levels and each pixel's depth as the previous camera saw it give the
 * disocclusion weight (004 §4; none when nothing moves); the mask is the
 * pixels either level covers. Colours go through the model's display as
 * the judge shows them (sRGB signal, then cd/m²). Then jnd_pop_predict. The
 * scene's selected level is restored. out as jnd_pop_predict's. */
JND_EXPERIMENTAL jnd_status jnd_pop_render(jnd_model *m, jnd_renderer *r, jnd_scene *scene, const jnd_view *view,
                          const jnd_pop_motion *mo, int level, int frame, const jnd_pop_params *p,
                          jnd_pop_result *out);

/* How a switch distance is searched. */
typedef struct {
  double rating_limit;     /* the largest R must stay below this (1: "rarely visible", 004 §3.2) */
  double tolerance;        /* relative: the distances searched are near × (1 + tolerance)^i up to
                              far (0.05) */
  double coverage_near;    /* the nearest distance searched: the bounding sphere (jnd_scene_subject_bounds)
                              fills this fraction of the image height (1) */
  double coverage_far;     /* the farthest (0.02) */
  int frame;               /* the switch frame along the motion (0: at the views' poses) */
  double start;            /* a distance where the answer is likely (another speed's or level's
                              answer): the search starts there and widens its bracket outwards;
                              0: none, a bisection of the whole range */
  int whole_frame;         /* 1: every distance rendered whole; 0 (default): where the object stays
                              centred, only its window of the frame (docs/pop.md "Switch decisions"),
                              R equal to the whole frame's to about 1e-4 */
} jnd_pop_switch_params;

/* Fills p with the defaults above. */
JND_EXPERIMENTAL void jnd_pop_switch_defaults(jnd_pop_switch_params *p);

typedef enum {
  JND_POP_SWITCH_FOUND = 0, /* popping-free from distance on, popping nearer (within tolerance) */
  JND_POP_SWITCH_NEAREST,   /* popping-free already at the nearest distance searched */
  JND_POP_SWITCH_NONE       /* pops even at the farthest: distance is +inf (never switch) */
} jnd_pop_switch_status;

typedef struct {
  jnd_pop_switch_status status;
  double distance;         /* camera distance from the views' target, object units (+inf: NONE) */
  double distance_popping; /* FOUND: the nearer end of the last bracket, where max R >= the limit
                              was measured (distance / distance_popping <= 1 + tolerance); NaN else */
  double max_rating;       /* the largest R over the views at distance (−inf: no region; at the
                              farthest distance for NONE) */
  double distance_pixel_rule; /* where level's geometric error covers one pixel at the image's
                              height (docs/lod.md's meshoptimizer rule): error_abs, or for levels
                              read from a file the largest distance of 16384 points of level 0's
                              surface from the level's (jnd_scene_lod_distance); NaN when it is 0 */
  int evaluations;         /* distances rendered and predicted */
} jnd_pop_switch;

/* The popping-free switch distance of level (>= 1: the distance from which
 * level replaces level − 1) for the motion mo: the views give the camera's
 * directions and images (their distances are replaced: eye = target +
 * d × the unit direction from target to eye); at distance d each view's
 * switch is rendered (jnd_pop_render) and the largest R over the views
 * (views after one at or above the limit are skipped; the view that failed
 * last is asked first) compared with sp->rating_limit. The distances are a
 * geometric grid from the near to the far distance (ratio 1 + tolerance);
 * assuming popping fades with distance, the answer is the nearest grid
 * distance where max R < limit was measured with max R >= limit measured at
 * the grid distance before it — by bisection of the grid, or from sp->start
 * outwards (doubling steps, then bisection): the same answer wherever the
 * assumption holds. Deterministic. */
JND_EXPERIMENTAL jnd_status jnd_pop_switch_distance(jnd_model *m, jnd_renderer *r, jnd_scene *scene, const jnd_view *views,
                                   int nviews, const jnd_pop_motion *mo, int level, const jnd_pop_params *p,
                                   const jnd_pop_switch_params *sp, jnd_pop_switch *out);

/* `jnd pop MODEL` as one call: the asset and its chain, one switch rendered
 * and predicted (view 0), and optionally the switch table over levels and
 * speeds with its picture. */
typedef struct {
  jnd_view_set views;      /* the views (jnd_view_set_defaults; image size, sampling, renderer) */
  const char *cameras;     /* a cameras file (jnd_views_read) instead of sampled views; NULL */
  int builtin_map_size;    /* map side of MODEL "builtin" / "builtin:sphere" (512) */
  jnd_lod_params chain;    /* the chain made when the file has no MSFT_lod levels (or rebuild) */
  int rebuild;             /* 1: make a chain even when the file has levels */
  const char *const *level_paths; /* levels from other files, finest first (instead of a chain) */
  int nlevel_paths;
  jnd_pop_motion motion;   /* the pair's motion */
  int level;               /* the pair: switch from level to level + 1 (0) */
  int frame;               /* the pair's switch frame (0) */
  jnd_pop_params pop;
  int decide;              /* 1: the switch table */
  const double *speeds;    /* its speeds in °/s (motion.kind ORBIT, OBJECT or PAN); NULL: 0, 30, 120 */
  int nspeeds;
  jnd_pop_switch_params search;
  void (*progress)(void *user, const char *stage, int done, int total);
  void *progress_user;
} jnd_pop_asset_params;

/* Fills p with the defaults above. */
JND_EXPERIMENTAL void jnd_pop_asset_defaults(jnd_pop_asset_params *p);

typedef struct {
  int level;               /* the level that takes over (>= 1) */
  double speed_dps;
  jnd_pop_switch sw;       /* distances in object units */
  double distance_m, distance_m_pixel_rule; /* × motion.unit_m */
} jnd_pop_switch_row;

typedef struct {
  jnd_pop_result pair;     /* the rendered switch's prediction */
  const char *chain_source; /* "file", "made" or "levels" */
  int nlevels;
  jnd_lod_level_info levels[64];
  int nviews;
  double pair_distance;    /* the pair's camera distance, object units */
  jnd_pop_switch_row *rows; /* decide: levels 1.. × speeds, level-major; owned */
  int nrows;
  jnd_image plot;          /* decide: distance per level, one line per speed (sRGB 0..1) */
  const char *distance_unit; /* the unit of the rows' distance_m: "m" for glTF (metres by its
                              specification) or a motion.unit_m other than 1, else "object units"
                              (OBJ and the built-in assets carry no unit) */
  char renderer[256];
  double load_s, render_s, decide_s;
} jnd_pop_asset_report;

/* Loads model_path (glTF/GLB/OBJ, "builtin", "builtin:sphere"), gets its
 * chain (the file's MSFT_lod levels, level files, or one made), renders and
 * predicts the pair and, with p->decide, the switch table. Nothing is
 * written. JND_ERR_ARG/FORMAT/IO "FILE: problem" for bad input; out is the
 * caller's (jnd_pop_asset_report_free). */
JND_EXPERIMENTAL jnd_status jnd_pop_asset_run(jnd_model *m, const char *model_path, const jnd_pop_asset_params *p,
                             jnd_pop_asset_report *out);

/* Frees a report; safe on a zeroed struct. */
JND_EXPERIMENTAL void jnd_pop_asset_report_free(jnd_pop_asset_report *r);

/* `jnd pop` as one call (the task shape, docs/architecture.md), in either
 * form: input a model (glTF/GLB/OBJ, builtin[:...]): the asset form
 * (jnd_pop_asset_run with p->asset); input NULL: the frames of p->frames
 * (jnd_pop_files), or with p->sequence every frame of the patterns
 * (jnd_pop_sequence). Writes into out_dir, through one output writer
 * (nothing over an input; all or nothing): regions.png, pop.json (the
 * report), with p->maps jnd.exr and weights.exr, a sequence's frames.csv,
 * the switch table's switch.png. */
typedef struct {
  jnd_model_params model;    /* the display, fps and threads (jnd_model_defaults) */
  jnd_pop_params pop;        /* thresholds and scores (jnd_pop_defaults) */
  jnd_pop_paths frames;      /* frame form: NEW (actual), EXPECTED and their maps */
  int sequence;              /* frame form: 1: the paths are patterns of frames seq.first..seq.last */
  jnd_pop_sequence_params seq;
  jnd_pop_asset_params asset; /* asset form (jnd_pop_asset_defaults; its pop is set from pop) */
  int maps;                  /* 1: also jnd.exr (the weighted JND map) and weights.exr */
  int max_regions;           /* regions listed in the report, best first (100; all are counted) */
  double fail_above;         /* report whether the largest rating exceeds this (NaN: not asked) */
  /* NULL or called at each stage (and step of the switch table or a sequence) */
  void (*progress)(void *user, const char *stage, int done, int total);
  void *progress_user;
  jnd_run_options run;       /* the report's copy, timings (map_size: see asset.builtin_map_size) */
} jnd_pop_run_params;

/* Fills p with the defaults above. */
void jnd_pop_run_defaults(jnd_pop_run_params *p);

typedef struct {
  const jnd_pop_result *pair; /* the prediction reported: the pair's, or a sequence's worst frame's
                                 (points into one of the three below) */
  jnd_pop_result frame;      /* frame form, one pair */
  jnd_pop_sequence_result sequence; /* frame form, a sequence */
  jnd_pop_asset_report asset; /* asset form */
  int above;                 /* a region's rating exceeds fail_above (when asked) */
  double total_s;            /* wall-clock seconds */
  char *report;              /* the report's JSON text */
} jnd_pop_run_result;

/* The task (`jnd pop`). *out is allocated (jnd_pop_run_result_free). Bad
 * input: one error "FILE: problem", nothing written. */
jnd_status jnd_pop_run(const char *model, const jnd_pop_run_params *p, const char *out_dir,
                       jnd_pop_run_result **out);

/* Frees what jnd_pop_run returned (NULL is fine). */
void jnd_pop_run_result_free(jnd_pop_run_result *r);

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
JND_EXPERIMENTAL jnd_status jnd_batch_manifest_parse_csv(const char *name, const char *text, size_t n, jnd_batch_manifest *out);
JND_EXPERIMENTAL jnd_status jnd_batch_manifest_parse_json(const char *name, const char *text, size_t n, jnd_batch_manifest *out);
/* Marks rows whose asset file is missing (relative to m->base_dir). */
JND_EXPERIMENTAL void jnd_batch_manifest_check(jnd_batch_manifest *m);
/* Frees every row and string and zeroes m; safe on a zeroed manifest. */
void jnd_batch_manifest_free(jnd_batch_manifest *m);

/* Parses a shard "I/N" (0 <= I < N <= 100000). JND_ERR_ARG with a message. */
JND_EXPERIMENTAL jnd_status jnd_batch_shard_parse(const char *spec, int *index, int *count);

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

/* The report of a run (`jnd batch --json`): the envelope with the manifest,
 * the shard, jobs, timeout and force, and the totals. Returns the JSON text
 * (ending in a newline; the caller frees it with free()), NULL when out of
 * memory. */
JND_EXPERIMENTAL char *jnd_batch_run_report(const jnd_batch_manifest *m, const jnd_batch_params *p, const jnd_batch_totals *t);

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
JND_EXPERIMENTAL void jnd_slurm_defaults(jnd_slurm_params *p);

/* The two job scripts, as text (caller frees): array_script runs `JND batch
 * SOURCE -o OUT --shard $SLURM_ARRAY_TASK_ID/N` (with run's jobs, threads,
 * timeout, force, and command/options for a glob) and merge_script runs `JND
 * batch merge OUT` and `JND report OUT`. Paths are made absolute. run->jnd_exe
 * is the program the nodes run. */
JND_EXPERIMENTAL jnd_status jnd_slurm_scripts(const jnd_batch_manifest *m, const char *glob_command, const char *glob_options,
                             const jnd_batch_params *run, const jnd_slurm_params *sp, char **array_script,
                             char **merge_script);

/* Writes the scripts to OUT/_batch/slurm/{array,merge}.sh and submits them:
 * `sbatch --parsable array.sh`, then `sbatch --parsable
 * --dependency=afterok:ARRAY merge.sh`. The job ids are returned (n bytes
 * each). sbatch comes from PATH. */
JND_EXPERIMENTAL jnd_status jnd_slurm_submit(const char *out_dir, const char *array_script, const char *merge_script,
                            char *array_job, char *merge_job, size_t n);

/* ------------------------------------------------------------------------ */
/* Gaze-contingent level of detail (002)                                    */
/* ------------------------------------------------------------------------ */
/* Surace et al.'s (002) two models, as jnd implements them (docs/gaze.md
 * writes every equation down): the spatial model predicts whether level i
 * of a chain is noticed beside level 0 when the object is seen at an
 * eccentricity (silhouette XOR weighted by eccentricity + a shading term
 * from jnd's vision model); the temporal model whether the switch between
 * consecutive levels is noticed. Probabilities are 2AFC proportions
 * correct: 0.5 is chance, 0.75 the midpoint 002 thresholds at. The table
 * L(distance, eccentricity) keeps the coarsest level below the threshold;
 * an engine looks it up per object per frame (jnd_gaze_lookup_level):
 *
 *     jnd_gaze_lookup lut;  jnd_gaze_lookup_load("out/gaze.csv", &lut);   // once
 *     int level = (int)jnd_gaze_lookup_level(&lut, dist_m, ecc_deg, JND_GAZE_FLOOR);
 *     jnd_gaze_lookup_free(&lut);
 */

/* The free parameters of 002's models (docs/gaze.md for the defaults and
 * where they come from). */
typedef struct {
  /* spatial model: w(e) = alpha · softplus_beta(s − e) + b (002 eq. 2), weights of the
     silhouette XOR's pixels at eccentricity e degrees */
  double alpha;        /* slope of the linear part, per degree of eccentricity */
  double beta;         /* sharpness of the softplus's knee, per degree */
  double s_deg;        /* eccentricity of the knee, degrees */
  double b;            /* the floor far in the periphery */
  /* D = ((w_g G)^k_s + (w_vdp V)^k_s)^(1/k_s) (002 eq. 3), P = ½ + ½ / (1 + D^−gamma) (eq. 4) */
  double w_g;          /* weight of the geometric term G (degrees) */
  double w_vdp;        /* weight of the shading term V (JND) */
  double k_s;          /* summation exponent of the two terms (1: they add; large: the larger decides) */
  double gamma;        /* slope of the sigmoid in log D */
  /* temporal model: P_switch = ½ + ½ / (1 + (w_t T)^−gamma_t) (002 eq. 5) */
  double w_t;          /* weight of the switch's pooled JND T */
  double gamma_t;      /* slope */
} jnd_gaze_model;

/* Fills m with jnd's defaults (docs/gaze.md "Defaults"). */
JND_EXPERIMENTAL void jnd_gaze_model_defaults(jnd_gaze_model *m);

/* 002 eq. 2: the weight of a silhouette pixel at eccentricity ecc_deg. */
JND_EXPERIMENTAL double jnd_gaze_weight(const jnd_gaze_model *m, double ecc_deg);

/* 002 eqs. 3–4: the probability (2AFC, 0.5..1) that a level whose
 * geometric term is g_deg (eq. 1, degrees) and shading term v_jnd (pooled
 * JND) is told from the reference. */
JND_EXPERIMENTAL double jnd_gaze_spatial_probability(const jnd_gaze_model *m, double g_deg, double v_jnd);

/* 002 eq. 5: the probability (0.5..1) that a switch whose pooled JND is
 * t_jnd is seen. */
JND_EXPERIMENTAL double jnd_gaze_switch_probability(const jnd_gaze_model *m, double t_jnd);

/* 002 eq. 1: Σ over pixels of S0 XOR Si of w(ecc_p) · A_p, over the
 * perimeter of S0. mask0, mask_i: coverage (1 channel, 0..1, same size);
 * ppd: pixels per degree (A_p = 1/ppd² deg²); (gaze_x, gaze_y): the
 * fixation point, pixels (may lie outside). *g_deg in degrees; 0 when S0
 * is empty. JND_ERR_ARG for mismatched masks. */
JND_EXPERIMENTAL jnd_status jnd_gaze_geometric_term(const jnd_gaze_model *m, const jnd_image *mask0, const jnd_image *mask_i,
                                   double ppd, double gaze_x, double gaze_y, double *g_deg);

/* What one stimulus (a level against the reference, a switch between two
 * levels) measures, at one fixation point. */
typedef struct {
  double g_deg;        /* eq. 1 (spatial) */
  double v_jnd;        /* shading term: pooled JND with the XOR region grey in both images */
  double t_jnd;        /* temporal term: pooled JND of the switch, nothing greyed */
  double p;            /* the model's probability */
} jnd_gaze_terms;

/* How renderings become terms. */
typedef struct {
  jnd_model_params model;   /* display and model (display.ppd is the rendering's, set per call) */
  jnd_pooling pool;         /* over the object's pixels (S0 ∪ Si): p93 */
  double background;        /* linear grey behind the object and in the XOR region (0.18) */
  double switch_hz;         /* the temporal frequency a level switch (a one-frame step) is judged
                               at, Hz (jnd_diff_inputs.temporal_hz; 3: docs/gaze.md "The temporal
                               model"); capped below half the display's refresh, model.fps */
  jnd_pair_judge *judge;    /* the pairs' judge, made from this model (jnd_pair_judge_create) and
                               kept for a run; NULL (default): one is made for each call */
} jnd_gaze_measure_params;
JND_EXPERIMENTAL void jnd_gaze_measure_defaults(jnd_gaze_measure_params *p);

/* The spatial model on two renderings: ref and lvl are linear RGB over a
 * black background (3 channels, as jnd_render gives), mask0 and mask_i
 * their coverage; ppd of the rendering; fixation point (gaze_x, gaze_y)
 * in pixels. Fills g_deg, v_jnd and p. */
JND_EXPERIMENTAL jnd_status jnd_gaze_spatial(const jnd_gaze_model *gm, const jnd_gaze_measure_params *mp, double ppd,
                            double gaze_x, double gaze_y, const jnd_image *ref, const jnd_image *mask0,
                            const jnd_image *lvl, const jnd_image *mask_i, jnd_gaze_terms *out);

/* The temporal model on the renderings of two consecutive levels a → b
 * (as jnd_gaze_spatial takes them): the change seen as a temporal
 * modulation at mp->switch_hz through the vision model's flicker
 * sensitivity, at each pixel's eccentricity. Fills t_jnd and p. */
JND_EXPERIMENTAL jnd_status jnd_gaze_switch(const jnd_gaze_model *gm, const jnd_gaze_measure_params *mp, double ppd,
                           double gaze_x, double gaze_y, const jnd_image *a, const jnd_image *mask_a,
                           const jnd_image *b, const jnd_image *mask_b, jnd_gaze_terms *out);

/* The table L(d, ecc) (002 eqs. 9–10). */
typedef struct {
  const double *distances_m;     /* ascending, > the object's bounding radius (metres = object units);
                                    NULL: 8 distances, 4 to 96 bounding radii, about evenly in log */
  int ndistances;
  const double *eccentricities_deg; /* ascending, 0..90; NULL: 0, 5, 10, 15, 20, 30, 40, 60 */
  int neccentricities;
  const jnd_lod_params *chain;   /* a scene with one level gets a chain made with these (NULL: error
                                    targets 1/1024, 1/256, 1/64: 4 levels at most) */
  int build_chain;               /* 1 (default): make that chain; 0: a scene of one level is refused */
  int orientations;              /* object orientations sampled per distance (8); the worst decides */
  uint64_t seed;                 /* of the orientations and lights (1) */
  double threshold;              /* both probabilities below it (0.75, 002) */
  int min_px, max_px;            /* rendering side in pixels: the object's window at the display's
                                    ppd, within [min_px, max_px] (64, 192) */
  int near_window;               /* 1 (default): where the whole object would need more than max_px,
                                    judge a window of max_px at the display's ppd around the
                                    silhouette facing the gaze; 0: the whole object at reduced ppd */
  jnd_gaze_model model;
  jnd_gaze_measure_params measure;
  jnd_renderer_params render;    /* env, samples, platform (its size is set per distance) */
  void (*progress)(void *user, int done, int total);
  void *progress_user;
} jnd_gaze_table_params;
JND_EXPERIMENTAL void jnd_gaze_table_defaults(jnd_gaze_table_params *p);

typedef struct {
  int nd, ne, nlevels, orientations;
  double *distances_m, *eccentricities_deg;   /* nd, ne */
  int *level;          /* nd × ne: the level an engine uses — the coarsest below the threshold,
                          made monotone (never finer as distance or eccentricity grows) */
  int *level_raw;      /* nd × ne: before the monotone step */
  double *p_spatial;   /* nd × ne × nlevels: worst orientation's spatial P of each level (0.5 at 0) */
  double *p_switch;    /* nd × ne × nlevels: worst switch P from level k − 1 to k (0.5 at 0) */
  double *ppd;         /* nd: pixels per degree of the renderings at each distance */
  int *side_px;        /* nd */
  int *windowed;       /* nd: 1 where a near object was judged on a window (near_window) */
  size_t *triangles;   /* nlevels */
  int renderings;
  char renderer[160];
} jnd_gaze_table;

/* Computes the table for the scene's chain (at least 2 levels): per
 * distance and orientation every level is rendered once (the object's
 * bounding sphere framed in a window at the display's ppd; a near object
 * that would need more than max_px, on max_px windows at the display's ppd
 * around the fixation point or the silhouette facing it: near_window); per
 * eccentricity (fixation point that many degrees left of the object's
 * centre) each level's spatial P and each switch's P are judged; the
 * worst orientation decides. JND_ERR_ARG "--distances/--eccentricities:
 * ..." for bad lists, "MODEL: ..." for a chain of one level. */
JND_EXPERIMENTAL jnd_status jnd_gaze_table_run(jnd_scene *scene, const jnd_gaze_table_params *p, jnd_gaze_table *out);
JND_EXPERIMENTAL void jnd_gaze_table_free(jnd_gaze_table *t);

/* The table's CSV (what jnd_gaze_lookup_load reads): one row per (distance,
 * eccentricity): distance_m, eccentricity_deg, level, level_raw,
 * p_spatial, p_switch (of the chosen level). Atomic. */
JND_EXPERIMENTAL jnd_status jnd_gaze_table_write_csv(const jnd_gaze_table *t, const char *path);

/* The picture of the table: the level over distance × eccentricity,
 * labelled (jnd_plot_grid): the title gives the threshold both probabilities
 * are below, the distance axis the asset's length unit (jnd_asset_length_unit).
 * out is allocated, 3 channels sRGB 0..1. */
JND_EXPERIMENTAL jnd_status jnd_gaze_table_figure(const jnd_gaze_table *t, double threshold, const char *length_unit,
                                                    jnd_image *out);

/* Observers' answers for fitting (002 "Calibrating the models"): one row per
 * trial with the stimulus's terms and the answer. */
typedef struct {
  double xor_deg;      /* spatial: the silhouette XOR's area over S0's perimeter, degrees (eq. 1
                          unweighted: the fit weighs it with w at the object's eccentricity) */
  double v_jnd;        /* spatial: the shading term */
  double ecc_deg;      /* spatial: the object's eccentricity */
  double t_jnd;        /* temporal: the switch's pooled JND */
  int seen;            /* 1: the observer told the level (or saw the switch) */
  int stimulus;        /* 0..stimuli−1: rows of one stimulus (cross-validation folds keep it whole) */
} jnd_gaze_trial;
typedef struct {
  jnd_gaze_trial *trials;
  int n, stimuli;
  int temporal;        /* 1: rows of the temporal model (t_jnd) */
} jnd_gaze_data;

/* Reads trials from CSV with a header: columns seen (0/1) and either
 * xor_deg, v_jnd, eccentricity_deg (spatial) or t_jnd (temporal); an
 * optional stimulus id 0..rows−1 (else rows with equal terms are one stimulus).
 * JND_ERR_FORMAT "NAME: row R: problem" for a missing column, a bad number
 * or an answer that is not 0/1. Free with jnd_gaze_data_free. */
JND_EXPERIMENTAL jnd_status jnd_gaze_data_read(const char *path, jnd_gaze_data *out);
JND_EXPERIMENTAL jnd_status jnd_gaze_data_parse(const char *name, const char *text, size_t n, jnd_gaze_data *out);
JND_EXPERIMENTAL void jnd_gaze_data_free(jnd_gaze_data *d);

#define JND_GAZE_MAX_FOLDS 16
typedef struct {
  int folds;               /* k of the cross-validation (4, as 002) */
  uint64_t seed;           /* of the assignment of stimuli to folds (1) */
  double confidence;       /* of the parameters' intervals (0.95) */
  jnd_gaze_model start;    /* where the search starts; fields not fitted are kept (defaults) */
} jnd_gaze_fit_params;
JND_EXPERIMENTAL void jnd_gaze_fit_defaults(jnd_gaze_fit_params *p);

typedef struct {
  jnd_gaze_model model;    /* the maximum-likelihood parameters (w_g = 1: see docs/gaze.md) */
  int temporal, nparams;
  const char *names[8];    /* the fitted parameters' names, as jnd_gaze_model's fields */
  double value[8], ci_lo[8], ci_hi[8];  /* each with its interval at the confidence asked (NaN:
                                          undetermined: a flat direction of the likelihood) */
  double neg_loglik;
  int trials, stimuli, folds;
  double r_all, mae_all;   /* on all data: Pearson r and mean absolute error between predicted P and
                              the observed proportion seen per stimulus */
  double fold_r[JND_GAZE_MAX_FOLDS], fold_mae[JND_GAZE_MAX_FOLDS];  /* on each held-out fold */
  double r_mean, r_sd, mae_mean, mae_sd;
} jnd_gaze_fit_result;

/* Fits the spatial or the temporal model to d by maximum likelihood over
 * the Bernoulli answers, with standard errors from the observed
 * information and k-fold cross-validation over stimuli. Deterministic. */
JND_EXPERIMENTAL jnd_status jnd_gaze_fit(const jnd_gaze_data *d, const jnd_gaze_fit_params *p, jnd_gaze_fit_result *out);

/* Fitted parameters read back (`jnd gaze MODEL --params FIT.json`): a
 * report of `jnd gaze fit` (gaze_fit.json: a spatial fit sets alpha, beta,
 * s_deg, w_vdp, k_s, gamma, b and w_g = 1; a temporal one w_t, gamma_t) or
 * the combined form of scripts/gaze-defaults.json ("fixed", "spatial",
 * "temporal"). Fields of a model the file does not carry are kept; on an
 * error m is unchanged and the message is "NAME: what is wrong". */
JND_EXPERIMENTAL jnd_status jnd_gaze_model_read(const char *path, jnd_gaze_model *m);
JND_EXPERIMENTAL jnd_status jnd_gaze_model_parse(const char *name, const char *text, size_t n, jnd_gaze_model *m);

/* Synthetic observers (docs/gaze.md "Defaults"): jnd ships no study, so its
 * default parameters are fitted to answers drawn from jnd's own vision model.
 * For each scene's chain, object size, orientation, eccentricity and level,
 * the stimulus's terms (xor_deg, v_jnd; t_jnd of the switch from the next
 * finer level) and the probability the vision model gives to telling the
 * level from the reference (the whole rendering, silhouette and shading,
 * nothing greyed, at each pixel's eccentricity: P = ½ + ½ · jnd_probability)
 * and to seeing the switch (its flicker JND); then `answers` Bernoulli
 * answers per stimulus from a seeded generator. */
typedef struct {
  const double *sizes_deg;       /* the bounding sphere's angular diameter, degrees, ascending in
                                    (0, 60]; NULL: 1.5, 4, 12 (002: 1.22 to 12.22) */
  int nsizes;
  const double *eccentricities_deg; /* ascending, 0..90; NULL: 0, 5, 10, 20, 30, 45, 60 */
  int neccentricities;
  const jnd_lod_params *chain;   /* a scene of one level gets this chain (NULL: 1/1024, 1/256, 1/64) */
  int orientations;              /* per size (2) */
  int answers;                   /* Bernoulli answers per stimulus (40) */
  uint64_t seed;                 /* of the orientations, lights and answers (1) */
  int min_px, max_px;            /* rendering side, as jnd_gaze_table_params (64, 192) */
  jnd_gaze_measure_params measure;
  jnd_renderer_params render;
  void (*progress)(void *user, int done, int total);
  void *progress_user;
} jnd_gaze_observers_params;
JND_EXPERIMENTAL void jnd_gaze_observers_defaults(jnd_gaze_observers_params *p);

typedef struct {
  int scene, orientation, level;   /* level ≥ 1: against level 0 (spatial), from level − 1 (switch) */
  double size_deg, ecc_deg;
  double xor_deg, v_jnd, jnd_whole, p_spatial;  /* terms; the vision model's JND of the whole change
                                                   and its 2AFC probability */
  double t_jnd, p_switch;          /* the switch's flicker JND and its probability */
  int seen_spatial, seen_switch;   /* of `answers` Bernoulli answers, how many said seen */
} jnd_gaze_stimulus;
typedef struct {
  jnd_gaze_stimulus *stimuli;
  int n, answers;
} jnd_gaze_observers;

/* Renders and judges every stimulus of nscenes scenes (each ≥ 2 levels, or
 * a chain made with p->chain), deterministic for any thread count. */
JND_EXPERIMENTAL jnd_status jnd_gaze_observers_run(jnd_scene *const *scenes, int nscenes, const jnd_gaze_observers_params *p,
                                  jnd_gaze_observers *out);
JND_EXPERIMENTAL void jnd_gaze_observers_free(jnd_gaze_observers *o);

/* The trials as `jnd gaze fit` reads them, one row per answer (atomic):
 * temporal 0: stimulus, xor_deg, v_jnd, eccentricity_deg, seen (and the
 * scene, size, level and p_true for the reader); temporal 1: stimulus,
 * t_jnd, seen (and the same). */
JND_EXPERIMENTAL jnd_status jnd_gaze_observers_write_csv(const jnd_gaze_observers *o, int temporal, const char *path);

/* `jnd gaze` as one call (the task shape, docs/architecture.md), in one of
 * three modes:
 *   JND_GAZE_RUN_TABLE      input a model (glTF/GLB/OBJ, builtin[:...]): the table
 *                           (jnd_gaze_table_run) into out_dir: gaze.json, gaze.csv,
 *                           gaze.png, and model/NAME.glb when the chain was made here;
 *   JND_GAZE_RUN_FIT        input a CSV of trials (jnd_gaze_data_read): jnd_gaze_fit,
 *                           out_dir/gaze_fit.json (out_dir NULL: only the report's copy);
 *   JND_GAZE_RUN_OBSERVERS  input NULL, the models in `models`: synthetic observers
 *                           (jnd_gaze_observers_run) into out_dir: spatial.csv,
 *                           temporal.csv, observers.json.
 * Everything goes through one output writer (nothing over an input; all or
 * nothing). */
typedef enum { JND_GAZE_RUN_TABLE = 0, JND_GAZE_RUN_FIT, JND_GAZE_RUN_OBSERVERS } jnd_gaze_run_mode;

typedef struct {
  jnd_gaze_run_mode mode;
  jnd_gaze_table_params table;         /* TABLE (jnd_gaze_table_defaults) */
  const char *const *model_files;      /* TABLE: fitted parameters read into table.model in order
                                          (jnd_gaze_model_read; NULL: none) */
  int nmodel_files;
  jnd_gaze_fit_params fit;             /* FIT (jnd_gaze_fit_defaults) */
  jnd_gaze_observers_params observers; /* OBSERVERS (jnd_gaze_observers_defaults) */
  const char *const *models;           /* OBSERVERS: the models, 1..64 */
  int nmodels;
  jnd_run_options run;                 /* map side of builtin assets (512), the report's copy, timings */
} jnd_gaze_run_params;

/* Fills p with the defaults above (mode TABLE). */
void jnd_gaze_run_defaults(jnd_gaze_run_params *p);

typedef struct {
  jnd_gaze_run_mode mode;
  jnd_gaze_table table;                /* TABLE */
  int input_levels;                    /* TABLE: levels the input had (< 2: the chain was made) */
  char chain_model[320];               /* TABLE: the chain's model under out_dir, or the input */
  double table_s;                      /* TABLE: wall-clock seconds of the table */
  int nreduced;                        /* TABLE: distances judged below the display's ppd (the
                                          window capped at max_px: .result.reduced_ppd) */
  int nwindowed;                       /* TABLE: distances judged on windows (.result.windowed) */
  jnd_gaze_fit_result fit;             /* FIT */
  jnd_gaze_observers observers;        /* OBSERVERS */
  double mean_p_spatial, mean_p_switch; /* OBSERVERS: over the stimuli */
  char *report;                        /* the report's JSON text */
} jnd_gaze_run_result;

/* The task (`jnd gaze`, `jnd gaze fit`, `jnd gaze observers`). *out is
 * allocated (jnd_gaze_run_result_free). Bad input: one error "FILE:
 * problem", nothing written. */
jnd_status jnd_gaze_run(const char *input, const jnd_gaze_run_params *p, const char *out_dir,
                        jnd_gaze_run_result **out);

/* Frees what jnd_gaze_run returned (NULL is fine). */
void jnd_gaze_run_result_free(jnd_gaze_run_result *r);

/* The engine's lookup: loaded once, no allocation per call. */
typedef struct {
  int nd, ne;
  double *distances_m, *eccentricities_deg;
  float *level;        /* nd × ne */
} jnd_gaze_lookup;
typedef enum {
  JND_GAZE_NEAREST = 0,  /* the nearest grid point's level */
  JND_GAZE_BILINEAR,     /* bilinear between the four grid points (a fractional level, to blend) */
  JND_GAZE_FLOOR         /* the grid point at or below in both: the finest of the neighbours, safe */
} jnd_gaze_lookup_mode;

/* From a table in memory, or a gaze.csv file (text: the same as parsed;
 * name for messages). A grid that is not complete, a level that is not a
 * whole number ≥ 0, a distance ≤ 0 or an eccentricity outside 0..90 is
 * JND_ERR_FORMAT "NAME: problem". */
jnd_status jnd_gaze_lookup_from_table(const jnd_gaze_table *t, jnd_gaze_lookup *out);
jnd_status jnd_gaze_lookup_load(const char *path, jnd_gaze_lookup *out);
jnd_status jnd_gaze_lookup_parse(const char *name, const char *text, size_t n, jnd_gaze_lookup *out);
void jnd_gaze_lookup_free(jnd_gaze_lookup *lut);

/* The level for an object at dist_m metres seen ecc_deg from the gaze
 * (both clamped to the grid). */
double jnd_gaze_lookup_level(const jnd_gaze_lookup *lut, double dist_m, double ecc_deg, jnd_gaze_lookup_mode mode);

#ifdef __cplusplus
}
#endif
#endif /* JND_H */
