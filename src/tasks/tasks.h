/* Internal helpers of the tasks layer, shared by the task files. Each part
 * is a delimited block owned by the file that implements it. */
#ifndef JND_TASKS_H
#define JND_TASKS_H

#include <stddef.h>
#include <stdint.h>
#include "jnd.h"
#include "io/draw.h"

/* ---- diff.c: jnd_diff_files on images kept as codes (begin) ---- */

/* jnd_diff_files where image a (0 ref, 1 test) may be an 8-bit RGB image
 * kept as its codes (jnd_image_read_rgb8) whose pyramids are made already
 * (jnd_model_image_rgb8): prep[a] non-NULL, the image holding only its
 * size, the display's luminance of each code lum[code]
 * (jnd_display_code_luminances). Both so: the model compares them
 * (jnd_model_diff_images); one: its planes are made from its codes. prep's
 * images are taken over (the pointers set to NULL), as the images are. */
typedef struct jnd_model_image jnd_model_image; /* vision/vision.h */
jnd_status diff_files_codes(jnd_model *m, jnd_image *ref, const jnd_image_info *ri, jnd_image *test,
                            const jnd_image_info *ti, jnd_model_image *prep[2], const float lum[256],
                            const jnd_diff_inputs *in, const jnd_pooling *pool, jnd_image *jnd_out,
                            jnd_diff_stats *stats);

/* ---- diff.c (end) ---- */

/* ---- judge.c: the judge's crop and the object's window (begin) ---- */

/* Pixels the judge keeps around the object's bounding box in each view:
 * room for the model's pyramid. */
#define JUDGE_CROP_MARGIN 16

/* The one object window (jnd lod's views at a distance, gaze's table): a
 * square window at the display's pixel scale framing an object object_px
 * display pixels across, grown by the factor grow and by margin_px each
 * side. *side: the grown object rounded up (round_up: the margins must hold
 * whole, as the judge's crop needs) or to the nearest pixel, plus the
 * margins, at least min_px; where that exceeds max_px, max_px, and *scale
 * (< 1, else 1) is the factor the display's pixels shrink by so that the
 * grown object and its margins fit: the object keeps its angular size at
 * fewer pixels per degree. */
void object_window(double object_px, double grow, int margin_px, int min_px, int max_px, int round_up, int *side,
                   double *scale);

/* The scene at level `level` of its chain (every mesh; left selected)
 * rendered from view v into f: the renderings that are compared as pairs
 * rather than held by a scene judge (gaze's levels, pop's switch). */
jnd_status judge_render_level(jnd_renderer *r, jnd_scene *scene, int level, const jnd_view *v, jnd_frame *f);

/* The renderer a task renders its views with: the viewer's, so that no file
 * under src/tasks but judge.c (and render_run.c, whose product is the
 * rendering) makes one (e2e.task_shape checks). rp's settings (NULL: the
 * defaults) at side × side pixels (side 0: rp's own size); a judge or task
 * resizes it to each window, and may share it across its screens or
 * distances. Free with jnd_renderer_free. */
jnd_status judge_renderer(const jnd_renderer_params *rp, int side, jnd_renderer **r);

/* The x of a fixation point ecc_deg degrees left of x = cx on a flat
 * screen of ppd pixels per degree seen from the distance the ppd implies
 * (as the model measures eccentricity): where 002's observers look when a
 * stimulus is ecc_deg out. */
double judge_fixation_left_of(double cx, double ecc_deg, double ppd);

/* A frame as the 8-bit codes a display is sent: c planes of w × h. */
typedef struct {
  int w, h, c;
  uint8_t *px;
} display_codes;

/* 003's frames (lod's PoI metric, lod_poi.c): the scene at level `level`
 * rendered from view v, unlit (flat base colour) or lit, and shown as the
 * display's 8-bit sRGB codes (3 planes): the display's curve rounded as the
 * PNG writer rounds, so that the codes are those of the frame
 * jnd_render_to_srgb shows. out's pixels are reused when it has the size
 * already (free them with free(out->px)). */
jnd_status judge_level_codes(jnd_renderer *r, jnd_scene *scene, int level, const jnd_view *v, int unlit,
                             display_codes *out);

/* ---- judge.c (end) ---- */

