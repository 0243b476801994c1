/* Files and folders of a batch's output: JSON in and out (atomic), folders
 * made and removed, paths joined. */
#include <errno.h>
#include <ftw.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "batch/batch.h"
#include "core/core.h"
#include "io/io.h"

#define MAX_JSON_BYTES ((size_t)256 << 20)

char *jnd_path_join(const char *a, const char *b) {
  size_t na = strlen(a), nb = strlen(b);
  char *p = malloc(na + nb + 2);
  if (!p) {
    jnd_fail(JND_ERR_NOMEM, "out of memory");
    return NULL;
  }
  memcpy(p, a, na);
  size_t k = na;
  if (na && a[na - 1] != '/') p[k++] = '/';
  memcpy(p + k, b, nb + 1);
  return p;
}

cJSON *jnd_json_read(const char *path) {
  unsigned char *buf;
  size_t n;
  if (jnd_read_file(path, MAX_JSON_BYTES, &buf, &n) != JND_OK) return NULL;
  cJSON *doc = cJSON_ParseWithLength((const char *)buf, n);
  free(buf);
  if (!doc) jnd_fail(JND_ERR_FORMAT, "%s: not valid JSON", path);
  return doc;
}

jnd_status jnd_json_write(const char *path, const cJSON *doc) {
  char *text = cJSON_Print(doc);
  if (!text) return jnd_fail(JND_ERR_NOMEM, "%s: out of memory", path);
  size_t n = strlen(text);
  char *t2 = realloc(text, n + 2);
  if (!t2) {
    free(text);
    return jnd_fail(JND_ERR_NOMEM, "%s: out of memory", path);
  }
  t2[n] = '\n';
  t2[n + 1] = 0;
  jnd_status s = jnd_write_file_atomic(path, t2, n + 1);
  free(t2);
  return s;
}

jnd_status jnd_mkdirs(const char *path) {
  char *p = strdup(path);
  if (!p) return jnd_fail(JND_ERR_NOMEM, "out of memory");
  for (char *c = p + 1;; c++) {
    if (*c != '/' && *c) continue;
    char keep = *c;
    *c = 0;
    if (mkdir(p, 0777) != 0 && errno != EEXIST) {
      jnd_status s = jnd_fail(JND_ERR_IO, "%s: cannot make the folder: %s", p, strerror(errno));
      free(p);
      return s;
    }
    *c = keep;
    if (!keep) break;
  }
  struct stat st;
  int ok = stat(p, &st) == 0 && S_ISDIR(st.st_mode);
  free(p);
  return ok ? JND_OK : jnd_fail(JND_ERR_IO, "%s: not a folder", path);
}

static int remove_one(const char *path, const struct stat *st, int flag, struct FTW *ftw) {
  (void)st;
  (void)flag;
  (void)ftw;
  return remove(path) != 0 && errno != ENOENT ? -1 : 0;
}

jnd_status jnd_remove_tree(const char *path) {
  struct stat st;
  if (lstat(path, &st) != 0) return errno == ENOENT ? JND_OK : jnd_fail(JND_ERR_IO, "%s: %s", path, strerror(errno));
  /* depth first, never following links out of the tree */
  if (nftw(path, remove_one, 16, FTW_DEPTH | FTW_PHYS) != 0)
    return jnd_fail(JND_ERR_IO, "%s: cannot remove: %s", path, strerror(errno));
  return JND_OK;
}

static const char *const STATUS[] = {"pending", "ok", "above", "failed"};

const char *jnd_asset_status_name(jnd_asset_status s) {
  return (unsigned)s < sizeof STATUS / sizeof STATUS[0] ? STATUS[s] : "pending";
}

int jnd_asset_status_parse(const char *name, jnd_asset_status *s) {
  for (int i = 0; i < 4; i++)
    if (name && strcmp(name, STATUS[i]) == 0) {
      *s = (jnd_asset_status)i;
      return 1;
    }
  return 0;
}
