/* Each task as one library call, with no command line: a program that links
 * libjnd.so (the public header only) runs `jnd_<task>_run` with the
 * parameters a command line names, and prints the report it returns.
 * tests/e2e/task_runs_slow.sh runs the same task through `jnd` and checks that
 * the two reports are byte-identical (issue 24: every report is produced by
 * the library).
 *
 *   task_runs texres MODEL OUTDIR     (--views 2 --size 96x96 --map-size 128
 *                                      --samples 1 --confirm 0 --min-size 16)
 *   task_runs pca builtin OUTDIR      (--model builtin --material builtin --map-size 128
 *                                      --views 2 --size 96x96 --anisotropy 1 --no-bc)
 *   task_runs pca - OUTDIR MAP...     (MAP... --psnr 40 --write-maps)
 *   task_runs calibrate CSV CAL.json  (--folds 2 --map-size 128 --views 2 --size 96x96)
 *   task_runs lod MODEL OUTDIR        (--screens 320x240 --views 1 --map-size 64
 *                                      --surface-samples 4096 --judge-views 1 --max-px 96
 *                                      --tolerance 0.5 --far-coverage 0.05)
 *   task_runs render MODEL OUTDIR     (--views 2 --size 64x48 --map-size 64
 *                                      --outputs color,depth,mask,motion,mip)
 *   task_runs diff REF TEST MAP       (--display phone --fail-above 0.01 --map MAP)
 *   task_runs csf DATA OUT.csv        (--dataset colorfest --dataset hansen2009 --every 8
 *                                      --cross-validate --fit-only sensitivity --iterations 2)
 *   task_runs gaze MODEL OUTDIR       (--map-size 32 --orientations 2 --distances 20,40,80
 *                                      --eccentricities 0,10,30 --min-px 48 --max-px 64)
 *   task_runs gaze-observers MODEL OUTDIR (--map-size 32 --sizes 3,8 --eccentricities 0,30
 *                                      --orientations 1 --answers 5 --min-px 32 --max-px 64)
 *   task_runs gaze-fit CSV OUTDIR     (gaze fit CSV -o OUTDIR)
 *   task_runs pop NEW EXPECTED OUTDIR (--maps --fail-above 0.5 --max-regions 3)
 *   task_runs pop MODEL OUTDIR        (--size 64x64 --views 1 --map-size 64 --errors 0.1
 *                                      --speeds 0,240 --tolerance 0.3) */
#include <stdio.h>
#include <string.h>

#include "jnd.h"
#include "../task_params.h"

static int texres(const char *model, const char *out_dir) {
  jnd_texres_params p;
  jnd_texres_defaults(&p);
  p.judge.views.sampling.count = 2;
  p.judge.views.render.width = p.judge.views.render.height = 96;
  p.judge.views.render.samples = 1;
  p.run.map_size = 128;
  p.confirm_rounds = 0;
  p.min_size = 16;
  jnd_texres_result *r = NULL;
  if (jnd_texres_run(model, &p, out_dir, &r) != JND_OK) {
    fprintf(stderr, "jnd: %s\n", jnd_last_error());
    return 2;
  }
  fputs(r->report, stdout);
  int rc = r->passes ? 0 : 1;
  jnd_texres_result_free(r);
  return rc;
}

static int pca(const char *model, const char *out_dir, const char *const *maps, int nmaps) {
  jnd_pca_params p;
  jnd_pca_defaults(&p);
  if (nmaps) {
    p.maps = maps;
    p.nmaps = nmaps;
    p.rule = JND_PCA_RULE_PSNR;
    p.psnr_db = 40;
    p.write_maps = 1;
    model = NULL;
  } else {
    p.material = "builtin";
    p.render.builtin_map_size = p.run.map_size = 128;
    p.render.judge.views.sampling.count = 2;
    p.render.judge.views.render.width = p.render.judge.views.render.height = 96;
    p.render.judge.views.render.anisotropy = 1;
    p.block_compression = 0;
  }
  jnd_pca_result *r = NULL;
  if (jnd_pca_run(model, &p, out_dir, &r) != JND_OK) {
    fprintf(stderr, "jnd: %s\n", jnd_last_error());
    return 2;
  }
  fputs(r->report, stdout);
  jnd_pca_result_free(r);
  return 0;
}

