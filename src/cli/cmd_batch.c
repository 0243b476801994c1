/* jnd batch: a manifest of assets, locally or as a Slurm job array, and the
 * merge of what the shards wrote. Parses, calls the library, prints. */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli.h"

static void help(void) {
  printf(
      "usage: jnd batch MANIFEST -o OUT [options]\n"
      "       jnd batch 'GLOB' --command CMD [--options 'OPTS'] -o OUT [options]\n"
      "       jnd batch MANIFEST -o OUT --slurm --shards N [slurm options]\n"
      "       jnd batch merge OUT\n"
      "\n"
      "Runs a jnd command on every asset of a library, each in a process of its own\n"
      "(a bad or crashing asset fails alone, the rest go on). MANIFEST is a CSV file\n"
      "with the header id,asset,command,options, or the same as JSON ([{\"id\": ...}]);\n"
      "asset paths are relative to the manifest, options are one shell-quoted string\n"
      "(never expanded). Commands: texres, pca (the asset is --model, or a map),\n"
      "diff (the asset is REF, TEST comes first in options), render.\n"
      "Each asset's outputs appear in OUT/<id>/ exactly as the command writes them,\n"
      "only once complete. A rerun skips complete assets (same row, same asset file,\n"
      "same jnd). See docs/batch.md.\n"
      "\n"
      "running:\n"
      "  -o, --output OUT    the output folder (created)\n"
      "  --shard I/N         run only rows r with r %% N == I (I from 0, as Slurm's array\n"
      "                      task ids): N shards together run every row once\n"
      "  --jobs N            assets at the same time (1); each gets CPUs / N threads\n"
      "  --threads N         threads per asset's command instead\n"
      "  --timeout S         kill an asset's command after S seconds (it fails)\n"
      "  --force             run complete assets again\n"
      "  --command CMD       with a GLOB instead of a manifest: the command for every\n"
      "  --options 'OPTS'    match, and its options; ids are the matches' names\n"
      "  --jnd PATH          the jnd program that runs each asset (default: this one)\n"
      "  --json FILE|-       a JSON report of the run (counts)\n"
      "  --quiet             nothing on stderr but errors (else one line per asset, or a\n"
      "                      progress bar on a terminal)\n"
      "\n"
      "merge (after every shard ran):\n"
      "  jnd batch merge OUT [--no-timings]   writes OUT/summary.json and summary.csv:\n"
      "                      per asset status, exit status, error, memory before/after,\n"
      "                      P(detect), the decision, seconds (left out with --no-timings,\n"
      "                      which makes n shards merge to the bytes of a single run)\n"
      "\n"
      "Slurm (a job array of N shards, then a merge job with afterok):\n"
      "  --slurm             write OUT/_batch/slurm/{array,merge}.sh and submit with sbatch\n"
      "  --dry-run           print the two scripts and the sbatch commands instead\n"
      "  --shards N          array tasks, one shard each (default 1)\n"
      "  --array-limit L     at most L tasks at once (--array=0-(N-1)%%L)\n"
      "  --cpus-per-task C   (1)     --mem SIZE (e.g. 8G)     --time LIMIT (e.g. 2:00:00)\n"
      "  --partition P       --account A     --gres G (e.g. gpu:1)     --job-name NAME\n"
      "  --sbatch OPT        one more sbatch option, e.g. --sbatch=--qos=low (repeatable)\n"
      "\n"
      "Exit status: 0 when the run went through (failed assets are recorded in OUT, not\n"
      "in the status); 2 for what stops the run: an unreadable or malformed manifest, a\n"
      "bad shard (3/2), OUT not writable (one line: jnd: FILE: problem).\n"
      "\n"
      "examples:\n"
      "  jnd batch assets.csv -o out --jobs 2 && jnd batch merge out && jnd report out\n"
      "  jnd batch 'models/*.glb' --command texres --options '--views 8' -o out\n"
      "  jnd batch assets.csv -o /shared/out --slurm --shards 64 --array-limit 16 \\\n"
      "      --cpus-per-task 4 --mem 8G --time 1:00:00\n");
}

