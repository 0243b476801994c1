/* The schema of the task reports (see report_schema.h): paths into a
 * report, so that a reader says where a field is (RS_TEXRES_MEMORY_BEFORE)
 * instead of carrying code to find it, and the list of every field a
 * reader relies on, per task. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tasks/report_schema.h"

static int select_from(const cJSON *node, const char *path, const cJSON **out, int max, int found) {
  if (!node) return found;
  while (*path == '.') path++;
  if (!*path) {
    if (found < max) out[found] = node;
    return found + 1;
  }
  if (*path == '[') {
    const char *close = strchr(path, ']');
    if (!close || !cJSON_IsArray(node)) return found;
    if (close == path + 1) {
      const cJSON *e;
      cJSON_ArrayForEach(e, node) found = select_from(e, close + 1, out, max, found);
      return found;
    }
    char *end;
    long i = strtol(path + 1, &end, 10);
    if (end != close || i < 0) return found;
    return select_from(cJSON_GetArrayItem(node, (int)i), close + 1, out, max, found);
  }
  size_t n = strcspn(path, ".[");
  char key[128];
  if (n >= sizeof key || !cJSON_IsObject(node)) return found;
  memcpy(key, path, n);
  key[n] = 0;
  return select_from(cJSON_GetObjectItemCaseSensitive(node, key), path + n, out, max, found);
}

int jnd_json_select(const cJSON *root, const char *path, const cJSON **out, int max) {
  return select_from(root, path, out, max, 0);
}

double jnd_json_number(const cJSON *root, const char *path) {
  if (!path) return NAN;
  if (strncmp(path, "max:", 4) == 0) {
    /* the largest of the numbers the path selects */
    const cJSON *v[1024];
    int n = jnd_json_select(root, path + 4, v, 1024);
    double m = NAN;
    for (int i = 0; i < n && i < 1024; i++)
      if (cJSON_IsNumber(v[i]) && !(v[i]->valuedouble <= m)) m = v[i]->valuedouble;
    return m;
  }
  const cJSON *v[1];
  if (jnd_json_select(root, path, v, 1) != 1 || !cJSON_IsNumber(v[0])) return NAN;
  return v[0]->valuedouble;
}

#define F(path, kind) {path, kind, NULL}
#define IF(path, kind, when) {path, kind, when}

static const report_field TEXRES[] = {
    F(RS_TEXRES_MEMORY_BEFORE, RS_NUMBER),
    F(RS_TEXRES_MEMORY_AFTER, RS_NUMBER),
    F(RS_TEXRES_MEMORY_REDUCTION, RS_NUMBER),
    F(RS_TEXRES_MEMORY_BLOCK_BEFORE, RS_NUMBER),
    F(RS_TEXRES_MEMORY_BLOCK_AFTER, RS_NUMBER),
    F(RS_TEXRES_VIEWS_PASSES, RS_BOOL),
    F(RS_TEXRES_VIEWS_P, RS_LIST),
    F(RS_TEXRES_VIEWS_P_EACH, RS_NUMBER),
    F(RS_TEXRES_VIEWS_FRACTION_ABOVE, RS_NUMBER),
    IF(RS_TEXRES_VERIFY_PASSES, RS_BOOL, RS_WHEN_VERIFY),
    F(RS_TEXRES_CRITERION_P, RS_NUMBER),
    F(RS_TEXRES_CHOICE_P, RS_NUMBER),
    F(RS_TEXRES_CRITERION_Q, RS_NUMBER),
    F(RS_TEXRES_PPD, RS_NUMBER),
    F(RS_TEXRES_RENDERER, RS_TEXT),
    F(RS_TEXRES_MAPS, RS_OBJECT),
    F(RS_PATH(RS_TEXRES_MAPS, RS_TEXRES_MAPS_NAME), RS_TEXT),
    F(RS_PATH(RS_TEXRES_MAPS, RS_TEXRES_MAPS_ORIGINAL), RS_LIST),
    F(RS_PATH(RS_TEXRES_MAPS, RS_TEXRES_MAPS_CHOSEN), RS_LIST),
    F(RS_PATH(RS_TEXRES_MAPS, RS_TEXRES_MAPS_MIP_BOUND), RS_LIST),
    F(RS_PATH(RS_TEXRES_MAPS, RS_TEXRES_MAPS_EYE_BOUND), RS_LIST),
    F(RS_PATH(RS_TEXRES_MAPS, RS_TEXRES_MAPS_RESOLUTION_AT_P), RS_NUMBER_OR_NULL),
    F(RS_PATH(RS_TEXRES_MAPS, RS_TEXRES_MAPS_BLOCK_FORMAT), RS_TEXT),
    F(RS_PATH(RS_TEXRES_MAPS, RS_TEXRES_MAPS_IMAGE), RS_NUMBER),
    F(RS_PATH(RS_TEXRES_MAPS, RS_TEXRES_MAPS_SEARCHED), RS_BOOL),
    F(RS_PATH(RS_TEXRES_MAPS, RS_TEXRES_MAPS_CANDIDATES), RS_LIST),
    F(RS_PATH(RS_TEXRES_MAPS, RS_TEXRES_MAPS_SERIES), RS_LIST),
    F(RS_PATH(RS_TEXRES_MAPS, RS_TEXRES_MAPS_SERIES_EARLY), RS_LIST),
    F(RS_TEXRES_IMAGES, RS_OBJECT),
    F(RS_PATH(RS_TEXRES_IMAGES, RS_TEXRES_IMAGES_MAPS), RS_LIST),
    F(RS_PATH(RS_TEXRES_IMAGES, RS_TEXRES_IMAGES_ORIGINAL), RS_LIST),
    F(RS_PATH(RS_TEXRES_IMAGES, RS_TEXRES_IMAGES_CHOSEN), RS_LIST),
    F(RS_PATH(RS_TEXRES_IMAGES, RS_TEXRES_IMAGES_BLOCK_FORMAT), RS_TEXT),
    F(RS_PATH(RS_TEXRES_IMAGES, RS_TEXRES_IMAGES_BEFORE_RGBA8), RS_NUMBER),
    F(RS_PATH(RS_TEXRES_IMAGES, RS_TEXRES_IMAGES_AFTER_RGBA8), RS_NUMBER),
    IF(RS_TEXRES_MATRICES_PNG, RS_TEXT, RS_WHEN_MATRIX),
};

