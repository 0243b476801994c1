/* The batch layer's parts that need no child process: shell words, manifest
 * rows and their errors, shards, JSON paths, escapes, and the merge of what
 * shards recorded (the runs themselves are end-to-end: tests/e2e/batch.sh). */
#include <sys/stat.h>
#include <unistd.h>

#include "test.h"

#include "batch/batch.h"
#include "jnd.h"

static int split_is(const char *s, int n, const char *const *want) {
  int argc;
  char **argv;
  if (jnd_shell_split(s, &argc, &argv) != JND_OK) return 0;
  int ok = argc == n;
  for (int i = 0; ok && i < n; i++) ok = strcmp(argv[i], want[i]) == 0;
  jnd_words_free(argc, argv);
  return ok;
}

TEST(options_split_into_words_as_a_shell_splits_them) {
  CHECK(split_is("--views 8  --maps body/baseColor", 4, (const char *[]){"--views", "8", "--maps", "body/baseColor"}));
  CHECK(split_is("'a b' \"c d\" e\\ f", 3, (const char *[]){"a b", "c d", "e f"}));
  CHECK(split_is("--maps='*/baseColor' x''y \"\"", 3, (const char *[]){"--maps=*/baseColor", "xy", ""}));
  CHECK(split_is("\"say \\\"hi\\\" \\\\ \\n\"", 1, (const char *[]){"say \"hi\" \\ \\n"}));
  CHECK(split_is("   ", 0, NULL));
  CHECK(split_is("a\tb\nc", 3, (const char *[]){"a", "b", "c"}));
}

TEST(options_that_a_shell_would_expand_are_refused_not_passed_on) {
  const char *bad[] = {"--env $HOME/x.hdr", "*.png", "a;b", "a | b", "a > out", "~/x", "--x \"$HOME\"", "`ls`",
                       "'unclosed", "\"unclosed", "trailing\\", "#comment", "a(b)", "x?"};
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    int argc = 7;
    char **argv = (char **)1;
    CHECK_STATUS(jnd_shell_split(bad[i], &argc, &argv), JND_ERR_FORMAT);
    CHECK(argc == 0 && argv == NULL);
    CHECK(strncmp(jnd_last_error(), "options: ", 9) == 0);
  }
  /* quoted, the same characters are plain text */
  CHECK(split_is("'$HOME' '*.png' 'a;b' \\~", 4, (const char *[]){"$HOME", "*.png", "a;b", "~"}));
}

TEST(joined_words_split_back_to_themselves) {
  char *words[] = {"plain", "with space", "it's", "\"q\"", "", "$HOME", "a\\b", "*", "new\nline"};
  char *line = jnd_shell_join(9, words);
  CHECK(line != NULL);
  int argc;
  char **argv;
  CHECK_OK(jnd_shell_split(line, &argc, &argv));
  CHECK(argc == 9);
  for (int i = 0; i < argc && i < 9; i++) CHECK(strcmp(argv[i], words[i]) == 0);
  jnd_words_free(argc, argv);
  free(line);
}

static jnd_batch_manifest csv(const char *text) {
  jnd_batch_manifest m;
  jnd_status s = jnd_batch_manifest_parse_csv("assets.csv", text, strlen(text), &m);
  if (s != JND_OK) memset(&m, 0, sizeof m);
  return m;
}

static const char *err(const jnd_batch_manifest *m, int row) { return m->rows[row].error ? m->rows[row].error : ""; }

TEST(a_csv_manifest_gives_one_row_per_asset_with_its_words) {
  jnd_batch_manifest m = csv("id,asset,command,options\n"
                             "helmet,models/helmet.glb,texres,\"--views 8 --maps 'body/baseColor'\"\n"
                             "\n"
                             "pair,ref.png,diff,test.png\r\n"
                             "set,builtin,pca,\n");
  CHECK(m.nrows == 3);
  if (m.nrows == 3) {
    CHECK(strcmp(m.rows[0].id, "helmet") == 0 && strcmp(m.rows[0].asset, "models/helmet.glb") == 0);
    CHECK(m.rows[0].argc == 4 && strcmp(m.rows[0].argv[3], "body/baseColor") == 0);
    CHECK(m.rows[0].line == 2 && m.rows[1].line == 4 && m.rows[2].line == 5); /* lines of the file */
    CHECK(!m.rows[0].error && !m.rows[1].error && !m.rows[2].error);
    CHECK(m.rows[2].argc == 0);
  }
  jnd_batch_manifest_free(&m);
  /* columns in any order, options optional */
  m = csv("command,id,asset\ntexres,a,builtin\n");
  CHECK(m.nrows == 1 && !m.rows[0].error && strcmp(m.rows[0].command, "texres") == 0 && m.rows[0].options[0] == 0);
  jnd_batch_manifest_free(&m);
}

TEST(each_bad_row_fails_alone_naming_the_file_and_line) {
  jnd_batch_manifest m = csv("id,asset,command,options\n"
                             "a,builtin,texres,--views 2\n"
                             "b,builtin,lodd,\n"
                             "c,builtin,texres,--views 'two\n"
                             "A,builtin,texres,\n"
                             "a,builtin,pca,\n"
                             "d,builtin,texres,-o elsewhere\n"
                             "e/x,builtin,texres,\n"
                             ",builtin,texres,\n"
                             "f,,texres,\n"
                             "g,builtin,texres\n"
                             "report,builtin,texres,\n"
                             "h,builtin,diff,--json=x.json\n");
  CHECK(m.nrows == 12);
  if (m.nrows != 12) return;
  CHECK(!m.rows[0].error);
  CHECK(strstr(err(&m, 1), "assets.csv:3: unknown command 'lodd'") && strstr(err(&m, 1), "texres, pca, diff, render"));
  CHECK(strstr(err(&m, 2), "assets.csv:4: options: a ' is not closed"));
  CHECK(strstr(err(&m, 3), "assets.csv:5: id 'A' differs only in case from 'a' (line 2)"));
  CHECK(strstr(err(&m, 4), "assets.csv:6: duplicate id 'a' (first on line 2)"));
  CHECK(strstr(err(&m, 5), "assets.csv:7: options: -o is set by jnd batch"));
  CHECK(strstr(err(&m, 6), "assets.csv:8: id 'e/x' is not a folder name"));
  CHECK(strstr(err(&m, 7), "assets.csv:9: no id"));
  CHECK(strstr(err(&m, 8), "assets.csv:10: no asset"));
  CHECK(strstr(err(&m, 9), "assets.csv:11: 3 fields where the header has 4"));
  CHECK(strstr(err(&m, 10), "assets.csv:12: id 'report' is a name the output folder uses"));
  CHECK(strstr(err(&m, 11), "assets.csv:13: options: --json is set by jnd batch"));
  for (int i = 1; i < 12; i++) CHECK(!strchr(err(&m, i), '\n'));
  jnd_batch_manifest_free(&m);
}