typedef struct {
  int quiet, tty, width;
} progress_ctx;

static const char *status_word(const jnd_batch_event *e) {
  if (e->skipped) return "complete, skipped";
  switch (e->status) {
    case JND_ASSET_OK: return "ok";
    case JND_ASSET_ABOVE: return "ok, above the criterion";
    case JND_ASSET_FAILED: return "FAILED";
    default: return "pending";
  }
}

/* item 6 of issue 14: done / total, failures, elapsed, an estimate */
static void on_asset(void *user, const jnd_batch_event *e) {
  progress_ctx *pc = user;
  if (pc->quiet) return;
  double left = e->done > 0 ? e->elapsed_s * (e->total - e->done) / e->done : 0;
  if (pc->tty) {
    int width = 24, filled = e->total > 0 ? width * e->done / e->total : width;
    if (e->status == JND_ASSET_FAILED) /* a failure stays on screen above the bar */
      fprintf(stderr, "\r%-78s\rjnd batch: %s (%s) FAILED: %s\n", "", e->id, e->command, e->error ? e->error : "");
    fprintf(stderr, "\rbatch [");
    for (int k = 0; k < width; k++) fputc(k < filled ? '#' : '.', stderr);
    fprintf(stderr, "] %d/%d, %d failed, %.0f s, ~%.0f s left ", e->done, e->total, e->failed, e->elapsed_s, left);
    if (e->done == e->total) fputc('\n', stderr);
    fflush(stderr);
    return;
  }
  fprintf(stderr, "jnd batch: %d/%d %s (%s) %s", e->done, e->total, e->id, e->command, status_word(e));
  if (e->status == JND_ASSET_FAILED) {
    if (e->exit_status >= 0) fprintf(stderr, " (exit %d)", e->exit_status);
    fprintf(stderr, ": %s", e->error ? e->error : "");
  } else if (!e->skipped) {
    fprintf(stderr, " in %.1f s", e->seconds);
  }
  fprintf(stderr, "; %d failed, %.0f s elapsed, ~%.0f s left\n", e->failed, e->elapsed_s, left);
  fflush(stderr);
}

static int merge(int argc, char **argv) {
  cli_common common = {0};
  const char *out = NULL;
  int timings = 1;
  cli_args args = cli_args_start(argc, argv, "batch merge"), *ap = &args;
  args.i = 2;
  for (; args.i < argc && !args.bad; args.i++) {
    if (cli_help(ap)) {
      help();
      return EXIT_OK;
    } else if (cli_flag(ap, "--no-timings")) {
      timings = 0;
    } else if (cli_common_opt(ap, &common)) {
    } else if (!cli_operand(ap, &out, NULL, 1)) {
      return EXIT_BAD;
    }
  }
  if (args.bad) return EXIT_BAD;
  if (!out) return cli_bad("batch merge: needs the output folder (jnd batch merge OUT)");
  jnd_batch_totals t;
  if (jnd_batch_merge(out, timings, &t) != JND_OK) return cli_bad("%s", jnd_last_error());
  cli_info(&common, "jnd batch merge: wrote %s/summary.json and summary.csv: %d assets, %d ok, %d above, %d failed, "
           "%d pending\n", out, t.assets, t.ok, t.above, t.failed, t.pending);
  return EXIT_OK;
}

/* this very program, for the children and the job scripts */
static const char *self_path(char *buf, size_t n) {
  ssize_t k = readlink("/proc/self/exe", buf, n - 1);
  if (k <= 0) return NULL;
  buf[k] = 0;
  return buf;
}

