/* jnd diff REF TEST — how likely a viewer notices the difference. */
#include <limits.h>
#include <malloc.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"

static void help(void) {
  printf(
      "usage: jnd diff REF TEST [options]\n"
      "\n"
      "Predicts, per pixel, how many just-noticeable differences (JND) separate TEST\n"
      "from REF as a viewer sees them on a display, and the probability that a viewer\n"
      "notices (000 eq. 4), pooled over the image (default: 93rd percentile, 000 §6).\n"
      "The viewing task (--task): by default the viewer sees the two images side by\n"
      "side, for as long as they like, as a user of a product sees one or the other;\n"
      "--task flicker predicts a viewer who toggles them in place (stricter).\n"
      "Inputs: PNG (8/16-bit, sRGB), JPEG, Radiance HDR, OpenEXR (linear, cd/m2 x\n"
      "--exr-scale). Alpha is composited over the display's black.\n"
      "\n"
      "%s"
      "\n"
      "model inputs:\n"
      "  --motion FILE.exr   per-pixel screen displacement, pixels per frame (2 channels)\n"
      "  --fps N             frames per second for --motion (default 60)\n"
      "  --weights FILE      per-pixel weights (first channel) multiplying the difference map\n"
      "  --gaze X,Y          fixation point in pixels, inside the image: sensitivity falls\n"
      "                      with eccentricity (default: every pixel is seen foveally)\n"
      "\n"
      "outputs:\n"
      "  --map FILE.exr      float JND per pixel\n"
      "  --heatmap FILE.png  JND over a dimmed grey copy of REF on a log scale from 0.1\n"
      "                      JND, with a colour bar (small images are magnified)\n"
      "  --heatmap-max J     JND at the top of the heatmap's scale (default: the 99.9th\n"
      "                      percentile rounded up to 1, 2 or 5 x 10^k, at least 2)\n"
      "  --pool P            pooling for p_detect: p93 (default), pNN, max, mean, minkowski\n"
      "  --calibration FILE  a `jnd calibrate` file: its JND transform, slope and percentile\n"
      "  --fail-above P      exit 1 when the pooled probability exceeds P (render gating)\n"
      "%s"
      "\n"
      "Paper numbers: 000 is Wolski et al. 2019 (pooling, psychometric function); the\n"
      "model is Schwarz & Stamminger 2009 (004); include/jnd.h lists them all.\n"
      "Exit status: 0, 1 when above --fail-above, 2 for bad input.\n",
      cli_display_help, cli_common_help);
}

/* One diff is one short process whose blocks (image planes, pyramid levels,
 * band planes: 0.5–25 MB each) are freed and asked for again: glibc would
 * map each of them by itself, unmap it when freed and map fresh pages for
 * the next, which the kernel zeroes again. Blocks up to 32 MB (glibc's
 * largest mmap threshold; a 1920×1080 plane is 8.3 MB, its three channels
 * 25 MB) now come from the heap, which is never trimmed: a freed block's
 * pages, already mapped in, serve the next. 1920×1080 pair: total
 * in-process time −5% (docs/speed.md, "Sixth pass: the process"); peak
 * RSS unchanged (the peak is where the most is held at once). Only here:
 * the long commands (texres, lod, pop) hold and free other patterns. */
/*
 * And the heap grows 64 MiB at a time (M_TOP_PAD; glibc's default is 128
 * KiB). Each growth — brk on the main thread's heap, mprotect on the second
 * decoding thread's — and each MADV_HUGEPAGE of the new pages takes the
 * process's mmap lock for writing, which waits for any populating call of
 * the other thread (jnd_alloc's MADV_POPULATE_WRITE holds the lock for
 * reading while it zeroes a huge page): the two threads took turns. A
 * 1920×1080 diff grew its heaps in 36 brk and 48 mprotect calls, now 3 and
 * 18 (`strace -f -c`); 31 alternated runs, median wall 0.199 → 0.177 s
 * (docs/speed.md "Eleventh pass"). The pad is address space: pages are
 * mapped in only where a block is populated or written, and the peak RSS
 * is unchanged. */