TEST(what_no_row_survives_is_an_error_of_the_whole_manifest) {
  const char *bad[] = {"", "id,asset,command,options\n", "id,asset\nx,y\n", "id,asset,command,option\n",
                       "id,asset,command,id\n", "id,asset,command,options\na,builtin,texres,\"--views 2\n"};
  const char *why[] = {"empty manifest", "no assets under the header", "no column 'command'",
                       "unknown column 'option'", "column 'id' twice", "assets.csv:2: malformed CSV record"};
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    jnd_batch_manifest m;
    CHECK_STATUS(jnd_batch_manifest_parse_csv("assets.csv", bad[i], strlen(bad[i]), &m), JND_ERR_FORMAT);
    CHECK(m.nrows == 0 && m.rows == NULL);
    CHECK(strstr(jnd_last_error(), why[i]) != NULL);
    if (!strstr(jnd_last_error(), why[i])) fprintf(stderr, "  %zu: %s\n", i, jnd_last_error());
  }
}

TEST(a_json_manifest_takes_a_string_or_a_list_of_words) {
  const char *text = "{\"assets\": [{\"id\": \"a\", \"asset\": \"builtin\", \"command\": \"texres\", \"options\": \"--views 2\"},"
                     " {\"id\": \"b\", \"asset\": \"x y.glb\", \"command\": \"texres\", \"options\": [\"--maps\", \"a b\"]},"
                     " {\"id\": \"c\", \"asset\": \"builtin\", \"command\": 3},"
                     " 7,"
                     " {\"id\": \"d\", \"asset\": \"builtin\", \"command\": \"pca\", \"extra\": 1}]}";
  jnd_batch_manifest m;
  CHECK_OK(jnd_batch_manifest_parse_json("assets.json", text, strlen(text), &m));
  CHECK(m.nrows == 5);
  if (m.nrows == 5) {
    CHECK(!m.rows[0].error && m.rows[0].argc == 2);
    CHECK(!m.rows[1].error && m.rows[1].argc == 2 && strcmp(m.rows[1].argv[1], "a b") == 0);
    CHECK(strcmp(m.rows[1].options, "--maps 'a b'") == 0);
    CHECK(strstr(err(&m, 2), "assets.json: entry 3: \"command\" is not a string"));
    CHECK(strstr(err(&m, 3), "assets.json: entry 4: not an object"));
    CHECK(strstr(err(&m, 4), "assets.json: entry 5: unknown key 'extra'"));
  }
  jnd_batch_manifest_free(&m);
  CHECK_STATUS(jnd_batch_manifest_parse_json("x.json", "{\"a\": 1}", 8, &m), JND_ERR_FORMAT);
  CHECK_STATUS(jnd_batch_manifest_parse_json("x.json", "[]", 2, &m), JND_ERR_FORMAT);
  CHECK_STATUS(jnd_batch_manifest_parse_json("x.json", "[{", 2, &m), JND_ERR_FORMAT);
}

TEST(a_missing_asset_fails_its_row_relative_to_the_manifest) {
  const char *dir = test_tmp_dir();
  char path[1200], asset[1200];
  snprintf(path, sizeof path, "%s/batch_manifest.csv", dir);
  snprintf(asset, sizeof asset, "%s/present.obj", dir);
  FILE *f = fopen(asset, "w");
  if (f) fclose(f);
  f = fopen(path, "w");
  CHECK(f != NULL);
  if (!f) return;
  fputs("id,asset,command,options\nhere,present.obj,texres,\ngone,absent.obj,texres,\nbuilt,builtin:sphere,texres,\n", f);
  fclose(f);
  jnd_batch_manifest m;
  CHECK_OK(jnd_batch_manifest_read(path, NULL, NULL, &m));
  CHECK(m.nrows == 3 && m.base_dir && strcmp(m.base_dir, dir) == 0 && m.source[0] == '/');
  if (m.nrows == 3) {
    CHECK(!m.rows[0].error && !m.rows[2].error);
    CHECK(strstr(err(&m, 1), ":3: absent.obj: no such file") != NULL);
  }
  jnd_batch_manifest_free(&m);
  CHECK_STATUS(jnd_batch_manifest_read("/nonexistent/assets.csv", NULL, NULL, &m), JND_ERR_IO);
}

/* a shell expands ~ and starts a comment with # only at the start of a word;
 * inside one they are plain text, and so they are here */
TEST(tilde_and_hash_inside_a_word_are_plain_text) {
  CHECK(split_is("--maps a~b x#1 --label=v#2", 4, (const char *[]){"--maps", "a~b", "x#1", "--label=v#2"}));
  /* inside double quotes a backslash keeps $ and ` from expanding, as in a shell */
  CHECK(split_is("\"cost \\$5 \\`x\\`\"", 1, (const char *[]){"cost $5 `x`"}));
  int argc;
  char **argv;
  CHECK_STATUS(jnd_shell_split("a ~b", &argc, &argv), JND_ERR_FORMAT);
  CHECK_STATUS(jnd_shell_split("a #b", &argc, &argv), JND_ERR_FORMAT);
}

/* a header as a spreadsheet saves it (a UTF-8 byte-order mark, blanks
 * around names); ids that a folder name cannot be, or that OUT uses itself
 * in any case; a third repeat names the first row, not the second */
TEST(manifest_headers_ids_and_repeats_at_their_edges) {
  jnd_batch_manifest m = csv("\xEF\xBB\xBF" "id , asset,command\nx,builtin,texres\n");
  CHECK(m.nrows == 1 && !m.rows[0].error && strcmp(m.rows[0].id, "x") == 0);
  jnd_batch_manifest_free(&m);
  m = csv("id,asset,command\n-x,builtin,texres\n.x,builtin,texres\n_x,builtin,texres\nREPORT,builtin,texres\n"
          "Summary.CSV,builtin,texres\nsummary.json,builtin,texres\na.b_c-9,builtin,texres\n"
          "r,builtin,texres\nr,builtin,pca\nr,builtin,diff\n");
  CHECK(m.nrows == 10);
  if (m.nrows == 10) {
    for (int i = 0; i < 3; i++) CHECK(strstr(err(&m, i), "is not a folder name") != NULL);
    for (int i = 3; i < 6; i++) CHECK(strstr(err(&m, i), "is a name the output folder uses") != NULL);
    CHECK(!m.rows[6].error && !m.rows[7].error);
    CHECK(strstr(err(&m, 8), "assets.csv:10: duplicate id 'r' (first on line 9)") != NULL);
    CHECK(strstr(err(&m, 9), "assets.csv:11: duplicate id 'r' (first on line 9)") != NULL);
  }
  jnd_batch_manifest_free(&m);
  /* the line of a row after a record that spans two lines */
  m = csv("id,asset,command,options\na,builtin,texres,\"--views\n2\"\nb,builtin,lodd,\n");
  CHECK(m.nrows == 2 && !m.rows[0].error && m.rows[0].argc == 2 && strstr(err(&m, 1), "assets.csv:4: unknown command"));
  jnd_batch_manifest_free(&m);
  /* options batch sets, as --name=value too */
  m = csv("id,asset,command,options\na,builtin,texres,--output=x\nb,builtin,pca,--out y\nc,builtin,texres,--jsonx 1\n");
  CHECK(m.nrows == 3 && strstr(err(&m, 0), "--output is set by jnd batch") && strstr(err(&m, 1), "--out is set by jnd batch"));
  CHECK(m.nrows == 3 && !m.rows[2].error);
  jnd_batch_manifest_free(&m);
  /* JSON rows say "entry" */
  const char *j = "[{\"id\": \"a\", \"asset\": \"builtin\", \"command\": \"texres\"},"
                  " {\"id\": \"a\", \"asset\": \"builtin\", \"command\": \"pca\"}]";
  CHECK_OK(jnd_batch_manifest_parse_json("a.json", j, strlen(j), &m));
  CHECK(m.nrows == 2 && strstr(err(&m, 1), "a.json: entry 2: duplicate id 'a' (first as entry 1)"));
  jnd_batch_manifest_free(&m);
}

