/* The schema of the task reports: where each field that a reader relies on
 * lies in a report, named once. The report builders
 * (src/tasks/<task>_report.c) write these fields; batch's summary and HTML
 * report (src/batch/commands.c, plots.c) read them through these names
 * only, never through a path spelt again; tests/unit/test_report_schema.c
 * runs each task, reads every field of its report through report_schema(),
 * and checks that every path batch's table of commands names is one of
 * them. So a renamed field fails a test instead of leaving a blank cell.
 *
 * A path: dots step into objects, [] into every element of a list, [N] into
 * one ("result.maps[].chosen"). A RS_<TASK>_<LIST>_<FIELD> name is relative
 * to its list's element (a table's column); RS_PATH joins the two. Internal
 * to the library. */
#ifndef JND_TASKS_REPORT_SCHEMA_H
#define JND_TASKS_REPORT_SCHEMA_H

#include <cjson/cJSON.h>

/* ---- reading a report ---- */

/* The items a path selects in a report: "result.memory.before_bytes" (one
 * item), "result.maps[].chosen" (one per element of maps), "result.p[0]".
 * Up to max items go to out; returns how many the path selects. */
int jnd_json_select(const cJSON *root, const char *path, const cJSON **out, int max);
/* The single number at path, or NaN; "max:PATH" is the largest number PATH selects. */
double jnd_json_number(const cJSON *root, const char *path);

/* a list's path and a path relative to its element, as one path */
#define RS_PATH(list, field) list "." field
/* the largest of the numbers a path selects (jnd_json_number) */
#define RS_MAX(path) "max:" path

/* ---- texres.json (tasks/texres_report.c) ---- */
#define RS_TEXRES_MEMORY_BEFORE "result.memory.before_bytes"
#define RS_TEXRES_MEMORY_AFTER "result.memory.after_bytes"
#define RS_TEXRES_MEMORY_REDUCTION "result.memory.reduction"
#define RS_TEXRES_MEMORY_BLOCK_BEFORE "result.memory.block_before_bytes"
#define RS_TEXRES_MEMORY_BLOCK_AFTER "result.memory.block_after_bytes"
#define RS_TEXRES_VIEWS_PASSES "result.views.passes"
#define RS_TEXRES_VIEWS_P "result.views.p"
#define RS_TEXRES_VIEWS_P_EACH "result.views.p[]"
#define RS_TEXRES_VIEWS_FRACTION_ABOVE "result.views.fraction_above"
#define RS_TEXRES_VERIFY_PASSES "result.verify.passes"            /* with held-out views */
#define RS_TEXRES_CRITERION_P "parameters.criterion.p"
#define RS_TEXRES_CRITERION_Q "parameters.criterion.q"
#define RS_TEXRES_CHOICE_P "parameters.choice_p"              /* p·(1 − margin): a size passes below it */
#define RS_TEXRES_PPD "result.ppd"
#define RS_TEXRES_RENDERER "result.renderer"
#define RS_TEXRES_MAPS "result.maps[]"                            /* one per searched map: */
#define RS_TEXRES_MAPS_NAME "name"
#define RS_TEXRES_MAPS_ORIGINAL "original"                        /* [w, h] */
#define RS_TEXRES_MAPS_CHOSEN "chosen"                            /* [w, h] */
#define RS_TEXRES_MAPS_MIP_BOUND "mip_bound"
#define RS_TEXRES_MAPS_EYE_BOUND "eye_bound"
#define RS_TEXRES_MAPS_RESOLUTION_AT_P "psychometric.resolution_at_p"
#define RS_TEXRES_MAPS_BLOCK_FORMAT "block_format"
#define RS_TEXRES_MAPS_IMAGE "image"
#define RS_TEXRES_MAPS_SEARCHED "searched"                      /* each map alone at each candidate: */
#define RS_TEXRES_MAPS_CANDIDATES "candidates"                  /* [[w, h], ...] */
#define RS_TEXRES_MAPS_SERIES "series"                          /* the statistic of each, or null */
#define RS_TEXRES_MAPS_SERIES_EARLY "series_decided_early"      /* 1: a lower bound */
#define RS_TEXRES_IMAGES "result.memory.images[]"                 /* each image once: */
#define RS_TEXRES_IMAGES_MAPS "maps"
#define RS_TEXRES_IMAGES_ORIGINAL "original"
#define RS_TEXRES_IMAGES_CHOSEN "chosen"
#define RS_TEXRES_IMAGES_BLOCK_FORMAT "block_format"
#define RS_TEXRES_IMAGES_BEFORE_RGBA8 "bytes_before.rgba8"
#define RS_TEXRES_IMAGES_AFTER_RGBA8 "bytes_after.rgba8"
#define RS_TEXRES_MATRICES_PNG "result.matrices[].png"            /* with --matrix */