/* ---- lod_poi.c and lod.c: jnd lod (begin) ---- */

/* The most screens one lod run analyses (003's analysis, the perceptual
 * step's workers). */
#define LOD_MAX_SCREENS 16

/* jnd_poi_analyse's checks of its parameters against the scene, and its
 * screens (the four presets unless p names some) into scr[*nscr]: what
 * jnd_poi_analyse refuses, refused before any work, so that a run can
 * start the perceptual step's screens beside the analysis (lod.c) */
jnd_status poi_check(const jnd_scene *scene, const jnd_poi_params *p, jnd_poi_screen scr[LOD_MAX_SCREENS],
                     int *nscr);
/* ... all of it but the scene's levels: the parameters and the screens,
 * which jnd_lod_analyse refuses before it loads the asset or builds its
 * chain */
jnd_status poi_params_check(const jnd_poi_params *p, jnd_poi_screen scr[LOD_MAX_SCREENS], int *nscr);

/* ---- lod_poi.c and lod.c (end) ---- */

/* ---- linalg.c: small dense linear algebra for pca.c (begin) ---- */

/* Means of n channels: planes[ch] points at count floats. Double
 * accumulation in fixed-size chunks summed in order (thread-independent). */
void linalg_channel_means(const float *const *planes, int n, size_t count, double *mean);

/* The n × n covariance (1/count) Σ (w_i(x_i − m_i))(w_j(x_j − m_j)) of n
 * planes; cov is row-major, symmetric, filled in full. Deterministic. */
jnd_status linalg_weighted_covariance(const float *const *planes, int n, size_t count,
                                      const double *mean, const double *weight, double *cov);

/* Eigen-decomposition of a symmetric n × n matrix (row-major, not
 * modified): eigenvalues descending, vectors as columns of vec (row-major
 * n × n, vec[i·n + k] = component i of vector k), each with its
 * largest-magnitude entry positive. LAPACKE dsyev. */
jnd_status linalg_symmetric_eigen(const double *a, int n, double *eigval, double *vec);

/* ---- linalg.c (end) ---- */

/* ---- pca.c (begin) ---- */

/* The knee of the cumulative energy of n descending values (001): the
 * component count 1..n where the curve from (0, 0) to (n, total) lies
 * farthest above its chord (jnd_knee). */
int pca_energy_knee(const double *energy, int n);

/* Rendered visibility hook: see jnd_pca_rendered_visibility (jnd.h). */
jnd_status pca_rendered_visibility(const jnd_texset *set, const jnd_pca_encoded *enc,
                                   const char *model_path, const char *material, double *p_detect);

/* The scene's image (jnd_map_info.image) that slot of r's material samples;
 * -1 when the material has no map there. */
int pca_render_slot_image(const jnd_pca_render *r, jnd_map_slot slot);

/* pca_run.c: 1 when map `map` of R's set is reconstructed from a component
 * that texture `tex` (R->textures) holds, i.e. its slot samples it. */
int pca_map_samples_texture(const jnd_pca_result *R, int map, int tex);

/* ---- pca.c (end) ---- */

/* ---- lod_poi.c: 003's screen-space and perceptual terms, for tests (begin) ---- */

/* E_p² · W2·H2 (003 eq. 2 before its normalisation): test, mw × mh 8-bit
 * codes (c planes, the M2 screen), against ref, w × h codes (M1), blocks by
 * area. */
double poi_ep_sum_codes(const uint8_t *ref, int w, int h, const uint8_t *test, int mw, int mh, int c);

/* M_p · N (003 eq. 4 before its normalisation) of two w × h luma planes on a
 * display of ppd pixels per degree. */
double poi_mp_sum(const float *y1, const float *y2, int w, int h, double ppd);

/* The luma plane M_p weighs (Rec. 709 weights over 256) of w × h codes in c
 * planes; *out is allocated. */
jnd_status poi_luma_codes(const uint8_t *px, int w, int h, int c, float **out);

/* ---- lod_poi.c (end) ---- */

/* ---- lod_switch.c: the perceptual choice and switch distances (begin) ---- */

/* A test of a change that fades with distance, at point x (a distance, or
 * an index into a grid of distances): 1 passes, 0 fails, < 0 an error. */