static const report_field PCA[] = {
    F(RS_PCA_MEMORY_BEFORE, RS_NUMBER),
    F(RS_PCA_MEMORY_AFTER, RS_NUMBER),
    F(RS_PCA_CHANNEL_COUNT, RS_NUMBER),
    F(RS_PCA_COMPONENTS_KEPT, RS_NUMBER),
    F(RS_PCA_KNEE, RS_NUMBER),
    IF(RS_PCA_RENDERED_PASS, RS_BOOL, RS_WHEN_RENDERED),
    IF(RS_PCA_RENDERED_P_CRITERION, RS_NUMBER, RS_WHEN_RENDERED),
    IF(RS_PCA_RENDERED_P_PER_VIEW, RS_LIST, RS_WHEN_RENDERED),
    F(RS_PCA_WIDTH, RS_NUMBER),
    F(RS_PCA_ENERGY_FRACTION, RS_NUMBER),
    F(RS_PCA_CUMULATIVE_ENERGY, RS_NUMBER),
    F(RS_PCA_COMPONENTS, RS_OBJECT),
    F(RS_PATH(RS_PCA_COMPONENTS, RS_PCA_COMPONENTS_DIVISOR), RS_NUMBER),
    F(RS_PCA_CHANNELS, RS_OBJECT),
    F(RS_PATH(RS_PCA_CHANNELS, RS_PCA_CHANNELS_NAME), RS_TEXT),
    F(RS_PATH(RS_PCA_CHANNELS, RS_PCA_CHANNELS_PSNR), RS_NUMBER_OR_NULL),
    IF(RS_PATH(RS_PCA_CHANNELS, RS_PCA_CHANNELS_PSNR_BC4), RS_NUMBER_OR_NULL, RS_WHEN_BC),
    IF(RS_PATH(RS_PCA_CHANNELS, RS_PCA_CHANNELS_PSNR_BC1), RS_NUMBER_OR_NULL, RS_WHEN_BC),
    IF(RS_PATH(RS_PCA_CHANNELS, RS_PCA_CHANNELS_PSNR_PLAIN_BC), RS_NUMBER_OR_NULL, RS_WHEN_BC),
    F(RS_PCA_TEXTURES, RS_OBJECT),
    F(RS_PATH(RS_PCA_TEXTURES, RS_PCA_TEXTURES_FILE), RS_TEXT),
    F(RS_PATH(RS_PCA_TEXTURES, RS_PCA_TEXTURES_WIDTH), RS_NUMBER),
    F(RS_PATH(RS_PCA_TEXTURES, RS_PCA_TEXTURES_HEIGHT), RS_NUMBER),
    F(RS_PATH(RS_PCA_TEXTURES, RS_PCA_TEXTURES_BITS), RS_NUMBER),
};

