/* The small parameters a test runs a task with, built once for every test
 * that runs it: tests/e2e/task_runs.c (the library against the command, so
 * they must be the command line's in task_runs.c's list) and
 * tests/unit/test_report_schema.c. The public header only. */
#ifndef JND_TEST_TASK_PARAMS_H
#define JND_TEST_TASK_PARAMS_H

#include "jnd.h"

/* jnd lod MODEL --screens 320x240 --views 1 --map-size 64 --surface-samples 4096
 * --judge-views 1 --max-px 96 --tolerance 0.5 --far-coverage 0.05; screen
 * (the caller's) holds the one screen p points at. */
static inline jnd_status task_lod_params(jnd_lod_run_params *p, jnd_poi_screen *screen) {
  jnd_lod_run_defaults(p);
  jnd_status st = jnd_poi_screen_parse("320x240", screen);
  p->poi.screens = screen;
  p->poi.nscreens = 1;
  p->poi.views = 1;
  p->poi.surface_samples = 4096;
  p->run.map_size = 64;
  p->sw.judge.views.sampling.count = 1;
  p->sw.max_px = 96;
  p->sw.tolerance = 0.5;
  p->sw.far_coverage = 0.05;
  return st;
}

#endif