static int run(int argc, char **argv) {
  if (argc >= 2 && strcmp(argv[1], "merge") == 0) return merge(argc, argv);
  cli_common common = {0};
  jnd_batch_params p;
  jnd_batch_defaults(&p);
  jnd_slurm_params sp;
  jnd_slurm_defaults(&sp);
  const char *manifest = NULL, *command = NULL, *options = NULL, *shard = NULL;
  const char *extra[64];
  int slurm = 0, dry = 0, shards_given = 0;
  char self[PATH_MAX];
  p.jnd_exe = self_path(self, sizeof self);
  sp.extra = extra;
  cli_args args = cli_args_start(argc, argv, "batch"), *ap = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    const char *v;
    if (cli_help(ap)) {
      help();
      return EXIT_OK;
    } else if (cli_opt(ap, "-o", &v) || cli_opt(ap, "--output", &v)) {
      p.out_dir = v;
    } else if (cli_opt(ap, "--shard", &v)) {
      shard = v;
    } else if (cli_opt(ap, "--jobs", &v)) {
      p.jobs = cli_int(ap, "--jobs", v, 1, 256);
    } else if (cli_opt(ap, "--threads", &v)) {
      p.threads = cli_int(ap, "--threads", v, 1, 1024);
    } else if (cli_opt(ap, "--timeout", &v)) {
      p.timeout_s = cli_double(ap, "--timeout", v, 0.001, 1e7);
    } else if (cli_flag(ap, "--force")) {
      p.force = 1;
    } else if (cli_opt(ap, "--command", &v)) {
      command = v;
    } else if (cli_opt(ap, "--options", &v)) {
      options = v;
    } else if (cli_opt(ap, "--jnd", &v)) {
      p.jnd_exe = v;
    } else if (cli_flag(ap, "--slurm")) {
      slurm = 1;
    } else if (cli_flag(ap, "--dry-run")) {
      dry = 1;
    } else if (cli_opt(ap, "--shards", &v)) {
      sp.shards = cli_int(ap, "--shards", v, 1, 100000);
      shards_given = 1;
    } else if (cli_opt(ap, "--array-limit", &v)) {
      sp.array_limit = cli_int(ap, "--array-limit", v, 1, 100000);
    } else if (cli_opt(ap, "--cpus-per-task", &v)) {
      sp.cpus_per_task = cli_int(ap, "--cpus-per-task", v, 1, 4096);
    } else if (cli_opt(ap, "--mem", &v)) {
      sp.mem = v;
    } else if (cli_opt(ap, "--time", &v)) {
      sp.time = v;
    } else if (cli_opt(ap, "--partition", &v)) {
      sp.partition = v;
    } else if (cli_opt(ap, "--account", &v)) {
      sp.account = v;
    } else if (cli_opt(ap, "--gres", &v)) {
      sp.gres = v;
    } else if (cli_opt(ap, "--job-name", &v)) {
      sp.job_name = v;
    } else if (cli_opt(ap, "--sbatch", &v)) {
      if (sp.nextra == 64) return cli_bad("batch: more than 64 --sbatch options");
      extra[sp.nextra++] = v;
    } else if (cli_common_opt(ap, &common)) {
    } else if (!cli_operand(ap, &manifest, NULL, 1)) {
      return EXIT_BAD;
    }
  }
  if (args.bad) return EXIT_BAD;
  if (!manifest) return cli_bad("batch: needs a manifest (or a glob with --command): jnd batch --help");
  if (!p.out_dir) return cli_bad("batch: needs the output folder: -o OUT");
  if (options && !command) return cli_bad("batch: --options goes with --command and a glob (a manifest has its own)");
  if (shard && jnd_batch_shard_parse(shard, &p.shard, &p.shards) != JND_OK) return cli_bad("batch: %s", jnd_last_error());
  if ((dry || shards_given) && !slurm) return cli_bad("batch: --dry-run and --shards go with --slurm (a local run takes --shard I/N)");
  if (slurm && shard) return cli_bad("batch: --slurm makes the shards itself (--shards N); --shard is for one run");
  if (!p.jnd_exe) return cli_bad("batch: cannot find this program's path (/proc/self/exe): give --jnd PATH");
  jnd_batch_manifest m;
  if (jnd_batch_manifest_read(manifest, command, options, &m) != JND_OK) return cli_bad("%s", jnd_last_error());
  int bad_rows = 0;
  for (int i = 0; i < m.nrows; i++) bad_rows += m.rows[i].error != NULL;
  /* the manifest and its assets are inputs: the output folder may not hold
   * them (each asset's command checks its own outputs too) */
  jnd_output *outw = NULL;
  const char *json_out = common.json_path;
  int rc = cli_out_open(&outw);
  if (rc == EXIT_OK) rc = cli_out_inputs(outw, &manifest, 1);
  for (int i = 0; i < m.nrows && rc == EXIT_OK; i++) {
    char full[4200];
    const char *slash = strrchr(manifest, '/');
    if (m.rows[i].asset[0] == '/' || !slash) snprintf(full, sizeof full, "%s", m.rows[i].asset);
    else snprintf(full, sizeof full, "%.*s/%s", (int)(slash - manifest), manifest, m.rows[i].asset);
    const char *one[] = {full};
    rc = cli_out_inputs(outw, one, 1);
  }
  if (rc == EXIT_OK && jnd_output_check_dir(outw, p.out_dir) != JND_OK) rc = cli_lib_error();
  if (rc == EXIT_OK) rc = cli_out_file(outw, common.json_path, &json_out);
  if (rc != EXIT_OK) {
    jnd_batch_manifest_free(&m);
    return cli_out_end(outw, rc);
  }
  if (slurm) {
    char *a = NULL, *b = NULL;
    int scripts = jnd_slurm_scripts(&m, command, options, &p, &sp, &a, &b) == JND_OK;
    if (!scripts) rc = cli_bad("%s", jnd_last_error());
    /* rows that cannot run are said now; they fail in their shard too */
    for (int i = 0; scripts && i < m.nrows && !common.quiet; i++)
      if (m.rows[i].error) cli_error("%s", m.rows[i].error);
    if (!scripts) {
    } else if (dry) {
      printf("# ---- %s/_batch/slurm/array.sh ----\n%s\n# ---- %s/_batch/slurm/merge.sh ----\n%s\n", p.out_dir, a,
             p.out_dir, b);
      printf("# ---- submitted with ----\n# sbatch --parsable %s/_batch/slurm/array.sh   -> ARRAY_ID\n"
             "# sbatch --parsable --dependency=afterok:ARRAY_ID %s/_batch/slurm/merge.sh\n", p.out_dir, p.out_dir);
    } else {
      char ja[64], jm[64];
      if (jnd_slurm_submit(p.out_dir, a, b, ja, jm, sizeof ja) != JND_OK) rc = cli_bad("%s", jnd_last_error());
      else {
        printf("%s %s\n", ja, jm);
        cli_info(&common, "jnd batch: submitted job array %s (%d shards of %d assets) and merge job %s (afterok)\n",
                 ja, sp.shards, m.nrows, jm);
      }
    }
    free(a);
    free(b);
    jnd_batch_manifest_free(&m);
    return cli_out_end(outw, rc);
  }
  progress_ctx pc = {.quiet = common.quiet, .tty = isatty(2)};
  p.progress = on_asset;
  p.progress_user = &pc;
  jnd_batch_totals t;
  jnd_status s = jnd_batch_run(&m, &p, &t);
  if (s != JND_OK) rc = cli_bad("%s", jnd_last_error());
  else {
    cli_info(&common, "jnd batch: %d assets in this shard: %d ran, %d complete before, %d failed%s; "
             "jnd batch merge %s gathers every shard\n", t.assets, t.ran, t.skipped, t.failed,
             bad_rows ? " (rows with errors among them)" : "", p.out_dir);
    char *text = common.json_path ? jnd_batch_run_report(&m, &p, &t) : NULL;
    if (common.json_path && !text) rc = cli_bad("out of memory writing the JSON report");
    else if (text && strcmp(common.json_path, "-") == 0) rc = cli_report_print(text, common.json_path);
    else if (text && jnd_write_file_atomic(json_out, text, strlen(text)) != JND_OK) rc = cli_lib_error();
    free(text);
  }
  jnd_batch_manifest_free(&m);
  return cli_out_end(outw, rc);
}

const jnd_command jnd_cmd_batch = {"batch", "a library of assets: a manifest, shards, Slurm, merge (docs/batch.md)", run};