typedef int (*switch_test_fn)(void *user, double x);

/* The next point to test strictly between lo (fails) and hi (passes), or
 * NaN when the bracket is fine enough. */
typedef double (*switch_between_fn)(void *user, double lo, double hi);

typedef enum {
  SWITCH_AT_START,   /* passes at lo already: *at = lo */
  SWITCH_NEVER,      /* fails at hi too (or hi <= lo): *fail_at = hi */
  SWITCH_FOUND       /* fails at *fail_at, passes at *at, between() had nothing left between them */
} switch_found;

/* The one distance search (jnd lod's switch distances on its grid, pop's
 * popping-free distance on log distance): the nearest point from lo
 * towards hi where a test that is taken to pass from some point on passes.
 * Tests lo, then hi (not when hi <= lo), then bisects the bracket at the
 * points between() gives. JND_ERR_INTERNAL when a test fails with an
 * error (the caller keeps its own status). */
jnd_status switch_search(double lo, double hi, switch_test_fn test, switch_between_fn between, void *user,
                         switch_found *found, double *at, double *fail_at);

/* Whether level `level` passes the criterion at grid distance `grid` (0 the
 * viewing condition, rising with the distance): 1 passes, 0 fails, < 0 an
 * error. */
typedef int (*lod_passes_fn)(void *user, int level, int grid);

/* Whether asking about grid distance `grid` is cheap now (its references
 * are rendered): 1 yes, 0 no. */
typedef int (*lod_ready_fn)(void *user, int grid);

/* The perceptual step's parameters that need no scene (views per distance,
 * coverages, tolerance, max_px, popping motion): JND_ERR_ARG naming the
 * first out of range. jnd_lod_run checks them before any work (issue 28:
 * they were refused only after minutes of 003's analysis). */
jnd_status lod_switch_check(const jnd_lod_switch_params *p);

/* The decisions of jnd_lod_switch_analyse on any oracle: *perceptual gets
 * the coarsest level passing at grid 0 (0: none); switch_idx[k] (nlevels,
 * caller's) the grid index from which level k is shown — level 0 at 0,
 * level k searched from level k − 1's index up by bisection (the oracle is
 * taken to be monotone in the distance), −1 when it fails at the far end
 * (ngrid − 1), and then for every coarser level. ready (may be NULL): a
 * bisection step asks, instead of the middle of its bracket, the ready
 * distance nearest to it within the bracket's middle half, if any (the
 * same answers on a monotone oracle, fewer distances to render).
 * JND_ERR_INTERNAL when the oracle fails. */
jnd_status lod_switch_search(int nlevels, int ngrid, lod_passes_fn passes, lod_ready_fn ready, void *user,
                             int *perceptual, int *switch_idx);

/* The switch distances from their two components (jnd_lod_switch_result):
 * out[0] = 0; out[k] = the farthest of criterion[k], pop[k] (NaN: no
 * constraint) and out[k − 1], so out rises with k; by[k] says which decided
 * (the criterion on a tie). */
void lod_switch_combine(int nlevels, const double *criterion, const double *pop, double *out, jnd_lod_switch_by *by);

/* ---- lod_switch.c (end) ---- */

/* pop.c: the model that judges a level switch, mp's with the flicker task
 * (a switch is a change in place; docs/pop.md "Viewing task"): pop's run and
 * lod's popping step make theirs with it. */
jnd_status pop_model_create(const jnd_model_params *mp, jnd_model **m);

/* ---- pop_weights.c: the popping predictor's weights, 004 §4 (begin) ---- */

/* Previous-frame visibility (0..1) of each pixel into vis (w × h, caller's):
 * percentage-closer filtering of prev_depth at the pixel's previous position
 * (pixel − displacement; disp NULL: static), each of the four bilinear
 * samples counting when depth <= (1 + tol) × its depth; 0 means nothing
 * there (infinitely far). Samples off the image do not count. */
jnd_status pop_visibility(const jnd_image *depth, const jnd_image *prev_depth, const jnd_image *disp, double tol,
                          float *vis);

