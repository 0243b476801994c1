/* The output writer (src/io/output.c, docs/outputs.md): never over an input,
 * all or nothing. Each test works in a fresh folder under JND_TMP. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "io/io.h"
#include "jnd.h"
#include "test.h"

static char root[1024];

static void fresh(const char *name) {
  const char *t = getenv("JND_TMP");
  snprintf(root, sizeof root, "%s/test_output/%s", t && *t ? t : "/tmp", name);
  char cmd[1200];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", root);
  if (system(cmd) != 0) fprintf(stderr, "cannot clear %s\n", root);
  jnd_make_dirs(root);
  if (chdir(root) != 0) fprintf(stderr, "cannot enter %s\n", root);
}

static void put(const char *path, const char *text) {
  jnd_write_file_atomic(path, text, strlen(text));
}

static int has(const char *path, const char *text) {
  unsigned char *d = NULL;
  size_t n = 0;
  if (jnd_read_file(path, 1 << 20, &d, &n) != JND_OK) return 0;
  int ok = n == strlen(text) && memcmp(d, text, n) == 0;
  free(d);
  return ok;
}

static int exists(const char *path) {
  struct stat st;
  return lstat(path, &st) == 0;
}

/* entries of the working folder, "." and ".." aside */
static int entries(void) {
  DIR *d = opendir(".");
  int n = 0;
  for (struct dirent *e; d && (e = readdir(d));) n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
  if (d) closedir(d);
  return n;
}

TEST(an_output_that_is_an_input_is_refused_however_it_is_named) {
  fresh("same");
  put("a.png", "input");
  jnd_make_dirs("sub");
  if (symlink("a.png", "link.png") != 0) fprintf(stderr, "no symlink\n");
  if (link("a.png", "hard.png") != 0) fprintf(stderr, "no hard link\n");
  const char *names[] = {"a.png", "./a.png", "sub/../a.png", "link.png", "hard.png", "missing/../a.png"};
  for (int k = 0; k < 6; k++) {
    jnd_output *w;
    const char *staged;
    CHECK_OK(jnd_output_open(&w));
    CHECK_OK(jnd_output_add_input(w, "a.png"));
    CHECK_STATUS(jnd_output_add_file(w, names[k], &staged), JND_ERR_ARG);
    CHECK(strstr(jnd_last_error(), names[k]) && strstr(jnd_last_error(), "a.png"));
    jnd_output_free(w);
  }
  CHECK(has("a.png", "input"));
  CHECK(entries() == 4);   /* a.png, sub, link.png, hard.png: nothing else */
}

TEST(an_input_registered_after_the_output_is_checked_too) {
  fresh("late");
  put("a.png", "input");
  jnd_output *w;
  const char *staged;
  CHECK_OK(jnd_output_open(&w));
  CHECK_OK(jnd_output_add_file(w, "a.png", &staged));
  CHECK_STATUS(jnd_output_add_input(w, "a.png"), JND_ERR_ARG);
  jnd_output_free(w);
  CHECK(has("a.png", "input"));
}

TEST(an_output_folder_holding_an_input_is_refused) {
  fresh("holds");
  jnd_make_dirs("in/deep");
  put("in/deep/m.gltf", "model");
  jnd_output *w;
  const char *staged;
  CHECK_OK(jnd_output_open(&w));
  CHECK_OK(jnd_output_add_input(w, "in/deep/m.gltf"));
  CHECK_STATUS(jnd_output_add_dir(w, "in", &staged), JND_ERR_ARG);
  CHECK_STATUS(jnd_output_add_dir(w, ".", &staged), JND_ERR_ARG);
  CHECK_OK(jnd_output_add_dir(w, "in/deep/out", &staged));   /* beside the input is fine */
  jnd_output_free(w);
  CHECK(!exists("in/deep/out"));
  CHECK(entries() == 1);
}