/* ---- pca.json (tasks/pca_report.c) ---- */
#define RS_PCA_MEMORY_BEFORE "result.memory.before_bytes"
#define RS_PCA_MEMORY_AFTER "result.memory.after_bytes"
#define RS_PCA_CHANNEL_COUNT "result.channel_count"
#define RS_PCA_COMPONENTS_KEPT "result.components_kept"
#define RS_PCA_KNEE "result.knee"
#define RS_PCA_RENDERED_PASS "result.rendered.pass"               /* the rendered choice (--model): */
#define RS_PCA_RENDERED_P_CRITERION "result.rendered.p_criterion"
#define RS_PCA_RENDERED_P_PER_VIEW "result.rendered.p_per_view"
#define RS_PCA_WIDTH "result.width"
#define RS_PCA_ENERGY_FRACTION "result.energy_fraction[]"
#define RS_PCA_CUMULATIVE_ENERGY "result.cumulative_energy[]"
#define RS_PCA_COMPONENTS "result.components[]"                   /* one per component kept: */
#define RS_PCA_COMPONENTS_DIVISOR "divisor"
#define RS_PCA_CHANNELS "result.channels[]"                       /* one per input channel: */
#define RS_PCA_CHANNELS_NAME "name"
#define RS_PCA_CHANNELS_PSNR "psnr_db"
#define RS_PCA_CHANNELS_PSNR_BC4 "psnr_bc4_db"                    /* with block compression: */
#define RS_PCA_CHANNELS_PSNR_BC1 "psnr_bc1_db"
#define RS_PCA_CHANNELS_PSNR_PLAIN_BC "psnr_plain_bc_db"
#define RS_PCA_TEXTURES "result.textures[]"                       /* the packed component files: */
#define RS_PCA_TEXTURES_FILE "file"
#define RS_PCA_TEXTURES_WIDTH "width"
#define RS_PCA_TEXTURES_HEIGHT "height"
#define RS_PCA_TEXTURES_BITS "bits"

/* ---- diff's report (tasks/diff_report.c) ---- */
#define RS_DIFF_P_DETECT "result.p_detect"
#define RS_DIFF_POOLING "result.pooling"
#define RS_DIFF_P_P50 "result.p_p50"
#define RS_DIFF_P_P99 "result.p_p99"
#define RS_DIFF_JND_MEAN "result.jnd_mean"
#define RS_DIFF_JND_P93 "result.jnd_p93"
#define RS_DIFF_JND_MAX "result.jnd_max"
#define RS_DIFF_WIDTH "result.width"
#define RS_DIFF_HEIGHT "result.height"
#define RS_DIFF_DISPLAY_NAME "parameters.display.name"

/* ---- views.json, render's (tasks/render_report.c) ---- */
#define RS_RENDER_RENDERER "result.renderer"
#define RS_RENDER_VIEWS "views[]"                                 /* one per view: */
#define RS_RENDER_VIEWS_COLOR "color"

/* ---- lod.json (tasks/lod_report.c) ---- */
#define RS_LOD_MEMORY_BEFORE "result.memory.before_bytes"
#define RS_LOD_MEMORY_AFTER "result.memory.after_bytes"
#define RS_LOD_MEMORY_SCREEN "result.memory.screen"
#define RS_LOD_TRIANGLES_BEFORE "result.triangles.before"
#define RS_LOD_TRIANGLES_AFTER "result.triangles.after"
#define RS_LOD_CHAIN_SOURCE "result.chain_source"
#define RS_LOD_CRITERION_P "parameters.perceptual.criterion.p"
#define RS_LOD_CRITERION_Q "parameters.perceptual.criterion.q"
#define RS_LOD_MODEL_SCREEN_COVERAGE "result.model.screen_coverage"
#define RS_LOD_RENDERER "result.renderer"
#define RS_LOD_LEVEL0_TRIANGLES "result.levels[0].triangles"
#define RS_LOD_LEVELS "result.levels[]"                           /* one per level of the chain: */
#define RS_LOD_LEVELS_LEVEL "level"
#define RS_LOD_LEVELS_TRIANGLES "triangles"
#define RS_LOD_LEVELS_ERROR "error"
#define RS_LOD_LEVELS_METHOD "method"
#define RS_LOD_SCREENS "result.screens[]"                         /* one per screen: */
#define RS_LOD_SCREENS_NAME "name"
#define RS_LOD_SCREENS_PERCEPTUAL_LEVEL "perceptual_level"        /* the perceptual choice (not --no-perceptual): */
#define RS_LOD_SCREENS_PERCEPTUAL_TRIANGLES "perceptual_triangles"
#define RS_LOD_SCREENS_PERCEPTUAL_STATISTIC "perceptual_statistic"
#define RS_LOD_SCREENS_POI_TRIANGLES "poi_triangles"
#define RS_LOD_SCREENS_MESHOPT_TRIANGLES "rules.meshopt.triangles"
#define RS_LOD_SCREENS_PIXEL_ERROR_TRIANGLES "rules.pixel_error.triangles"
#define RS_LOD_SCREENS_SWITCH_DISTANCE "switch_distance_m"
#define RS_LOD_SCREENS_SWITCH_COVERAGE "switch_coverage"

