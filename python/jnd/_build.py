"""Builds jnd's C extension (cffi, API mode) against include/jnd.h and libjnd.so.

API mode, not ABI mode: the compiler checks every declaration below against
jnd.h, and structs declared with "..." take their layout from the header, so
the binding cannot drift from the library silently.

    python3 -m jnd._build --include DIR --libdir DIR --out DIR

writes DIR/jnd/_jnd_cffi*.so (the package's files are copied beside it).
The extension finds libjnd.so through an rpath to --libdir.
"""
import argparse
import os
import shutil
import sys

CDEF = r"""
typedef enum { JND_OK, JND_ERR_IO, JND_ERR_FORMAT, JND_ERR_ARG, JND_ERR_LIMIT,
               JND_ERR_NOMEM, JND_ERR_GL, JND_ERR_INTERNAL } jnd_status;
const char *jnd_last_error(void);
const char *jnd_version(void);

typedef struct { int w, h, c; float *data; } jnd_image;
jnd_status jnd_image_alloc(jnd_image *img, int w, int h, int c);
void jnd_image_free(jnd_image *img);

typedef enum { JND_ENCODING_SRGB, JND_ENCODING_LINEAR } jnd_encoding;
typedef struct {
  jnd_encoding encoding;
  int bits;
  int channels;
  int has_alpha;
  char format[8];
} jnd_image_info;
jnd_status jnd_image_read(const char *path, jnd_image *out, jnd_image_info *info);

typedef enum { JND_TASK_SIDE_BY_SIDE, JND_TASK_FLICKER } jnd_viewing_task;
const char *jnd_viewing_task_name(jnd_viewing_task t);
jnd_status jnd_viewing_task_parse(const char *s, jnd_viewing_task *t);
typedef struct {
  char name[32];
  double ppd, peak_cdm2, black_cdm2, ambient_lux, reflectivity, exr_scale;
  double diagonal_in, distance_m;
  int width_px, height_px;
  jnd_viewing_task task;
} jnd_display;
void jnd_display_defaults(jnd_display *d);
jnd_status jnd_display_preset(const char *name, jnd_display *d);
const char *const *jnd_display_preset_names(void);
double jnd_ppd_from_geometry(double diagonal_in, int width_px, int height_px, double distance_m);

typedef struct {
  jnd_display display;
  double beta;
  int has_gaze;
  double gaze_x, gaze_y;
  double fps;
  int threads;
  double min_band_cpd;
  ...;
} jnd_model_params;
void jnd_model_defaults(jnd_model_params *p);

typedef struct jnd_model jnd_model;
jnd_status jnd_model_create(const jnd_model_params *p, jnd_model **out);
void jnd_model_free(jnd_model *m);
int jnd_model_band_peaks(const jnd_model *m, double *cpd, int max);

typedef struct { ...; } jnd_diff_inputs;

typedef enum { JND_POOL_PERCENTILE, JND_POOL_MAX, JND_POOL_MEAN, JND_POOL_MINKOWSKI } jnd_pool_kind;
typedef struct { jnd_pool_kind kind; double percentile; } jnd_pooling;
jnd_status jnd_pooling_parse(const char *s, jnd_pooling *out);

typedef struct {
  double p_detect;
  double p_p50, p_p93, p_p99, p_max, p_mean;
  double jnd_mean, jnd_p93, jnd_max;
  double jnd_minkowski;
} jnd_diff_stats;
double jnd_probability(double jnd, double beta);
jnd_status jnd_diff_files(jnd_model *m, jnd_image *ref, const jnd_image_info *ref_info,
                          jnd_image *test, const jnd_image_info *test_info,
                          const jnd_diff_inputs *in, const jnd_pooling *pool,
                          jnd_image *jnd_out, jnd_diff_stats *stats);

/* ---- the task runs (jnd_<task>_run): only the fields the binding sets or
   reads are named; "..." takes the rest of each layout from jnd.h ---- */
typedef struct {
  int map_size;
  const char *report_path;
  int timings;
  void (*warning)(void *user, const char *message);
  void *warning_user;
} jnd_run_options;
void jnd_run_options_defaults(jnd_run_options *o);

typedef struct { double percentile; double scale, bias; double beta; double threshold_p; ...; } jnd_calibration;
void jnd_calibration_defaults(jnd_calibration *c);
jnd_status jnd_calibration_load(const char *path, jnd_calibration *c);

typedef struct {
  int count; uint64_t seed; double coverage; double distance; double fov_y_deg;
  double min_elevation_deg; double max_elevation_deg; int lights; double light_intensity; ...;
} jnd_view_sampling;
typedef struct {
  int width, height; int samples; int anisotropy; const char *env_path; const char *platform; ...;
} jnd_renderer_params;
typedef struct { jnd_view_sampling sampling; const char *cameras_path; jnd_renderer_params render; ...; } jnd_view_set;
void jnd_view_set_defaults(jnd_view_set *vs);
typedef struct { double p; double q; ...; } jnd_criterion;
typedef struct {
  jnd_view_set views; jnd_model_params model; jnd_calibration calibration; jnd_criterion criterion; ...;
} jnd_judge_params;

typedef struct {
  jnd_judge_params judge;
  int verify_views; double margin; int confirm_rounds; int min_size;
  const int *sizes; int nsizes; const char *maps; int matrix;
  void (*progress)(void *user, const char *line, int done, int total);
  void *progress_user;
  jnd_run_options run;
  ...;
} jnd_texres_params;
void jnd_texres_defaults(jnd_texres_params *p);
typedef struct { char *report; int passes; ...; } jnd_texres_result;
jnd_status jnd_texres_run(const char *model, const jnd_texres_params *p, const char *out_dir,
                          jnd_texres_result **out);
void jnd_texres_result_free(jnd_texres_result *r);

typedef enum { JND_PCA_RULE_AUTO, JND_PCA_RULE_RENDERED, JND_PCA_RULE_ENERGY, JND_PCA_RULE_PSNR,
               JND_PCA_RULE_COMPONENTS } jnd_pca_rule;
typedef struct { jnd_judge_params judge; int builtin_map_size; ...; } jnd_pca_render_params;
typedef struct {
  const char *const *maps; int nmaps; const char *channels; const char *weights;
  const char *model; const char *material; const char *const *slots; int nslots;
  jnd_pca_render_params render; jnd_pca_rule rule; double energy; double psnr_db; int max_scale;
  int components; int scale[32]; int nscale; int bits[32]; int nbits; int block_compression;
  void (*progress)(void *user, const char *line, int done, int total);
  void *progress_user;
  int write_maps;
  jnd_run_options run;
  ...;
} jnd_pca_params;
void jnd_pca_defaults(jnd_pca_params *p);
typedef struct { char *report; ...; } jnd_pca_result;
jnd_status jnd_pca_run(const char *model, const jnd_pca_params *p, const char *out_dir, jnd_pca_result **out);
void jnd_pca_result_free(jnd_pca_result *r);

typedef struct {
  int folds; double beta; double threshold_p; double bias_min, bias_max; ...;
} jnd_calibrate_params;
typedef struct {
  jnd_calibrate_params fit; jnd_judge_params judge; const char *pairs; const int *sizes; int nsizes;
  const char *histogram;
  void (*progress)(void *user, const char *line, int done, int total);
  void *progress_user;
  jnd_run_options run;
  ...;
} jnd_calibrate_run_params;
void jnd_calibrate_run_defaults(jnd_calibrate_run_params *p);
typedef struct { char *report; ...; } jnd_calibrate_result;
jnd_status jnd_calibrate_run(const char *thresholds_csv, const jnd_calibrate_run_params *p, const char *out_path,
                             jnd_calibrate_result **out);
void jnd_calibrate_result_free(jnd_calibrate_result *r);

typedef struct {
  const double *errors; int nerrors; const double *ratios; int nratios; int lock_border; int allow_sloppy;
  int threads; ...;
} jnd_lod_params;
typedef enum { JND_POP_ORBIT, JND_POP_TRANSLATE, JND_POP_OBJECT, JND_POP_PAN } jnd_pop_motion_kind;
typedef struct { char name[32]; int width_px, height_px; double ppd; } jnd_poi_screen;
jnd_status jnd_poi_screen_parse(const char *spec, jnd_poi_screen *s);
typedef struct {
  const jnd_poi_screen *screens; int nscreens; int views; uint64_t seed; double coverage; double fov_y_deg;
  int lights; double virtual_scale; int max_virtual_px; int anisotropy; int surface_samples;
  double meshopt_pixels; double pixel_error; int textures; const char *env_path; const char *platform; ...;
} jnd_poi_params;
typedef struct {
  jnd_judge_params judge; double distance; double far_coverage; double tolerance; int max_px; int pop;
  int pop_motion; double pop_speed; ...;
} jnd_lod_switch_params;
typedef struct {
  jnd_lod_params chain; int rebuild; const char *const *level_paths; int nlevel_paths; int analyse;
  jnd_poi_params poi; int perceptual; jnd_lod_switch_params sw; int threads;
  void (*progress)(void *user, const char *stage, int done, int total);
  void *progress_user;
  jnd_run_options run;
  ...;
} jnd_lod_run_params;
void jnd_lod_run_defaults(jnd_lod_run_params *p);
typedef struct { char *report; ...; } jnd_lod_result;
jnd_status jnd_lod_run(const char *model, const jnd_lod_run_params *p, const char *out_dir, jnd_lod_result **out);
void jnd_lod_result_free(jnd_lod_result *r);

static const int JND_RENDER_COLOR, JND_RENDER_DEPTH, JND_RENDER_MASK, JND_RENDER_MOTION, JND_RENDER_MIP,
                 JND_RENDER_EXR;
typedef struct { const char *map; const char *file; double factor; int w, h; } jnd_map_edit;
typedef struct {
  jnd_view_set views; int lod; int strict; double env_intensity; double env_rotation_deg; double exposure;
  int background_env; double motion_orbit_deg; unsigned outputs; const jnd_map_edit *edits; int nedits;
  void (*progress)(void *user, const char *line, int done, int total);
  void *progress_user;
  jnd_run_options run;
  ...;
} jnd_render_params;
void jnd_render_defaults(jnd_render_params *p);
typedef struct { char *report; ...; } jnd_render_result;
jnd_status jnd_render_run(const char *model, const jnd_render_params *p, const char *out_dir,
                          jnd_render_result **out);
void jnd_render_result_free(jnd_render_result *r);

typedef struct {
  jnd_model_params model; jnd_pooling pool; const char *calibration_path; const char *motion_path;
  const char *weights_path; const char *map_path; const char *heatmap_path; double heatmap_max;
  double fail_above; int exr_scale_given; jnd_run_options run; ...;
} jnd_diff_params;
void jnd_diff_defaults(jnd_diff_params *p);
typedef struct { int above; char *report; ...; } jnd_diff_result;
jnd_status jnd_diff_run(const char *ref, const char *test, const jnd_diff_params *p, jnd_diff_result **out);
void jnd_diff_result_free(jnd_diff_result *r);

/* csf */
int jnd_model_constant_find(const char *name);
jnd_status jnd_model_constant_set(jnd_model_params *p, int k, double value);
typedef struct {
  int fit; int cross_validate; int search_every; int max_iterations; int fit_mask_set; unsigned long long fit_mask;
  int threads;
  void (*progress)(void *user, const char *stage, int done, int total);
  void *user;
  ...;
} jnd_csf_options;
typedef struct {
  jnd_model_params model; jnd_csf_options options; const char *colors; const char *backgrounds;
  const char *const *datasets; int ndatasets; int static_only; int every; jnd_run_options run; ...;
} jnd_csf_run_params;
void jnd_csf_run_defaults(jnd_csf_run_params *p);
typedef struct { char *report; ...; } jnd_csf_run_result;
jnd_status jnd_csf_run(const char *data, const jnd_csf_run_params *p, const char *out_csv, jnd_csf_run_result **out);
void jnd_csf_run_result_free(jnd_csf_run_result *r);

/* gaze */
void jnd_lod_defaults(jnd_lod_params *p);
typedef struct { double b; ...; } jnd_gaze_model;
typedef struct { jnd_model_params model; ...; } jnd_gaze_measure_params;
typedef struct {
  const double *distances_m; int ndistances; const double *eccentricities_deg; int neccentricities;
  const jnd_lod_params *chain; int orientations; uint64_t seed; double threshold; int min_px, max_px;
  int near_window; jnd_gaze_measure_params measure; jnd_renderer_params render;
  void (*progress)(void *user, int done, int total);
  void *progress_user;
  ...;
} jnd_gaze_table_params;
typedef struct { int folds; uint64_t seed; double confidence; jnd_gaze_model start; ...; } jnd_gaze_fit_params;
typedef struct {
  const double *sizes_deg; int nsizes; const double *eccentricities_deg; int neccentricities;
  const jnd_lod_params *chain; int orientations; int answers; uint64_t seed; int min_px, max_px;
  jnd_renderer_params render;
  void (*progress)(void *user, int done, int total);
  void *progress_user;
  ...;
} jnd_gaze_observers_params;
typedef enum { JND_GAZE_RUN_TABLE, JND_GAZE_RUN_FIT, JND_GAZE_RUN_OBSERVERS } jnd_gaze_run_mode;
typedef struct {
  jnd_gaze_run_mode mode; jnd_gaze_table_params table; const char *const *model_files; int nmodel_files;
  jnd_gaze_fit_params fit; jnd_gaze_observers_params observers; const char *const *models; int nmodels;
  jnd_run_options run; ...;
} jnd_gaze_run_params;
void jnd_gaze_run_defaults(jnd_gaze_run_params *p);
typedef struct { char *report; ...; } jnd_gaze_run_result;
jnd_status jnd_gaze_run(const char *input, const jnd_gaze_run_params *p, const char *out_dir,
                        jnd_gaze_run_result **out);
void jnd_gaze_run_result_free(jnd_gaze_run_result *r);

/* pop */
typedef struct { jnd_pop_motion_kind kind; double speed; double direction[3]; double unit_m; ...; } jnd_pop_motion;
typedef struct { int threads; ...; } jnd_pop_params;
typedef struct {
  const char *actual, *expected; const char *displacement; const char *displacement_expected;
  const char *depth, *depth_expected; const char *prev_depth, *prev_depth_expected;
  const char *weights, *prev_color, *prev_shading, *mask; ...;
} jnd_pop_paths;
typedef struct { int first, last; ...; } jnd_pop_sequence_params;
typedef struct { double tolerance; double coverage_near; double coverage_far; ...; } jnd_pop_switch_params;
typedef struct {
  jnd_view_set views; const char *cameras; int builtin_map_size; jnd_lod_params chain; int rebuild;
  const char *const *level_paths; int nlevel_paths; jnd_pop_motion motion; int level; int frame; int decide;
  const double *speeds; int nspeeds; jnd_pop_switch_params search; ...;
} jnd_pop_asset_params;
typedef struct {
  jnd_model_params model; jnd_pop_params pop; jnd_pop_paths frames; int sequence; jnd_pop_sequence_params seq;
  jnd_pop_asset_params asset; int maps; int max_regions; double fail_above;
  void (*progress)(void *user, const char *stage, int done, int total);
  void *progress_user;
  jnd_run_options run;
  ...;
} jnd_pop_run_params;
void jnd_pop_run_defaults(jnd_pop_run_params *p);
typedef struct { int above; char *report; ...; } jnd_pop_run_result;
jnd_status jnd_pop_run(const char *model, const jnd_pop_run_params *p, const char *out_dir, jnd_pop_run_result **out);
void jnd_pop_run_result_free(jnd_pop_run_result *r);

/* budget */
typedef struct {
  jnd_texres_params texres; jnd_lod_run_params lod; double bytes_per_triangle; double memory_bytes;
  double triangles; int verify_views;
  void (*progress)(void *user, const char *line, int done, int total);
  void *progress_user;
  jnd_run_options run;
  ...;
} jnd_budget_params;
void jnd_budget_defaults(jnd_budget_params *p);
typedef struct { int passes; char *report; ...; } jnd_budget_result;
jnd_status jnd_budget_run(const char *model, const jnd_budget_params *p, const char *out_dir,
                          jnd_budget_result **out);
void jnd_budget_result_free(jnd_budget_result *r);

/* the callbacks of a run, into Python (jnd/tasks.py) */
extern "Python" void _jnd_progress(void *user, const char *line, int done, int total);
extern "Python" void _jnd_progress_count(void *user, int done, int total);
extern "Python" void _jnd_warning(void *user, const char *message);
"""