static int calibrate(const char *csv, const char *out_path) {
  jnd_calibrate_run_params p;
  jnd_calibrate_run_defaults(&p);
  p.fit.folds = 2;
  p.run.map_size = 128;
  p.judge.views.sampling.count = 2;
  p.judge.views.render.width = p.judge.views.render.height = 96;
  jnd_calibrate_result *r = NULL;
  if (jnd_calibrate_run(csv, &p, out_path, &r) != JND_OK) {
    fprintf(stderr, "jnd: %s\n", jnd_last_error());
    return 2;
  }
  fputs(r->report, stdout);
  jnd_calibrate_result_free(r);
  return 0;
}

static int lod(const char *model, const char *out_dir) {
  jnd_lod_run_params p;
  jnd_poi_screen screen;
  if (task_lod_params(&p, &screen) != JND_OK) return 2;
  jnd_lod_result *r = NULL;
  if (jnd_lod_run(model, &p, out_dir, &r) != JND_OK) {
    fprintf(stderr, "jnd: %s\n", jnd_last_error());
    return 2;
  }
  fputs(r->report, stdout);
  jnd_lod_result_free(r);
  return 0;
}

static int render(const char *model, const char *out_dir) {
  jnd_render_params p;
  jnd_render_defaults(&p);
  p.views.sampling.count = 2;
  p.views.render.width = 64;
  p.views.render.height = 48;
  p.run.map_size = 64;
  p.outputs = JND_RENDER_COLOR | JND_RENDER_DEPTH | JND_RENDER_MASK | JND_RENDER_MOTION | JND_RENDER_MIP;
  jnd_render_result *r = NULL;
  if (jnd_render_run(model, &p, out_dir, &r) != JND_OK) {
    fprintf(stderr, "jnd: %s\n", jnd_last_error());
    return 2;
  }
  fputs(r->report, stdout);
  jnd_render_result_free(r);
  return 0;
}

static int diff(const char *ref, const char *test, const char *map) {
  jnd_diff_params p;
  jnd_diff_defaults(&p);
  if (jnd_display_preset("phone", &p.model.display) != JND_OK) return 2;
  p.fail_above = 0.01;
  p.map_path = map;
  jnd_diff_result *r = NULL;
  if (jnd_diff_run(ref, test, &p, &r) != JND_OK) {
    fprintf(stderr, "jnd: %s\n", jnd_last_error());
    return 2;
  }
  fputs(r->report, stdout);
  int rc = r->above ? 1 : 0;
  jnd_diff_result_free(r);
  return rc;
}

static int csf(const char *data, const char *out_csv) {
  jnd_csf_run_params p;
  jnd_csf_run_defaults(&p);
  p.options.cross_validate = 1;
  p.options.fit_mask_set = 1;
  p.options.fit_mask = 1ull << jnd_model_constant_find("sensitivity");
  p.options.max_iterations = 2;
  const char *only[] = {"colorfest", "hansen2009"};
  p.datasets = only;
  p.ndatasets = 2;
  p.every = 8;
  jnd_csf_run_result *r = NULL;
  if (jnd_csf_run(data, &p, out_csv, &r) != JND_OK) {
    fprintf(stderr, "jnd: %s\n", jnd_last_error());
    return 2;
  }
  fputs(r->report, stdout);
  jnd_csf_run_result_free(r);
  return 0;
}