static const report_field DIFF[] = {
    F(RS_DIFF_P_DETECT, RS_NUMBER),   F(RS_DIFF_POOLING, RS_TEXT),  F(RS_DIFF_P_P50, RS_NUMBER),
    F(RS_DIFF_P_P99, RS_NUMBER),      F(RS_DIFF_JND_MEAN, RS_NUMBER), F(RS_DIFF_JND_P93, RS_NUMBER),
    F(RS_DIFF_JND_MAX, RS_NUMBER),    F(RS_DIFF_WIDTH, RS_NUMBER),  F(RS_DIFF_HEIGHT, RS_NUMBER),
    F(RS_DIFF_DISPLAY_NAME, RS_TEXT),
};

static const report_field RENDER[] = {
    F(RS_RENDER_RENDERER, RS_TEXT),
    F(RS_RENDER_VIEWS, RS_OBJECT),
    IF(RS_PATH(RS_RENDER_VIEWS, RS_RENDER_VIEWS_COLOR), RS_TEXT, RS_WHEN_COLOR),
};

static const report_field LOD[] = {
    F(RS_LOD_MEMORY_BEFORE, RS_NUMBER),
    F(RS_LOD_MEMORY_AFTER, RS_NUMBER),
    F(RS_LOD_MEMORY_SCREEN, RS_TEXT),
    F(RS_LOD_TRIANGLES_BEFORE, RS_NUMBER),
    F(RS_LOD_TRIANGLES_AFTER, RS_NUMBER),
    F(RS_LOD_CHAIN_SOURCE, RS_TEXT),
    F(RS_LOD_CRITERION_P, RS_NUMBER),
    F(RS_LOD_CRITERION_Q, RS_NUMBER),
    F(RS_LOD_MODEL_SCREEN_COVERAGE, RS_LIST),
    F(RS_LOD_RENDERER, RS_TEXT),
    F(RS_LOD_LEVEL0_TRIANGLES, RS_NUMBER),
    F(RS_LOD_LEVELS, RS_OBJECT),
    F(RS_PATH(RS_LOD_LEVELS, RS_LOD_LEVELS_LEVEL), RS_NUMBER),
    F(RS_PATH(RS_LOD_LEVELS, RS_LOD_LEVELS_TRIANGLES), RS_NUMBER),
    F(RS_PATH(RS_LOD_LEVELS, RS_LOD_LEVELS_ERROR), RS_NUMBER),
    F(RS_PATH(RS_LOD_LEVELS, RS_LOD_LEVELS_METHOD), RS_TEXT),
    F(RS_LOD_SCREENS, RS_OBJECT),
    F(RS_PATH(RS_LOD_SCREENS, RS_LOD_SCREENS_NAME), RS_TEXT),
    IF(RS_PATH(RS_LOD_SCREENS, RS_LOD_SCREENS_PERCEPTUAL_LEVEL), RS_NUMBER, RS_WHEN_PERCEPTUAL),
    IF(RS_PATH(RS_LOD_SCREENS, RS_LOD_SCREENS_PERCEPTUAL_TRIANGLES), RS_NUMBER,
       RS_WHEN_PERCEPTUAL),
    IF(RS_PATH(RS_LOD_SCREENS, RS_LOD_SCREENS_PERCEPTUAL_STATISTIC), RS_NUMBER_OR_NULL,
       RS_WHEN_PERCEPTUAL),
    F(RS_PATH(RS_LOD_SCREENS, RS_LOD_SCREENS_POI_TRIANGLES), RS_NUMBER),
    F(RS_PATH(RS_LOD_SCREENS, RS_LOD_SCREENS_MESHOPT_TRIANGLES), RS_NUMBER),
    F(RS_PATH(RS_LOD_SCREENS, RS_LOD_SCREENS_PIXEL_ERROR_TRIANGLES), RS_NUMBER),
    F(RS_PATH(RS_LOD_SCREENS, RS_LOD_SCREENS_SWITCH_DISTANCE), RS_LIST),
    F(RS_PATH(RS_LOD_SCREENS, RS_LOD_SCREENS_SWITCH_COVERAGE), RS_LIST),
};