def ffibuilder(include_dir, lib_dir):
    from cffi import FFI

    ffi = FFI()
    ffi.cdef(CDEF)
    ffi.set_source(
        "jnd._jnd_cffi",
        '#include "jnd.h"',
        include_dirs=[os.path.abspath(include_dir)],
        library_dirs=[os.path.abspath(lib_dir)],
        libraries=["jnd"],
        extra_link_args=["-Wl,-rpath," + os.path.abspath(lib_dir)],
        extra_compile_args=os.environ.get("JND_PY_CFLAGS", "").split(),
    )
    return ffi


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--include", required=True, help="the folder holding jnd.h")
    ap.add_argument("--libdir", required=True, help="the folder holding libjnd.so")
    ap.add_argument("--out", required=True, help="the folder to put the package jnd/ in")
    a = ap.parse_args(argv)
    here = os.path.dirname(os.path.abspath(__file__))
    pkg = os.path.join(a.out, "jnd")
    os.makedirs(pkg, exist_ok=True)
    for f in os.listdir(here):
        if f.endswith(".py"):
            shutil.copy2(os.path.join(here, f), os.path.join(pkg, f))
    tmp = os.path.join(a.out, "_cffi_build")
    ffibuilder(a.include, a.libdir).compile(tmpdir=tmp, verbose=False, target=None)
    for f in os.listdir(os.path.join(tmp, "jnd")):
        if f.startswith("_jnd_cffi") and f.endswith(".so"):
            shutil.copy2(os.path.join(tmp, "jnd", f), os.path.join(pkg, f))
            return 0
    print("jnd._build: the extension was not built", file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main())