static void touch_file(const char *path) {
  FILE *f = fopen(path, "w");
  CHECK(f != NULL);
  if (f) fclose(f);
}

/* a glob's ids: the match's path less the folders all matches share and its
 * extension, '/' as '-', other characters outside the id alphabet as '_';
 * rows in sorted order, numbered from 1 */
TEST(a_glob_names_each_match_by_its_path_below_the_shared_folder) {
  char d[1200], p[1400];
  snprintf(d, sizeof d, "%s/batch_glob", test_tmp_dir());
  jnd_remove_tree(d);
  snprintf(p, sizeof p, "%s/one", d);
  CHECK_OK(jnd_mkdirs(p));
  snprintf(p, sizeof p, "%s/two", d);
  CHECK_OK(jnd_mkdirs(p));
  const char *files[] = {"one/x.obj", "two/y.v2.glb", "two/z w.obj"};
  for (int i = 0; i < 3; i++) {
    snprintf(p, sizeof p, "%s/%s", d, files[i]);
    touch_file(p);
  }
  snprintf(p, sizeof p, "%s/*/*", d);
  jnd_batch_manifest m;
  CHECK_OK(jnd_batch_manifest_read(p, "texres", "--views 2", &m));
  CHECK(m.nrows == 3);
  if (m.nrows == 3) {
    const char *ids[] = {"one-x", "two-y.v2", "two-z_w"};
    for (int i = 0; i < 3; i++) {
      CHECK(strcmp(m.rows[i].id, ids[i]) == 0 && m.rows[i].line == i + 1 && !m.rows[i].error);
      if (strcmp(m.rows[i].id, ids[i]) != 0) fprintf(stderr, "  id %s, wanted %s\n", m.rows[i].id, ids[i]);
      CHECK(m.rows[i].argc == 2 && strcmp(m.rows[i].command, "texres") == 0);
    }
  }
  jnd_batch_manifest_free(&m);
  /* one match: its file name */
  snprintf(p, sizeof p, "%s/one/*.obj", d);
  CHECK_OK(jnd_batch_manifest_read(p, "pca", NULL, &m));
  CHECK(m.nrows == 1 && strcmp(m.rows[0].id, "x") == 0);
  jnd_batch_manifest_free(&m);
  snprintf(p, sizeof p, "%s/one/*.png", d);
  CHECK_STATUS(jnd_batch_manifest_read(p, "pca", NULL, &m), JND_ERR_IO);
  CHECK(strstr(jnd_last_error(), "no file matches") != NULL);
}

static char *read_path(const char *path);

/* the Slurm scripts, read as sbatch reads their #SBATCH lines and run by
 * bash as a node would run them (with a stand-in for jnd that logs how it
 * was called): task 3 of 4 runs shard 3/4 in the manifest's folder, with the
 * task's CPUs shared among the assets run at once; the merge job merges,
 * then writes the report */