static void keep_freed_memory(void) {
#if defined(__GLIBC__) && defined(M_MMAP_THRESHOLD) && defined(M_TRIM_THRESHOLD)
  (void)mallopt(M_MMAP_THRESHOLD, 32 << 20);
  (void)mallopt(M_TRIM_THRESHOLD, INT_MAX);
#endif
#if defined(__GLIBC__) && defined(M_TOP_PAD)
  (void)mallopt(M_TOP_PAD, 64 << 20);
#endif
  /* And one heap for both threads (M_ARENA_MAX). glibc gave the second
   * decoding thread a heap of its own, mapped by itself: jnd_alloc advises
   * only the whole huge pages inside each of its blocks, so most of that
   * thread's image (its codes, its pyramid's levels) was populated in 4 KiB
   * pages, several times slower here than the main heap's huge pages, and
   * its decoding ended 5–10 ms after the main thread's (the main thread
   * waiting). 20 interleaved runs each, stage times inside the process
   * (docs/speed.md "Eleventh pass"): both images decoded at 44.4 ms
   * instead of 48.3 (medians), the run 158.6 ms instead of 164.3; the peak
   * RSS is 65–74 MB either way. The two threads' few dozen mallocs now
   * share a lock. */
#if defined(__GLIBC__) && defined(M_ARENA_MAX)
  (void)mallopt(M_ARENA_MAX, 1);
#endif
}

static int run(int argc, char **argv) {
  cli_common common = {0};
  jnd_diff_params p;
  jnd_diff_defaults(&p);
  jnd_model_params *mp = &p.model;
  const char *paths[2] = {0}, *pool_name = NULL;   /* NULL: the run's default (p93) */
  int npaths = 0;
  cli_display disp;
  cli_display_init(&disp);
  cli_args args = cli_args_start(argc, argv, "diff"), *ap = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    const char *v;
    if (cli_help(ap)) {
      help();
      return EXIT_OK;
    } else if (cli_display_opt(ap, &disp)) {
    } else if (cli_opt(ap, "--motion", &v)) {
      p.motion_path = v;
    } else if (cli_opt(ap, "--fps", &v)) {
      mp->fps = cli_double(ap, "--fps", v, 1, 1000);
    } else if (cli_opt(ap, "--weights", &v)) {
      p.weights_path = v;
    } else if (cli_opt(ap, "--gaze", &v)) {
      cli_pair(ap, "--gaze", v, &mp->gaze_x, &mp->gaze_y);
      mp->has_gaze = 1;
    } else if (cli_opt(ap, "--pool", &v)) {
      pool_name = v;
    } else if (cli_opt(ap, "--calibration", &v)) {
      p.calibration_path = v;
    } else if (cli_opt(ap, "--map", &v)) {
      p.map_path = v;
    } else if (cli_opt(ap, "--heatmap", &v)) {
      p.heatmap_path = v;
    } else if (cli_opt(ap, "--heatmap-max", &v)) {
      p.heatmap_max = cli_double(ap, "--heatmap-max", v, 0.2, 1e4);
    } else if (cli_opt(ap, "--fail-above", &v)) {
      p.fail_above = cli_double(ap, "--fail-above", v, 0, 1);
    } else if (cli_common_opt(ap, &common)) {
    } else if (!cli_operand(ap, paths, &npaths, 2)) {
      return EXIT_BAD;
    }
  }
  if (args.bad) return EXIT_BAD;
  if (npaths != 2) {
    cli_error("diff: needs two images, REF and TEST (jnd diff --help)");
    return EXIT_BAD;
  }
  mp->display = cli_display_get(&disp);
  mp->threads = common.threads;
  p.exr_scale_given = cli_display_exr_scale_given(&disp);
  if (pool_name && jnd_pooling_parse(pool_name, &p.pool) != JND_OK) {
    cli_error("diff: --pool: %s", jnd_last_error());
    return EXIT_BAD;
  }
  cli_run_options(&p.run, &common, 0);
  jnd_diff_result *R = NULL;
  keep_freed_memory();
  /* each thread on a CPU of its own: diff starts no threads but OpenMP's
   * (jnd.h jnd_threads_pin; docs/speed.md "Twelfth pass") */
  (void)jnd_threads_pin(mp->threads);
  if (jnd_diff_run(paths[0], paths[1], &p, &R) != JND_OK) return cli_lib_error();
  int rc = cli_report_print(R->report, common.json_path);
  const jnd_diff_stats *st = &R->stats;
  cli_info(&common, "P(detect) %s = %.3f   (p50 %.3f, p99 %.3f, max %.3f)   JND p93 %.2f, max %.2f   %dx%d, %.2f s\n",
           R->pooling, st->p_detect, st->p_p50, st->p_p99, st->p_max, st->jnd_p93, st->jnd_max, R->width, R->height,
           R->total_s);
  if (R->above) cli_info(&common, "above --fail-above %.3f\n", p.fail_above);
  if (rc == EXIT_OK && R->above) rc = EXIT_ABOVE;
  jnd_diff_result_free(R);
  return rc;
}

const jnd_command jnd_cmd_diff = {"diff", "how likely a viewer notices the difference between two images", run};