static const report_field GAZE[] = {
    F(RS_GAZE_THRESHOLD, RS_NUMBER),     F(RS_GAZE_ORIENTATIONS, RS_NUMBER),
    F(RS_GAZE_DISTANCES, RS_LIST),       F(RS_GAZE_DISTANCES_EACH, RS_NUMBER),
    F(RS_GAZE_ECCENTRICITIES, RS_LIST),  F(RS_GAZE_ECCENTRICITIES_EACH, RS_NUMBER),
    F(RS_GAZE_TRIANGLES, RS_LIST),       F(RS_GAZE_RENDERER, RS_TEXT),
    F(RS_GAZE_LEVEL_ROWS, RS_LIST),
};

static const report_field POP[] = {
    F(RS_POP_RESULT, RS_OBJECT),
    IF(RS_POP_MAX_RATING, RS_NUMBER, RS_WHEN_REGION),
    F(RS_POP_REGION_COUNT, RS_NUMBER),
    F(RS_POP_DETECTION_SCORE, RS_NUMBER),
    F(RS_POP_COVERAGE_SCORE, RS_TEXT),
    F(RS_POP_RATING_SCORE, RS_TEXT),
    F(RS_POP_MAX_DELTA_E94, RS_NUMBER),
    IF(RS_POP_DISTANCE, RS_NUMBER, RS_WHEN_ASSET),
    IF(RS_POP_DISTANCE_UNIT, RS_TEXT, RS_WHEN_ASSET),
    IF(RS_POP_RENDERER, RS_TEXT, RS_WHEN_ASSET),
    IF(RS_POP_REGIONS, RS_OBJECT, RS_WHEN_REGION),
    IF(RS_PATH(RS_POP_REGIONS, RS_POP_REGIONS_PIXELS), RS_NUMBER, RS_WHEN_REGION),
    IF(RS_PATH(RS_POP_REGIONS, RS_POP_REGIONS_SIGMA), RS_NUMBER, RS_WHEN_REGION),
    IF(RS_PATH(RS_POP_REGIONS, RS_POP_REGIONS_RATING), RS_NUMBER, RS_WHEN_REGION),
    IF(RS_PATH(RS_POP_REGIONS, RS_POP_REGIONS_JND_MAX), RS_NUMBER, RS_WHEN_REGION),
    IF(RS_PATH(RS_POP_RESULT, RS_POP_SWITCH_KEY), RS_LIST, RS_WHEN_DECIDE),
    IF(RS_POP_SWITCH, RS_OBJECT, RS_WHEN_DECIDE),
    IF(RS_PATH(RS_POP_SWITCH, RS_POP_SWITCH_LEVEL), RS_NUMBER, RS_WHEN_DECIDE),
    IF(RS_PATH(RS_POP_SWITCH, RS_POP_SWITCH_SPEED), RS_NUMBER, RS_WHEN_DECIDE),
    IF(RS_PATH(RS_POP_SWITCH, RS_POP_SWITCH_DISTANCE), RS_NUMBER_OR_NULL, RS_WHEN_DECIDE),
    IF(RS_PATH(RS_POP_SWITCH, RS_POP_SWITCH_PIXEL_RULE), RS_NUMBER_OR_NULL, RS_WHEN_DECIDE),
    IF(RS_PATH(RS_POP_SWITCH, RS_POP_SWITCH_STATUS), RS_TEXT, RS_WHEN_DECIDE),
    IF(RS_POP_SWITCH_PLOT, RS_TEXT, RS_WHEN_DECIDE),
};

const report_field *report_schema(const char *task, int *n) {
  static const struct {
    const char *task;
    const report_field *fields;
    int n;
  } all[] = {
#define T(name, table) {name, table, (int)(sizeof table / sizeof table[0])}
      T("texres", TEXRES), T("pca", PCA), T("diff", DIFF), T("render", RENDER),
      T("lod", LOD),       T("gaze", GAZE), T("pop", POP),
#undef T
  };
  for (size_t i = 0; task && i < sizeof all / sizeof all[0]; i++)
    if (strcmp(all[i].task, task) == 0) {
      *n = all[i].n;
      return all[i].fields;
    }
  *n = 0;
  return NULL;
}