TEST(slurm_scripts_run_the_shard_of_their_task_and_then_the_merge) {
  char d[1200], base[1300], out[1300], exe[1300], logf[1300], cmd[4200];
  snprintf(d, sizeof d, "%s/batch_slurm", test_tmp_dir());
  jnd_remove_tree(d);
  snprintf(base, sizeof base, "%s/base", d);
  snprintf(out, sizeof out, "%s/out", d);
  snprintf(exe, sizeof exe, "%s/fake-jnd", d);
  snprintf(logf, sizeof logf, "%s/calls.log", d);
  CHECK_OK(jnd_mkdirs(base));
  FILE *f = fopen(exe, "w");
  CHECK(f != NULL);
  if (!f) return;
  fprintf(f, "#!/bin/sh\necho \"$PWD|${OMP_NUM_THREADS:-}|$*\" >> '%s'\n", logf);
  fclose(f);
  chmod(exe, 0755);
  jnd_batch_manifest m = csv("id,asset,command\na,builtin,texres\n");
  free(m.source), free(m.base_dir);
  m.source = jnd_path_join(base, "assets.csv");
  m.base_dir = strdup(base);
  jnd_batch_params run = {.out_dir = out, .jobs = 2, .timeout_s = 30, .force = 1, .jnd_exe = exe};
  jnd_slurm_params sp;
  jnd_slurm_defaults(&sp);
  const char *extra[] = {"--qos=low"};
  sp.shards = 4, sp.array_limit = 2, sp.cpus_per_task = 8, sp.mem = "4G", sp.time = "1-02:00:00";
  sp.partition = "gpu", sp.gres = "gpu:1", sp.job_name = "nightly", sp.extra = extra, sp.nextra = 1;
  char *a = NULL, *b = NULL;
  CHECK_OK(jnd_slurm_scripts(&m, NULL, NULL, &run, &sp, &a, &b));
  if (!a || !b) return;
  char want[8000];
  const char *lines_a[] = {"#SBATCH --array=0-3%2\n", "#SBATCH --cpus-per-task=8\n", "#SBATCH --mem=4G\n",
                           "#SBATCH --time=1-02:00:00\n", "#SBATCH --partition=gpu\n", "#SBATCH --gres=gpu:1\n",
                           "#SBATCH --job-name=nightly\n", "#SBATCH --qos=low\n", "#SBATCH --ntasks=1\n"};
  for (size_t i = 0; i < sizeof lines_a / sizeof lines_a[0]; i++) {
    CHECK(strstr(a, lines_a[i]) != NULL);
    if (!strstr(a, lines_a[i])) fprintf(stderr, "  array script lacks %s", lines_a[i]);
  }
  snprintf(want, sizeof want, "#SBATCH --output=%s/_batch/slurm/shard-%%a.log\n", out);
  CHECK(strstr(a, want) != NULL);
  const char *lines_b[] = {"#SBATCH --job-name=nightly-merge\n", "#SBATCH --cpus-per-task=1\n", "#SBATCH --qos=low\n",
                           "#SBATCH --time=1-02:00:00\n", "#SBATCH --partition=gpu\n"};
  for (size_t i = 0; i < sizeof lines_b / sizeof lines_b[0]; i++) CHECK(strstr(b, lines_b[i]) != NULL);
  snprintf(want, sizeof want, "#SBATCH --output=%s/_batch/slurm/merge.log\n", out);
  CHECK(strstr(b, want) != NULL);
  CHECK(!strstr(b, "--array") && !strstr(b, "--gres") && !strstr(b, "--mem"));
  /* run them */
  char pa[1400], pb[1400];
  snprintf(pa, sizeof pa, "%s/array.sh", d);
  snprintf(pb, sizeof pb, "%s/merge.sh", d);
  CHECK_OK(jnd_write_file_atomic(pa, a, strlen(a)));
  CHECK_OK(jnd_write_file_atomic(pb, b, strlen(b)));
  snprintf(cmd, sizeof cmd, "cd / && env -i PATH=/usr/bin:/bin SLURM_ARRAY_TASK_ID=3 SLURM_CPUS_PER_TASK=8 bash '%s' "
           "&& env -i PATH=/usr/bin:/bin bash '%s'", pa, pb);
  CHECK(system(cmd) == 0);
  char *calls = read_path(logf);
  snprintf(want, sizeof want, "%s|4|batch %s/assets.csv -o %s --shard 3/4 --jobs 2 --timeout 30 --force\n"
           "%s||batch merge %s\n%s||report %s\n", base, base, out, "/", out, "/", out);
  CHECK(calls && strcmp(calls, want) == 0);
  if (calls && strcmp(calls, want) != 0) fprintf(stderr, "  calls:\n%s  wanted:\n%s", calls, want);
  free(calls);
  free(a), free(b);
  /* threads given: each asset's command gets that many, whatever the CPUs */
  run.threads = 3;
  sp.array_limit = 0;
  CHECK_OK(jnd_slurm_scripts(&m, "texres", "--views 2", &run, &sp, &a, &b));
  CHECK(a && strstr(a, "export OMP_NUM_THREADS=3\n") && strstr(a, "#SBATCH --array=0-3\n"));
  snprintf(want, sizeof want, " batch assets.csv --command texres --options '--views 2' -o %s", out);
  CHECK(a && strstr(a, want)); /* the glob relative to the folder it was given in */
  free(a), free(b);
  /* what sbatch would misread is refused */
  const char *bad_time[] = {"1-", "-1", "1::2", "1:2:3:4", "1:", "a", "1-2-3"};
  for (size_t i = 0; i < sizeof bad_time / sizeof bad_time[0]; i++) {
    jnd_slurm_params q = sp;
    q.time = bad_time[i];
    CHECK_STATUS(jnd_slurm_scripts(&m, NULL, NULL, &run, &q, &a, &b), JND_ERR_ARG);
  }
  const char *good_time[] = {"30", "1:30", "2:00:00", "1-0", "1-2:30"};
  for (size_t i = 0; i < sizeof good_time / sizeof good_time[0]; i++) {
    jnd_slurm_params q = sp;
    q.time = good_time[i];
    CHECK_OK(jnd_slurm_scripts(&m, NULL, NULL, &run, &q, &a, &b));
    free(a), free(b);
  }
  const char *bad_mem[] = {"4GB", "G", "4X", ""}, *good_mem[] = {"4000", "500M", "4g"};
  for (size_t i = 0; i < 4; i++) {
    jnd_slurm_params q = sp;
    q.mem = bad_mem[i];
    CHECK_STATUS(jnd_slurm_scripts(&m, NULL, NULL, &run, &q, &a, &b), JND_ERR_ARG);
  }
  for (size_t i = 0; i < 3; i++) {
    jnd_slurm_params q = sp;
    q.mem = good_mem[i];
    CHECK_OK(jnd_slurm_scripts(&m, NULL, NULL, &run, &q, &a, &b));
    free(a), free(b);
  }
  const char *bad_extra[] = {"-x", "-qos=low", "--=1", "--a\nb", "qos=low"};
  for (size_t i = 0; i < 5; i++) {
    jnd_slurm_params q = sp;
    q.extra = &bad_extra[i];
    CHECK_STATUS(jnd_slurm_scripts(&m, NULL, NULL, &run, &q, &a, &b), JND_ERR_ARG);
  }
  jnd_slurm_params q = sp;
  q.partition = "gpu;rm";
  CHECK_STATUS(jnd_slurm_scripts(&m, NULL, NULL, &run, &q, &a, &b), JND_ERR_ARG);
  q = sp, q.gres = "gpu 1";
  CHECK_STATUS(jnd_slurm_scripts(&m, NULL, NULL, &run, &q, &a, &b), JND_ERR_ARG);
  q = sp, q.shards = 0;
  CHECK_STATUS(jnd_slurm_scripts(&m, NULL, NULL, &run, &q, &a, &b), JND_ERR_ARG);
  q = sp, q.cpus_per_task = 0;
  CHECK_STATUS(jnd_slurm_scripts(&m, NULL, NULL, &run, &q, &a, &b), JND_ERR_ARG);
  q = sp, q.array_limit = -1;
  CHECK_STATUS(jnd_slurm_scripts(&m, NULL, NULL, &run, &q, &a, &b), JND_ERR_ARG);
  jnd_batch_params r2 = run;
  char odd[1400];
  snprintf(odd, sizeof odd, "%s/o ut", d);
  r2.out_dir = odd;
  CHECK_STATUS(jnd_slurm_scripts(&m, NULL, NULL, &r2, &sp, &a, &b), JND_ERR_ARG);
  jnd_batch_manifest_free(&m);
}

TEST(shards_are_parsed_strictly) {
  int i = -1, n = -1;
  CHECK_OK(jnd_batch_shard_parse("0/1", &i, &n));
  CHECK(i == 0 && n == 1);
  CHECK_OK(jnd_batch_shard_parse("3/4", &i, &n));
  CHECK(i == 3 && n == 4);
  const char *bad[] = {"3/2", "2/2", "1/0", "-1/2", "1", "1/", "/2", "a/b", "1/2x", "1/200000", ""};
  for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) CHECK_STATUS(jnd_batch_shard_parse(bad[k], &i, &n), JND_ERR_ARG);
  CHECK_STATUS(jnd_batch_shard_parse("3/2", &i, &n), JND_ERR_ARG);
  CHECK(strstr(jnd_last_error(), "index 3 is not below the count 2") != NULL);
}