static int gaze(const char *mode, const char *input, const char *out_dir) {
  jnd_gaze_run_params p;
  jnd_gaze_run_defaults(&p);
  p.run.map_size = 32;
  const char *models[1] = {input};
  if (strcmp(mode, "gaze") == 0) {
    static const double dist[] = {20, 40, 80}, ecc[] = {0, 10, 30};
    p.table.orientations = 2;
    p.table.distances_m = dist;
    p.table.ndistances = 3;
    p.table.eccentricities_deg = ecc;
    p.table.neccentricities = 3;
    p.table.min_px = 48;
    p.table.max_px = 64;
  } else if (strcmp(mode, "gaze-observers") == 0) {
    static const double sizes[] = {3, 8}, ecc[] = {0, 30};
    p.mode = JND_GAZE_RUN_OBSERVERS;
    p.models = models;
    p.nmodels = 1;
    input = NULL;
    p.observers.sizes_deg = sizes;
    p.observers.nsizes = 2;
    p.observers.eccentricities_deg = ecc;
    p.observers.neccentricities = 2;
    p.observers.orientations = 1;
    p.observers.answers = 5;
    p.observers.min_px = 32;
    p.observers.max_px = 64;
  } else {
    p.mode = JND_GAZE_RUN_FIT;
  }
  jnd_gaze_run_result *r = NULL;
  if (jnd_gaze_run(input, &p, out_dir, &r) != JND_OK) {
    fprintf(stderr, "jnd: %s\n", jnd_last_error());
    return 2;
  }
  fputs(r->report, stdout);
  jnd_gaze_run_result_free(r);
  return 0;
}

static int pop(const char *model, const char *new_frame, const char *expected, const char *out_dir) {
  jnd_pop_run_params p;
  jnd_pop_run_defaults(&p);
  static const double errors[] = {0.1}, speeds[] = {0, 240};
  if (model) {
    p.asset.views.render.width = p.asset.views.render.height = 64;
    p.asset.views.sampling.count = 1;
    p.asset.builtin_map_size = 64;
    p.asset.chain.errors = errors;
    p.asset.chain.nerrors = 1;
    p.asset.decide = 1;
    p.asset.speeds = speeds;
    p.asset.nspeeds = 2;
    p.asset.search.tolerance = 0.3;
  } else {
    p.frames.actual = new_frame;
    p.frames.expected = expected;
    p.maps = 1;
    p.fail_above = 0.5;
    p.max_regions = 3;
  }
  jnd_pop_run_result *r = NULL;
  if (jnd_pop_run(model, &p, out_dir, &r) != JND_OK) {
    fprintf(stderr, "jnd: %s\n", jnd_last_error());
    return 2;
  }
  fputs(r->report, stdout);
  int rc = r->above ? 1 : 0;
  jnd_pop_run_result_free(r);
  return rc;
}

int main(int argc, char **argv) {
  if (argc == 4 && strcmp(argv[1], "calibrate") == 0) return calibrate(argv[2], argv[3]);
  if (argc == 4 && strcmp(argv[1], "texres") == 0) return texres(argv[2], argv[3]);
  if (argc >= 4 && strcmp(argv[1], "pca") == 0)
    return pca(argv[2], argv[3], (const char *const *)argv + 4, argc - 4);
  if (argc == 4 && strcmp(argv[1], "lod") == 0) return lod(argv[2], argv[3]);
  if (argc == 4 && strcmp(argv[1], "render") == 0) return render(argv[2], argv[3]);
  if (argc == 5 && strcmp(argv[1], "diff") == 0) return diff(argv[2], argv[3], argv[4]);
  if (argc == 4 && strcmp(argv[1], "csf") == 0) return csf(argv[2], argv[3]);
  if (argc == 4 && strncmp(argv[1], "gaze", 4) == 0) return gaze(argv[1], argv[2], argv[3]);
  if (argc == 4 && strcmp(argv[1], "pop") == 0) return pop(argv[2], NULL, NULL, argv[3]);
  if (argc == 5 && strcmp(argv[1], "pop") == 0) return pop(NULL, argv[2], argv[3], argv[4]);
  fprintf(stderr, "usage: task_runs TASK INPUT OUTDIR\n");
  return 2;
}