/* The flicker weight (0..1) of each pixel into wout (caller's): ΔE*94 of
 * prev_shading against prev_color sampled at the previous position (from
 * the samples whose depth matches, when depth and prev_depth are given;
 * both NULL otherwise), over de_levels (the two levels' ΔE*94), ramped
 * between p->flicker_ratio_lo and _hi, trusted less from
 * p->flicker_motion_lo_px of displacement and not at all from _hi_px. */
jnd_status pop_flicker_weight(const jnd_display *d, const jnd_image *prev_shading, const jnd_image *prev_color,
                              const jnd_image *disp, const jnd_image *depth, const jnd_image *prev_depth,
                              const jnd_image *de_levels, const jnd_pop_params *p, float *wout);

/* ---- pop_weights.c (end) ---- */

/* ---- pop_picture.c: 004 Fig. 4 (begin) ---- */

/* The picture's backdrop: a frame (absolute linear RGB, cd/m²) as display d
 * shows it, in dimmed grey (1 channel, signal 0..1; grey allocated). */
jnd_status pop_backdrop(const jnd_display *d, const jnd_image *frame, jnd_image *grey);

/* The backdrop with each region's pixels coloured by its rating R, and a
 * legend column: the counts and scores, and a colour bar of R. */
jnd_status pop_picture(const jnd_image *grey, const jnd_pop_result *r, jnd_image *out);

/* ---- pop_picture.c (end) ---- */

/* pop_asset.c: switch.png of a report with rows (decide): the popping-free
 * distance per level, one line per speed, and the 1-pixel rule's distances,
 * on a log axis labelled in r->distance_unit; its layout too unless NULL */
jnd_status pop_switch_plot(const jnd_pop_asset_report *r, const double *speeds, int nspeeds, jnd_image *out,
                           jnd_plot_layout *layout);

/* pop_asset.c: jnd_pop_render of a view whose object stays centred, with
 * only a centred window of side pixels of r's frame rendered (the frame's
 * side minus side even) and put back in the frame, as the switch search
 * renders far distances (docs/pop.md "Switch decisions"); side 0: the whole
 * frame. r is left at its size. */
jnd_status pop_render_window(jnd_model *m, jnd_renderer *r, jnd_scene *scene, const jnd_view *view,
                             const jnd_pop_motion *mo, int level, int frame, const jnd_pop_params *p, int side,
                             jnd_pop_result *out);

/* ---- texres.c (begin) ---- */
/* The whole mip levels a map whose finest sampled level is mip_min
 * (jnd_judge_mip_min, ≥ 0) can drop without a visible change: 000 §4's
 * bound with texres's half-level margin for drivers' derivatives. jnd
 * budget caps a level's maps with it at the level's switch distance. */
int texres_mip_bound_level(double mip_min);
/* ---- texres.c (end) ---- */

/* ---- texres_figures.c: pictures of a texres result (begin) ---- */

/* The worst view's figure: the object as rendered (ref_srgb, display
 * signal) beside its heatmap, magnified to a readable size, titled with the
 * view and its pooled P. */
jnd_status texres_worst_view_figure(const jnd_image *ref_srgb, const jnd_image *map, int view, int nviews, double p,
                                    jnd_image *out);

/* ---- texres_figures.c (end) ---- */

/* ---- lod_figures.c: lod's Pareto plot (begin) ---- */

/* jnd_poi_pareto_plot's picture (out, unless NULL) and its layout (unless
 * NULL): the ticks, labels and marks a test checks against the data. */
jnd_status lod_pareto_plot(const jnd_poi_result *r, int screen, int perceptual, jnd_image *out,
                           jnd_plot_layout *layout);

/* ---- lod_figures.c (end) ---- */

/* ---- budget.c: the separate candidate taken (begin) ---- */

/* Step 7 of jnd_budget_search (docs/budget.md), on R after the joint
 * choice (R->chosen, R->passes, R->levels) and the separate candidate's
 * chain (R->separate_levels) are verified: 1 where, in cheapest-unnoticed
 * mode, the separate candidate is another than the choice, passes p on the
 * judge's views (pass) and every level of its chain passes its held-out
 * views, and the choice costs more or is seen. */
int budget_take_separate(const jnd_budget_result *R);

/* ---- budget.c (end) ---- */

/* ---- budget_figures.c: budget's Pareto plot (begin) ---- */