TEST(json_paths_select_what_the_table_of_commands_names) {
  const char *t = "{\"result\": {\"maps\": [{\"chosen\": [64, 32]}, {\"chosen\": [8, 8]}], \"p\": [0.1, 0.7, 0.3],"
                  " \"memory\": {\"before_bytes\": 100}}}";
  cJSON *doc = cJSON_Parse(t);
  const cJSON *v[4];
  CHECK(jnd_json_select(doc, "result.maps[].chosen", v, 4) == 2);
  CHECK(cJSON_GetArrayItem(v[1], 0)->valueint == 8);
  CHECK(jnd_json_select(doc, "result.maps[1].chosen[0]", v, 4) == 1 && v[0]->valueint == 8);
  CHECK(jnd_json_number(doc, "result.memory.before_bytes") == 100);
  CHECK(jnd_json_number(doc, "max:result.p[]") == 0.7);
  CHECK(isnan(jnd_json_number(doc, "result.nothing")) && isnan(jnd_json_number(doc, "result.maps")));
  CHECK(jnd_json_select(doc, "result.maps[9]", v, 4) == 0 && jnd_json_select(doc, "result.p[]", v, 4) == 3);
  cJSON_Delete(doc);
}

TEST(text_escapes_for_html_and_csv) {
  jnd_text t = {0};
  jnd_text_html(&t, "<a href=\"x\">'&'</a>");
  jnd_text_put(&t, "|");
  jnd_text_csv(&t, "plain");
  jnd_text_put(&t, "|");
  jnd_text_csv(&t, "a,\"b\"\nc");
  char *s = jnd_text_take(&t);
  CHECK(s && strcmp(s, "&lt;a href=&quot;x&quot;&gt;&#39;&amp;&#39;&lt;/a&gt;|plain|\"a,\"\"b\"\"\nc\"") == 0);
  free(s);
  jnd_text e = {0};
  s = jnd_text_take(&e);
  CHECK(s && s[0] == 0);
  free(s);
}

/* a fake output folder: what two shards would have recorded */
static void write_file(const char *dir, const char *name, const char *text) {
  char *p = jnd_path_join(dir, name);
  CHECK_OK(jnd_write_file_atomic(p, text, strlen(text)));
  free(p);
}

static char *read_path(const char *path) {
  FILE *f = path ? fopen(path, "rb") : NULL;
  if (!f) return NULL;
  static char buf[1 << 16];
  size_t n = fread(buf, 1, sizeof buf - 1, f);
  fclose(f);
  buf[n] = 0;
  return strdup(buf);
}

static char *read_all(const char *dir, const char *name) {
  char *p = jnd_path_join(dir, name);
  char *s = read_path(p);
  free(p);
  return s;
}

/* an empty output folder with OUT/_batch/records and OUT/<also> */
static void fresh_out(const char *out, const char *also) {
  char d[1300];
  jnd_remove_tree(out);
  snprintf(d, sizeof d, "%s/_batch/records", out);
  CHECK_OK(jnd_mkdirs(d));
  snprintf(d, sizeof d, "%s/%s", out, also);
  CHECK_OK(jnd_mkdirs(d));
}

static void fake_out(const char *out, int order) {
  fresh_out(out, "a");
  write_file(out, "_batch/manifest.json",
             "{\"source\": \"/m/assets.csv\", \"base_dir\": \"/m\", \"rows\": ["
             "{\"line\": 2, \"id\": \"a\", \"asset\": \"builtin\", \"command\": \"texres\", \"options\": \"--views 2\"},"
             "{\"line\": 3, \"id\": \"b\", \"asset\": \"builtin\", \"command\": \"texres\", \"options\": \"--views x\"},"
             "{\"line\": 4, \"id\": \"c\", \"asset\": \"nope.glb\", \"command\": \"texres\", \"options\": \"\", "
             "\"error\": \"assets.csv:4: nope.glb: no such file\"},"
             "{\"line\": 5, \"id\": \"d\", \"asset\": \"builtin\", \"command\": \"pca\", \"options\": \"\"}]}");
  /* the records land in another order, from other shards and hosts */
  const char *ra = "{\"id\": \"a\", \"command\": \"texres\", \"asset\": \"builtin\", \"options\": \"--views 2\", "
                   "\"status\": \"ok\", \"exit_status\": 0, \"seconds\": 1.5, \"host\": \"n1\"}";
  const char *rb = "{\"id\": \"b\", \"command\": \"texres\", \"asset\": \"builtin\", \"options\": \"--views x\", "
                   "\"status\": \"failed\", \"exit_status\": 2, \"error\": \"jnd: texres: --views: 'x' is not an "
                   "integer\", \"seconds\": 0.1, \"host\": \"n2\"}";
  if (order) {
    write_file(out, "_batch/records/b.json", rb);
    write_file(out, "_batch/records/a.json", ra);
  } else {
    write_file(out, "_batch/records/a.json", ra);
    write_file(out, "_batch/records/b.json", rb);
  }
  write_file(out, "a/texres.json",
             "{\"command\": \"texres\", \"result\": {\"maps\": [{\"name\": \"m/baseColor\", \"original\": [64, 64], "
             "\"chosen\": [32, 32]}], \"memory\": {\"before_bytes\": 1000, \"after_bytes\": 250}, "
             "\"views\": {\"p\": [0.05, 0.15]}}}");
}

TEST(merge_gives_the_same_summary_whatever_order_the_shards_wrote_in) {
  char a[1200], b[1200];
  snprintf(a, sizeof a, "%s/batch_merge_a", test_tmp_dir());
  snprintf(b, sizeof b, "%s/batch_merge_b", test_tmp_dir());
  fake_out(a, 0);
  fake_out(b, 1);
  jnd_batch_totals t;
  CHECK_OK(jnd_batch_merge(a, 0, &t));
  CHECK(t.assets == 4 && t.ok == 1 && t.failed == 2 && t.pending == 1 && t.above == 0);
  CHECK_OK(jnd_batch_merge(b, 0, NULL));
  char *ja = read_all(a, "summary.json"), *jb = read_all(b, "summary.json");
  char *ca = read_all(a, "summary.csv"), *cb = read_all(b, "summary.csv");
  CHECK(ja && jb && strcmp(ja, jb) == 0);
  CHECK(ca && cb && strcmp(ca, cb) == 0);
  /* the numbers come from the asset's own report; rows in manifest order */
  CHECK(ca && strstr(ca, "a,2,builtin,texres,--views 2,ok,0,,1000,250,0.75,0.15,m/baseColor 32×32 (from 64×64)\n"));
  CHECK(ca && strstr(ca, "b,3,builtin,texres,--views x,failed,2,jnd: texres: --views: 'x' is not an integer,,,,,\n"));
  CHECK(ca && strstr(ca, "c,4,nope.glb,texres,,failed,,assets.csv:4: nope.glb: no such file,,,,,\n"));
  CHECK(ca && strstr(ca, "d,5,builtin,pca,,pending,,,,,,,\n"));
  CHECK(ca && !strstr(ca, "seconds"));
  free(ja), free(jb), free(ca), free(cb);
  /* with timings, the seconds of the records */
  CHECK_OK(jnd_batch_merge(a, 1, NULL));
  ca = read_all(a, "summary.csv");
  CHECK(ca && strstr(ca, ",seconds\n") && strstr(ca, ",1.5\n"));
  free(ca);
  /* a record of other options is not this row's result */
  write_file(a, "_batch/records/a.json", "{\"id\": \"a\", \"command\": \"texres\", \"asset\": \"builtin\", "
                                         "\"options\": \"--views 9\", \"status\": \"ok\", \"exit_status\": 0}");
  CHECK_OK(jnd_batch_merge(a, 0, &t));
  CHECK(t.ok == 0 && t.pending == 2);
}

