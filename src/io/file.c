/* Whole-file reads, folder creation and atomic writes (the one place for
 * each): outputs go to a temporary file in the
 * same folder and are renamed over the target, so a reader never sees half a
 * file and an interrupted run leaves the old file intact. */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/core.h"
#include "io/io.h"

jnd_status jnd_read_file(const char *path, size_t max_bytes, unsigned char **data, size_t *size) {
  *data = NULL;
  *size = 0;
  struct stat st;
  if (stat(path, &st) != 0) return jnd_fail(JND_ERR_IO, "%s: %s", path, strerror(errno));
  if (S_ISDIR(st.st_mode)) return jnd_fail(JND_ERR_IO, "%s: is a directory", path);
  FILE *f = fopen(path, "rb");
  if (!f) return jnd_fail(JND_ERR_IO, "%s: %s", path, strerror(errno));
  /* a regular file is read into a buffer of its size, one byte more to see
   * its end (no regrowing and copying; a 2 MB PNG took six); a pipe grows */
  size_t cap = 1 << 16, n = 0;
  if (S_ISREG(st.st_mode) && st.st_size > 0 && (uintmax_t)st.st_size < max_bytes) cap = (size_t)st.st_size + 1;
  unsigned char *buf = jnd_alloc(cap, 1);
  if (!buf) {
    fclose(f);
    return jnd_fail(JND_ERR_NOMEM, "%s: out of memory", path);
  }
  for (;;) {
    if (n == cap) {
      if (cap >= max_bytes) {
        free(buf);
        fclose(f);
        return jnd_fail(JND_ERR_LIMIT, "%s: file is larger than the limit of %zu bytes", path, max_bytes);
      }
      cap = cap * 2 > max_bytes ? max_bytes : cap * 2;
      unsigned char *nb = realloc(buf, cap);
      if (!nb) {
        free(buf);
        fclose(f);
        return jnd_fail(JND_ERR_NOMEM, "%s: out of memory", path);
      }
      buf = nb;
    }
    size_t got = fread(buf + n, 1, cap - n, f);
    n += got;
    if (got == 0) break;
  }
  int err = ferror(f);
  fclose(f);
  if (err) {
    free(buf);
    return jnd_fail(JND_ERR_IO, "%s: read error", path);
  }
  *data = buf;
  *size = n;
  return JND_OK;
}

jnd_status jnd_write_file_atomic(const char *path, const void *data, size_t n) {
  /* the host as well as the process: shards of a batch on several machines
   * write the same file in a shared folder, and process ids repeat across
   * machines */
  char host[64] = "";
  gethostname(host, sizeof host - 1);
  for (char *c = host; *c; c++)
    if (*c == '/') *c = '_';
  size_t len = strlen(path);
  char *tmp = jnd_alloc(len + 96, 1);
  if (!tmp) return JND_ERR_NOMEM;
  snprintf(tmp, len + 96, "%s.tmp.%s.%ld", path, host, (long)getpid());
  FILE *f = fopen(tmp, "wb");
  if (!f) {
    jnd_status s = jnd_fail(JND_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
    free(tmp);
    return s;
  }
  size_t put = n ? fwrite(data, 1, n, f) : 0;
  int bad = put != n;
  bad |= fflush(f) != 0;
  bad |= fclose(f) != 0;
  if (bad || rename(tmp, path) != 0) {
    jnd_status s = jnd_fail(JND_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
    remove(tmp);
    free(tmp);
    return s;
  }
  free(tmp);
  return JND_OK;
}

jnd_status jnd_make_dirs(const char *dir) {
  char buf[4096];
  if (!dir || !*dir || strlen(dir) >= sizeof buf) return jnd_fail(JND_ERR_ARG, "%s: not a folder name", dir ? dir : "");
  snprintf(buf, sizeof buf, "%s", dir);
  for (char *p = buf + 1; *p; p++)
    if (*p == '/') {
      *p = 0;
      if (mkdir(buf, 0777) != 0 && errno != EEXIST) return jnd_fail(JND_ERR_IO, "%s: cannot create the folder (%s)", dir, strerror(errno));
      *p = '/';
    }
  if (mkdir(buf, 0777) != 0 && errno != EEXIST) return jnd_fail(JND_ERR_IO, "%s: cannot create the folder (%s)", dir, strerror(errno));
  struct stat st;
  if (stat(buf, &st) != 0 || !S_ISDIR(st.st_mode)) return jnd_fail(JND_ERR_IO, "%s: cannot create the folder (not a folder)", dir);
  return JND_OK;
}