/* jnd_budget_pareto_plot's picture (out, unless NULL) and its layout (unless
 * NULL): the ticks and legend a test checks against the candidates. */
jnd_status budget_pareto_plot(const jnd_budget_result *r, const jnd_criterion *c, jnd_image *out,
                              jnd_plot_layout *layout);

/* ---- budget_figures.c (end) ---- */

/* ---- csf_data.c: castleCSF colour (begin) ---- */

/* castleCSF's CIE 2006 LMS → CIE XYZ matrix (derived for LED-LCD spectra),
 * the colour space of every `jnd csf` stimulus. */
extern const double jnd_csf_lms2006_xyz[3][3];
void jnd_csf_lms_to_xyz(const double lms[3], double xyz[3]);

/* The unit CIE 2006 LMS direction of a change of chromaticity at constant
 * luminance Y along angle_deg in the CIE 1976 u′v′ diagram, around the
 * chromaticity of bkg_lms (kong2018's modulations, docs/csf.md). */
void jnd_csf_uv_direction(const double bkg_lms[3], double angle_deg, double dir_lms[3]);

/* jnd_csf_data_read on tables already parsed: *table is taken over (left
 * empty), the other two are only read; the names are for messages. */
jnd_status jnd_csf_data_from_tables(const char *data, jnd_csv *table, const char *colors, const jnd_csv *tc,
                                    const char *backgrounds, const jnd_csv *tb, jnd_csf_data *out);

/* ---- csf_data.c (end) ---- */

/* ---- csf_check.c: threshold searches (begin) ---- */

/* 1: each threshold is the one a single model run at a small probe contrast
 * implies (the model is linear in a stimulus's contrast up to the few per
 * cent it adds to the local mean); the fit's fast surrogate. 0: searched to
 * 0.02 dB (the default, and every reported figure). */
void jnd_csf_context_set_linear(jnd_csf_context *ctx, int linear);

/* The images a threshold search shows the model: *bg the uniform background
 * at the stimulus's luminance (XYZ, cd/m²), *stim the modulation at unit RMS
 * cone contrast (XYZ), both side × side at *ppd (jnd_csf_sampling's). */
jnd_status csf_stimulus_images(const jnd_csf_stimulus *st, double *ppd, jnd_image *bg, jnd_image *stim);

/* ---- csf_check.c (end) ---- */

/* ---- gaze.c, gaze_table.c: what the table and the synthetic observers share (begin) ---- */

/* The pooled JND (mp->pool over S0 ∪ Si) of two renderings (linear over
 * black, with coverage) seen over the background with the fixation point at
 * (gx, gy) pixels on a display of ppd; grey_xor: the silhouette XOR grey in
 * both (the shading term); temporal_hz > 0: the change judged as a temporal
 * modulation at that frequency (jnd_diff_inputs.temporal_hz). */
jnd_status gaze_pooled_jnd(const jnd_gaze_measure_params *mp, double ppd, double gx, double gy, const jnd_image *a,
                           const jnd_image *ma, const jnd_image *b, const jnd_image *mb, int grey_xor,
                           double temporal_hz, double *out);

/* A list of 1 to 256 values, ascending, each in [lo, hi] ((lo, hi] with
 * lo_open); JND_ERR_ARG "FLAG: problem" otherwise. */
jnd_status gaze_check_axis(const double *v, int n, const char *flag, double lo, int lo_open, double hi);

/* The window that frames a bounding sphere of radius r at distance d: its
 * vertical field of view (degrees), side (pixels, the display's ppd within
 * [min_px, max_px]) and the pixels per degree at its centre. */
void gaze_frame_for(double ppd_display, int min_px, int max_px, double radius, double d, double *fov_deg, int *side,
                    double *ppd);

/* Every level (L) of the scene's chain rendered from each of no views,
 * colour and coverage, into R->color/mask[o · L + k]; *count += renderings.
 * Leaves level 0 selected. */
typedef struct {
  jnd_image *color, *mask;
} gaze_renders;
jnd_status gaze_render_levels(jnd_scene *scene, jnd_renderer *r, const jnd_view *views, int no, int L,
                              gaze_renders *R, int *count);

/* ---- gaze.c, gaze_table.c (end) ---- */

#endif