TEST(two_outputs_of_one_run_may_not_be_the_same_file) {
  fresh("twice");
  jnd_output *w;
  const char *a, *b;
  CHECK_OK(jnd_output_open(&w));
  CHECK_OK(jnd_output_add_file(w, "h.png", &a));
  CHECK_STATUS(jnd_output_add_file(w, "./h.png", &b), JND_ERR_ARG);
  CHECK_STATUS(jnd_output_add_file(w, "h.png/x.json", &b), JND_ERR_ARG);
  jnd_output_free(w);
  CHECK(entries() == 0);
}

TEST(nothing_is_published_before_commit_and_everything_after) {
  fresh("commit");
  jnd_output *w;
  const char *dir, *file, *inner;
  CHECK_OK(jnd_output_open(&w));
  CHECK_OK(jnd_output_add_dir(w, "new/out", &dir));
  CHECK_OK(jnd_output_add_file(w, "r.json", &file));
  CHECK_OK(jnd_output_add_file(w, "new/out/report.json", &inner));
  CHECK(strstr(inner, dir) == inner);   /* staged inside the folder's staging */
  char p[2048];
  snprintf(p, sizeof p, "%s/a.png", dir);
  put(p, "A");
  put(file, "R");
  put(inner, "J");
  CHECK(!exists("new/out") && !exists("r.json"));
  CHECK_OK(jnd_output_commit(w));
  jnd_output_free(w);
  CHECK(has("new/out/a.png", "A") && has("r.json", "R") && has("new/out/report.json", "J"));
  CHECK(exists("new/out/.jnd-output"));
  CHECK(entries() == 2);   /* new, r.json: no staging left */
}

TEST(abort_leaves_no_file_and_no_folder_and_keeps_the_earlier_output) {
  fresh("abort");
  jnd_make_dirs("old");
  put("old/a.png", "earlier");
  put("keep.json", "earlier");
  jnd_output *w;
  const char *dir, *file, *fresh_dir;
  CHECK_OK(jnd_output_open(&w));
  CHECK_OK(jnd_output_add_dir(w, "old", &dir));
  CHECK_OK(jnd_output_add_file(w, "keep.json", &file));
  CHECK_OK(jnd_output_add_dir(w, "a/b/c", &fresh_dir));
  char p[2048];
  snprintf(p, sizeof p, "%s/a.png", dir);
  put(p, "new");
  put(file, "new");
  jnd_output_free(w);   /* no commit: a failed run */
  CHECK(has("old/a.png", "earlier") && has("keep.json", "earlier"));
  CHECK(!exists("a"));
  CHECK(entries() == 2);
}

TEST(a_file_output_in_an_unwritable_place_is_refused_at_registration) {
  fresh("unwritable");
  put("file", "x");
  jnd_output *w;
  const char *staged;
  CHECK_OK(jnd_output_open(&w));
  CHECK_STATUS(jnd_output_add_dir(w, "file/out", &staged), JND_ERR_IO);
  CHECK_STATUS(jnd_output_add_file(w, "file/x.json", &staged), JND_ERR_IO);
  jnd_output_free(w);
  CHECK(entries() == 1 && has("file", "x"));
}

TEST(an_existing_folder_keeps_the_users_files_and_loses_only_jnds_old_ones) {
  fresh("merge");
  jnd_output *w;
  const char *dir;
  char p[2048];
  /* run 1 writes a and b */
  CHECK_OK(jnd_output_open(&w));
  CHECK_OK(jnd_output_add_dir(w, "out", &dir));
  snprintf(p, sizeof p, "%s/a.png", dir);
  put(p, "1");
  snprintf(p, sizeof p, "%s/sub/b.png", dir);
  jnd_make_dirs(p);
  rmdir(p);
  snprintf(p, sizeof p, "%s/sub", dir);
  jnd_make_dirs(p);
  snprintf(p, sizeof p, "%s/sub/b.png", dir);
  put(p, "1");
  CHECK_OK(jnd_output_commit(w));
  jnd_output_free(w);
  put("out/mine.txt", "user");
  /* run 2 writes only a */
  CHECK_OK(jnd_output_open(&w));
  CHECK_OK(jnd_output_add_dir(w, "out", &dir));
  snprintf(p, sizeof p, "%s/a.png", dir);
  put(p, "2");
  CHECK_OK(jnd_output_commit(w));
  jnd_output_free(w);
  CHECK(has("out/a.png", "2"));
  CHECK(!exists("out/sub/b.png") && !exists("out/sub"));
  CHECK(has("out/mine.txt", "user"));
  CHECK(entries() == 1);
}