TEST(merge_of_a_folder_no_batch_ran_in_says_so) {
  CHECK_STATUS(jnd_batch_merge("/nonexistent/out", 0, NULL), JND_ERR_IO);
  CHECK(strstr(jnd_last_error(), "no batch has run in this folder") != NULL);
}

TEST(the_report_has_a_page_per_asset_and_the_summary_numbers) {
  char a[1200];
  snprintf(a, sizeof a, "%s/batch_report", test_tmp_dir());
  fake_out(a, 0);
  CHECK_STATUS(jnd_batch_report(a, NULL, 0), JND_ERR_IO); /* before merge */
  CHECK_OK(jnd_batch_merge(a, 1, NULL));
  char index[2048];
  CHECK_OK(jnd_batch_report(a, index, sizeof index));
  CHECK(strstr(index, "/report/index.html") != NULL);
  char *html = read_all(a, "report/index.html");
  CHECK(html && strstr(html, "<tr data-status=\"ok\" data-id=\"a\">"));
  CHECK(html && strstr(html, "data-value=\"1000\"") && strstr(html, "data-value=\"0.75\""));
  CHECK(html && strstr(html, "id=\"total-failed\" data-value=\"2\""));
  CHECK(html && strstr(html, "&#39;x&#39; is not an integer")); /* escaped */
  CHECK(html && !strstr(html, "http://") && !strstr(html, "https://"));
  free(html);
  for (int i = 0; i < 4; i++) {
    char name[32];
    snprintf(name, sizeof name, "report/%c.html", "abcd"[i]);
    char *page = read_all(a, name);
    CHECK(page && strstr(page, "<h1>"));
    free(page);
  }
}

/* an output folder with an asset of each command, hand-built reports whose
 * decisions and numbers are known */
static void record(const char *out, const char *id, const char *command, const char *status, int code) {
  char name[128], text[512];
  snprintf(name, sizeof name, "_batch/records/%s.json", id);
  snprintf(text, sizeof text, "{\"id\": \"%s\", \"command\": \"%s\", \"asset\": \"builtin\", \"options\": \"\", "
           "\"status\": \"%s\", \"exit_status\": %d, \"seconds\": 0.25, \"log\": \"_batch/logs/%s.log\"%s}",
           id, command, status, code, id, strcmp(status, "failed") == 0 ? ", \"error\": \"boom\"" : "");
  write_file(out, name, text);
}

static void report_of(const char *out, const char *id, const char *json_name, const char *text) {
  char d[1300], name[128];
  snprintf(d, sizeof d, "%s/%s", out, id);
  CHECK_OK(jnd_mkdirs(d));
  snprintf(name, sizeof name, "%s/%s", id, json_name);
  write_file(out, name, text);
}

static const struct {
  const char *id, *command, *json, *report, *status;
  int code;
} KINDS[] = {
    {"p", "pca", "pca.json",
     "{\"result\": {\"channel_count\": 9, \"components_kept\": 4, \"components\": [{\"divisor\": 1}, {\"divisor\": 2}, "
     "{\"divisor\": 4}, {\"divisor\": 1}], \"memory\": {\"before_bytes\": 4194304, \"after_bytes\": 1048576}, "
     "\"rendered\": {\"p_criterion\": 0.125, \"pass\": true, \"p_per_view\": [0.1234, 0.5]}}}", "ok", 0},
    {"d", "diff", "diff.json", "{\"result\": {\"p_detect\": 0.4321, \"pooling\": \"p93\", \"jnd_max\": 2.5}}", "above", 1},
    {"l", "lod", "lod.json",
     "{\"result\": {\"levels\": [{\"triangles\": 1000}, {\"triangles\": 250}], \"screens\": [{\"name\": \"phone\", "
     "\"perceptual_level\": 1, \"perceptual_triangles\": 250, \"perceptual_statistic\": 0.05}, {\"name\": \"desk\", "
     "\"perceptual_level\": 0, \"perceptual_triangles\": 1000, \"perceptual_statistic\": 0.15}], "
     "\"memory\": {\"before_bytes\": 2000, \"after_bytes\": 500}}}", "ok", 0},
    {"l2", "lod", "lod.json", "{\"result\": {\"levels\": [{\"triangles\": 10}], \"screens\": [], "
     "\"memory\": {\"before_bytes\": 7000}}}", "ok", 0},
    {"g", "gaze", "gaze.json", "{\"result\": {\"level\": [[0, 1, 2], [1, 3, 2]], \"distances_m\": [1, 2], "
     "\"eccentricities_deg\": [0, 10, 20]}}", "ok", 0},
    {"o0", "pop", "pop.json", "{\"result\": {\"region_count\": 0, \"detection_score\": 1}}", "ok", 0},
    {"o1", "pop", "pop.json", "{\"result\": {\"region_count\": 1, \"max_rating\": 1.234, \"detection_score\": 3}}", "above", 1},
    {"o3", "pop", "pop.json", "{\"result\": {\"region_count\": 3, \"max_rating\": 2.5, \"detection_score\": 4, "
     "\"switch\": [{\"level\": 1, \"distance\": 4}]}}", "ok", 0},
    {"u", "budget", "budget.json", "{\"result\": {\"chosen\": {\"level\": 2, \"statistic\": 0.09}, \"comparison\": "
     "{\"chosen_cost_bytes\": 3145728, \"separate_cost_bytes\": 4194304, \"original_cost_bytes\": 8388608}}}", "ok", 0},
    {"t", "texres", "texres.json",
     "{\"parameters\": {\"criterion\": {\"p\": 0.2, \"q\": 0.1}}, \"result\": {\"maps\": [{\"name\": \"m/normal\", "
     "\"original\": [64, 32], \"chosen\": [64, 32]}], \"memory\": {\"before_bytes\": 3145728, \"after_bytes\": 3145728, "
     "\"reduction\": 0.125}, \"views\": {\"passes\": true, \"p\": [0.05, 0.1]}, \"verify\": {\"passes\": false}}}", "ok", 0},
    {"f", "texres", NULL, NULL, "failed", 2},
};
#define NKINDS (sizeof KINDS / sizeof KINDS[0])