/* ---- gaze.json, the table (tasks/gaze_report.c) ---- */
#define RS_GAZE_THRESHOLD "parameters.threshold"
#define RS_GAZE_ORIENTATIONS "parameters.orientations"
#define RS_GAZE_DISTANCES "result.distances_m"
#define RS_GAZE_DISTANCES_EACH "result.distances_m[]"
#define RS_GAZE_ECCENTRICITIES "result.eccentricities_deg"
#define RS_GAZE_ECCENTRICITIES_EACH "result.eccentricities_deg[]"
#define RS_GAZE_TRIANGLES "result.triangles"
#define RS_GAZE_RENDERER "result.renderer"
#define RS_GAZE_LEVEL_ROWS "result.level[]"                       /* a row of levels per distance */

/* ---- pop.json (tasks/pop_report.c) ---- */
#define RS_POP_RESULT "result"
#define RS_POP_MAX_RATING "result.max_rating"                     /* with a popping region */
#define RS_POP_REGION_COUNT "result.region_count"
#define RS_POP_DETECTION_SCORE "result.detection_score"
#define RS_POP_COVERAGE_SCORE "result.coverage_score"
#define RS_POP_RATING_SCORE "result.rating_score"
#define RS_POP_MAX_DELTA_E94 "result.max_delta_e94"
#define RS_POP_DISTANCE "result.distance_m"                       /* the asset form: */
#define RS_POP_DISTANCE_UNIT "result.distance_unit"
#define RS_POP_RENDERER "result.renderer"
#define RS_POP_REGIONS "result.regions[]"                         /* one per popping region: */
#define RS_POP_REGIONS_PIXELS "pixels"
#define RS_POP_REGIONS_SIGMA "sigma"
#define RS_POP_REGIONS_RATING "rating"
#define RS_POP_REGIONS_JND_MAX "jnd_max"
#define RS_POP_SWITCH_KEY "switch"                                /* the asset form with --decide: */
#define RS_POP_SWITCH "result.switch[]"
#define RS_POP_SWITCH_LEVEL "level"
#define RS_POP_SWITCH_SPEED "speed_dps"
#define RS_POP_SWITCH_DISTANCE "distance_m"
#define RS_POP_SWITCH_PIXEL_RULE "distance_m_pixel_rule"
#define RS_POP_SWITCH_STATUS "status"
#define RS_POP_SWITCH_PLOT "result.outputs.switch"

/* ---- every field, for the test that reads each run's report ---- */

typedef enum {
  RS_NUMBER, /* a number */
  RS_NUMBER_OR_NULL, /* a number, or null where it is not finite */
  RS_TEXT,   /* a string */
  RS_BOOL,   /* true or false */
  RS_LIST,   /* an array */
  RS_OBJECT  /* an object */
} report_kind;

/* the conditions of the fields not in every report */
#define RS_WHEN_VERIFY "held-out views (--verify-views)"
#define RS_WHEN_MATRIX "the size matrices (--matrix, --quick-matrix)"
#define RS_WHEN_RENDERED "the rendered choice (--model)"
#define RS_WHEN_BC "block compression (not --no-bc)"
#define RS_WHEN_COLOR "colour outputs (--outputs color, the default)"
#define RS_WHEN_PERCEPTUAL "the perceptual choice (not --no-perceptual)"
#define RS_WHEN_REGION "a popping region"
#define RS_WHEN_ASSET "the asset form (jnd pop MODEL)"
#define RS_WHEN_DECIDE "the asset form with --decide"

typedef struct {
  const char *path;
  report_kind kind;
  const char *when; /* NULL: in every report; else its RS_WHEN_* condition (absent otherwise) */
} report_field;

/* The fields of task's report ("texres", "pca", "diff", "render", "lod",
 * "gaze", "pop"; the name batch's table of commands uses), *n their count;
 * NULL for a task without a schema here. */
const report_field *report_schema(const char *task, int *n);

#endif