TEST(standard_output_is_allowed_and_unstaged) {
  fresh("stdout");
  jnd_output *w;
  const char *staged;
  CHECK_OK(jnd_output_open(&w));
  CHECK_OK(jnd_output_add_file(w, "-", &staged));
  CHECK(strcmp(staged, "-") == 0);
  CHECK_OK(jnd_output_commit(w));
  jnd_output_free(w);
  CHECK(entries() == 0);
}

TEST(an_assets_referenced_files_are_listed) {
  fresh("refs");
  jnd_make_dirs("m/tex");
  put("m/a.gltf", "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"uri\":\"a%20b.bin\",\"byteLength\":1}],"
                  "\"images\":[{\"uri\":\"tex/c.png\"},{\"uri\":\"data:image/png;base64,AAAA\"}]}");
  put("m/o.obj", "mtllib o.mtl\nv 0 0 0\n");
  put("m/o.mtl", "newmtl x\nmap_Kd -s 1 1 1 tex/d.png\nbump tex/n.png\n");
  char **f;
  int n;
  CHECK_OK(jnd_asset_files("m/a.gltf", &f, &n));
  CHECK(n == 3 && strcmp(f[0], "m/a.gltf") == 0 && strcmp(f[1], "m/a b.bin") == 0 && strcmp(f[2], "m/tex/c.png") == 0);
  jnd_asset_files_free(f, n);
  /* a GLB: its JSON chunk names an external image; the binary chunk is not read for it */
  const char js[] = "{\"asset\":{\"version\":\"2.0\"},\"images\":[{\"uri\":\"tex/g.png\"}]}";
  unsigned char glb[256];
  unsigned jl = (unsigned)(sizeof js - 1 + 3) / 4 * 4, total = 12 + 8 + jl + 8 + 4;
  memset(glb, ' ', sizeof glb);
  memcpy(glb, "glTF", 4);
  unsigned hdr[] = {2, total, jl};
  memcpy(glb + 4, hdr, 12);
  memcpy(glb + 16, "JSON", 4);
  memcpy(glb + 20, js, sizeof js - 1);
  unsigned bin[] = {4, 0x004E4942u, 0};
  memcpy(glb + 20 + jl, bin, 12);
  jnd_write_file_atomic("m/g.glb", glb, total);
  CHECK_OK(jnd_asset_files("m/g.glb", &f, &n));
  CHECK(n == 2 && strcmp(f[1], "m/tex/g.png") == 0);
  jnd_asset_files_free(f, n);
  CHECK_OK(jnd_asset_files("m/o.obj", &f, &n));
  CHECK(n == 4 && strcmp(f[1], "m/o.mtl") == 0 && strcmp(f[2], "m/tex/d.png") == 0 && strcmp(f[3], "m/tex/n.png") == 0);
  jnd_asset_files_free(f, n);
}

RUN_TESTS(an_output_that_is_an_input_is_refused_however_it_is_named, an_input_registered_after_the_output_is_checked_too,
            an_output_folder_holding_an_input_is_refused, two_outputs_of_one_run_may_not_be_the_same_file,
            nothing_is_published_before_commit_and_everything_after,
            abort_leaves_no_file_and_no_folder_and_keeps_the_earlier_output,
            a_file_output_in_an_unwritable_place_is_refused_at_registration,
            an_existing_folder_keeps_the_users_files_and_loses_only_jnds_old_ones, standard_output_is_allowed_and_unstaged,
            an_assets_referenced_files_are_listed)