static void fake_kinds(const char *out) {
  fresh_out(out, "_batch/logs");
  jnd_text plan = {0};
  jnd_text_put(&plan, "{\"source\": \"/m/assets.csv\", \"base_dir\": \"/m\", \"rows\": [");
  for (size_t i = 0; i < NKINDS; i++) {
    jnd_text_printf(&plan, "%s{\"line\": %zu, \"id\": \"%s\", \"asset\": \"builtin\", \"command\": \"%s\", \"options\": \"\"}",
                    i ? ", " : "", i + 2, KINDS[i].id, KINDS[i].command);
    record(out, KINDS[i].id, KINDS[i].command, KINDS[i].status, KINDS[i].code);
    if (KINDS[i].report) report_of(out, KINDS[i].id, KINDS[i].json, KINDS[i].report);
  }
  jnd_text_put(&plan, "]}");
  char *text = jnd_text_take(&plan);
  write_file(out, "_batch/manifest.json", text);
  free(text);
  write_file(out, "_batch/logs/f.log", "first line\nlast <line> of the log\n");
}

static const cJSON *asset_of(const cJSON *summary, const char *id) {
  const cJSON *e;
  cJSON_ArrayForEach(e, cJSON_GetObjectItem(cJSON_GetObjectItem(summary, "result"), "assets")) {
    const cJSON *v = cJSON_GetObjectItem(e, "id");
    if (cJSON_IsString(v) && strcmp(v->valuestring, id) == 0) return e;
  }
  return NULL;
}

static const char *text_of(const cJSON *e, const char *key) {
  const cJSON *v = cJSON_GetObjectItem(e, key);
  return cJSON_IsString(v) ? v->valuestring : "";
}

static double number_of(const cJSON *e, const char *key) {
  const cJSON *v = cJSON_GetObjectItem(e, key);
  return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

/* each command's decision in words and its numbers, from its own report:
 * the texts and values below are written by hand from the reports above */
TEST(merge_tells_each_commands_decision_and_numbers_from_its_report) {
  char a[1200];
  snprintf(a, sizeof a, "%s/batch_kinds", test_tmp_dir());
  fake_kinds(a);
  jnd_batch_totals t;
  CHECK_OK(jnd_batch_merge(a, 1, &t));
  CHECK(t.assets == (int)NKINDS && t.ok == 8 && t.above == 2 && t.failed == 1 && t.pending == 0);
  char *text = read_all(a, "summary.json");
  cJSON *doc = text ? cJSON_Parse(text) : NULL;
  free(text);
  CHECK(doc != NULL);
  if (!doc) return;
  const struct {
    const char *id, *decision;
    double p, before, after;
  } want[] = {
      {"p", "4 of 9 components, 2 at reduced resolution", 0.125, 4194304, 1048576},
      {"d", "P(detect) 0.432 (p93), max 2.5 JND", 0.4321, NAN, NAN},
      {"l", "phone level 1 (250 of 1000 triangles); desk level 0 (1000 of 1000 triangles)", 0.15, 2000, 500},
      {"l2", "no perceptual choice (--no-perceptual)", NAN, 7000, NAN},
      {"g", "levels 0–3 over 2 distances × 3 eccentricities", NAN, NAN, NAN},
      {"o0", "no popping region, detection score 1 of 5", NAN, NAN, NAN},
      {"o1", "1 popping region, max R 1.23, detection score 3 of 5", NAN, NAN, NAN},
      {"o3", "3 popping regions, max R 2.50, detection score 4 of 5; 1 switch distance", NAN, NAN, NAN},
      {"u", "level 2, 3.000 MiB of textures and mesh (texres + pca + lod separately: 4.000 MiB)", 0.09, 8388608, 3145728},
      {"t", "m/normal 64×32", 0.1, 3145728, 3145728},
  };
  for (size_t i = 0; i < sizeof want / sizeof want[0]; i++) {
    const cJSON *e = asset_of(doc, want[i].id);
    CHECK(e != NULL);
    if (!e) continue;
    CHECK(strcmp(text_of(e, "decision"), want[i].decision) == 0);
    if (strcmp(text_of(e, "decision"), want[i].decision) != 0)
      fprintf(stderr, "  %s: '%s', wanted '%s'\n", want[i].id, text_of(e, "decision"), want[i].decision);
    double v[3] = {number_of(e, "p_detect"), number_of(e, "memory_before_bytes"), number_of(e, "memory_after_bytes")};
    double w[3] = {want[i].p, want[i].before, want[i].after};
    for (int k = 0; k < 3; k++) CHECK(isnan(w[k]) ? isnan(v[k]) : v[k] == w[k]);
    double red = number_of(e, "reduction");
    CHECK(isnan(w[2]) ? isnan(red) : fabs(red - (1 - w[2] / w[1])) < 1e-12);
  }
  /* what was chosen, as JSON */
  const cJSON *c = cJSON_GetObjectItem(asset_of(doc, "l"), "chosen");
  CHECK(number_of(cJSON_GetObjectItem(c, "perceptual_level"), "phone") == 1);
  c = cJSON_GetObjectItem(asset_of(doc, "g"), "chosen");
  CHECK(number_of(c, "finest") == 0 && number_of(c, "coarsest") == 3);
  c = cJSON_GetObjectItem(asset_of(doc, "p"), "chosen");
  CHECK(number_of(c, "components") == 4 && number_of(c, "channels") == 9);
  c = cJSON_GetObjectItem(asset_of(doc, "u"), "chosen");
  CHECK(number_of(c, "level") == 2 && number_of(c, "cost_bytes") == 3145728);
  c = cJSON_GetObjectItem(asset_of(doc, "o3"), "chosen");
  CHECK(number_of(c, "detection_score") == 4 && cJSON_GetArraySize(cJSON_GetObjectItem(c, "switch")) == 1);
  /* totals: memory over the assets that report both numbers (l2 reports only before) */
  const cJSON *tot = cJSON_GetObjectItem(cJSON_GetObjectItem(doc, "result"), "totals");
  double before = 4194304.0 + 2000 + 8388608 + 3145728, after = 1048576.0 + 500 + 3145728 + 3145728;
  CHECK(number_of(tot, "with_memory") == 4);
  CHECK(number_of(tot, "memory_before_bytes") == before && number_of(tot, "memory_after_bytes") == after);
  CHECK_NEAR(number_of(tot, "reduction"), 1 - after / before, 1e-12);
  CHECK_NEAR(number_of(tot, "seconds"), 0.25 * NKINDS, 1e-9);
  CHECK(number_of(asset_of(doc, "d"), "exit_status") == 1 && strcmp(text_of(asset_of(doc, "d"), "status"), "above") == 0);
  CHECK(strcmp(text_of(asset_of(doc, "f"), "error"), "boom") == 0);
  cJSON_Delete(doc);
}

/* the report's pages show each number in its unit, recomputed here from
 * the bytes and fractions of the reports above */
TEST(the_report_shows_numbers_in_their_units_links_and_the_failures_log) {
  char a[1200];
  snprintf(a, sizeof a, "%s/batch_kinds_report", test_tmp_dir());
  fake_kinds(a);
  CHECK_OK(jnd_batch_merge(a, 1, NULL));
  CHECK_OK(jnd_batch_report(a, NULL, 0));
  char *html = read_all(a, "report/index.html");
  CHECK(html != NULL);
  if (!html) return;
  double before = 4194304.0 + 2000 + 8388608 + 3145728, after = 1048576.0 + 500 + 3145728 + 3145728;
  char want[512];
  snprintf(want, sizeof want, "<div id=\"total-memory_before_bytes\" data-value=\"%.0f\"><b>%.2f MiB</b>", before,
           before / 1048576);
  CHECK(strstr(html, want) != NULL);
  snprintf(want, sizeof want, "<div id=\"total-reduction\" data-value=\"%.17g\"><b>%.1f%%</b>", 1 - after / before,
           100 * (1 - after / before));
  CHECK(strstr(html, want) != NULL);
  CHECK(strstr(html, "<div id=\"total-above\" data-value=\"2\"><b>2</b>") != NULL);
  CHECK(strstr(html, "<div id=\"total-seconds\" data-value=\"2.75\"><b>2.75</b>") != NULL);
  /* the pca row: P, 4 MiB before, 1 MiB after, 75 % smaller; l's 2000 bytes
   * are 0.0019 MiB (four decimals under 0.01 MiB) */
  CHECK(strstr(html, "<td class=\"num\" data-value=\"0.125\">0.125</td>"
                     "<td class=\"num\" data-value=\"4194304\" title=\"4194304 bytes\">4.00 MiB</td>"
                     "<td class=\"num\" data-value=\"1048576\" title=\"1048576 bytes\">1.00 MiB</td>"
                     "<td class=\"num\" data-value=\"0.75\">75.0%</td>") != NULL);
  CHECK(strstr(html, "title=\"2000 bytes\">0.0019 MiB</td>") != NULL);
  CHECK(strstr(html, "<td class=\"num\" data-value=\"0.25\">0.2</td>") || strstr(html, "data-value=\"0.25\">0.3</td>"));
  CHECK(strstr(html, "<tr data-status=\"above\" data-id=\"d\"><td><a href=\"d.html\">d</a></td><td>diff</td>"
                     "<td data-value=\"above\"><span class=\"status above\">above</span></td>") != NULL);
  free(html);
  /* an asset's page: its fields in their formats, its tables, links to its
   * neighbours in manifest order */
  html = read_all(a, "report/t.html");
  CHECK(html != NULL);
  if (!html) return;
  CHECK(strstr(html, "<tr><th>memory before (unique images, RGBA8 + mips)</th><td>3.00 MiB</td></tr>") != NULL);
  CHECK(strstr(html, "<tr><th>reduction</th><td>12.5%</td></tr>") != NULL);
  CHECK(strstr(html, "<tr><th>passes the criterion</th><td>yes</td></tr>") != NULL);
  CHECK(strstr(html, "<tr><th>held-out views pass</th><td>no</td></tr>") != NULL);
  CHECK(strstr(html, "<tr><th>P per view (pooled)</th><td>0.05, 0.1</td></tr>") != NULL);
  CHECK(strstr(html, "<tr><th>criterion: P above</th><td>0.200</td></tr>") != NULL);
  CHECK(strstr(html, "<tr><th>criterion: fraction of views allowed above</th><td>10.0%</td></tr>") != NULL);
  CHECK(strstr(html, "<tr><td>m/normal</td><td>64×32</td><td>64×32</td><td>—</td>") != NULL);
  CHECK(strstr(html, "<a href=\"u.html\">previous</a>") && strstr(html, "<a href=\"f.html\">next</a>"));
  CHECK(strstr(html, "<dt>time</dt><dd>0.2 s</dd>") || strstr(html, "<dt>time</dt><dd>0.3 s</dd>"));
  free(html);
  html = read_all(a, "report/p.html");
  CHECK(html && !strstr(html, "previous</a>") && strstr(html, "<a href=\"d.html\">next</a>"));
  CHECK(html && strstr(html, "<tr><th>rendered: P per view</th><td>0.123, 0.5</td></tr>"));
  CHECK(html && strstr(html, "<tr><th>components kept</th><td>4</td></tr>"));
  free(html);
  /* the failure's page: its error, exit status and the end of its log, escaped */
  html = read_all(a, "report/f.html");
  CHECK(html && strstr(html, "<dt>error</dt><dd>boom</dd>") && strstr(html, "<dt>exit status</dt><dd>2</dd>"));
  CHECK(html && strstr(html, "<h2>End of its log</h2>\n<pre>first line\nlast &lt;line&gt; of the log\n</pre>"));
  CHECK(html && !strstr(html, "next</a>"));
  free(html);
}

RUN_TESTS(options_split_into_words_as_a_shell_splits_them, options_that_a_shell_would_expand_are_refused_not_passed_on,
          tilde_and_hash_inside_a_word_are_plain_text, manifest_headers_ids_and_repeats_at_their_edges,
          a_glob_names_each_match_by_its_path_below_the_shared_folder,
          slurm_scripts_run_the_shard_of_their_task_and_then_the_merge,
          joined_words_split_back_to_themselves, a_csv_manifest_gives_one_row_per_asset_with_its_words,
          each_bad_row_fails_alone_naming_the_file_and_line, what_no_row_survives_is_an_error_of_the_whole_manifest,
          a_json_manifest_takes_a_string_or_a_list_of_words, a_missing_asset_fails_its_row_relative_to_the_manifest,
          shards_are_parsed_strictly, json_paths_select_what_the_table_of_commands_names,
          text_escapes_for_html_and_csv, merge_gives_the_same_summary_whatever_order_the_shards_wrote_in,
          merge_of_a_folder_no_batch_ran_in_says_so, the_report_has_a_page_per_asset_and_the_summary_numbers,
          merge_tells_each_commands_decision_and_numbers_from_its_report,
          the_report_shows_numbers_in_their_units_links_and_the_failures_log)
