/* The output writer: every file a run writes goes out through one jnd_output,
 * which is where "never over an input" and "all or nothing" live
 * (docs/outputs.md).
 *
 * 1. Inputs are registered with their resolved path (realpath) and identity
 *    (st_dev, st_ino).
 * 2. Each output (a file or a folder) is registered before any work: it is
 *    resolved the same way (the longest existing prefix through realpath,
 *    the rest lexically, so `.`, `..` and symlinks are seen through) and
 *    refused when it is an input, a folder holding an input, or another
 *    output of the run. Its staging area is made at once, which proves the
 *    target folder writable before the analysis starts.
 * 3. A file output is written to PATH.jnd-partial-PID beside it; a folder
 *    output to the sibling folder PATH.jnd-partial-PID; an output that lies
 *    inside a registered output folder is staged inside that folder's
 *    staging.
 * 4. Commit publishes everything by rename; abort (or free without commit)
 *    removes the staging and every folder the writer created, so a failed
 *    run leaves nothing, and an earlier run's output is untouched.
 *
 * An existing output folder is never renamed or removed: the staged files
 * are moved into it one by one at commit. When the folder carries the marker
 * an earlier jnd run left (MARKER: the files that run wrote), the files it
 * lists that this run did not write are removed; any other file in it is the
 * user's and is left alone. */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/core.h"
#include "io/io.h"

#define MARKER ".jnd-output"

typedef struct {
  char *given;       /* the path as the caller named it (for messages) */
  char *canon;       /* absolute, symlinks and . / .. resolved */
  int exists;
  dev_t dev;
  ino_t ino;
} node;

typedef struct {
  node n;
  int is_dir;
  int inside;        /* index of the output folder it lies in, or -1 */
  char *staged;      /* where the run writes it */
} output;

struct jnd_output {
  node *in;
  int n_in, cap_in;
  output *out;
  int n_out, cap_out;
  char **made;       /* folders the writer created (parents of outputs), in order */
  int n_made, cap_made;
  int committed;
  int finished;      /* committed or aborted: nothing left to clean */
};

static char *dup_str(const char *s) {
  size_t n = strlen(s) + 1;
  char *d = malloc(n);
  if (d) memcpy(d, s, n);
  return d;
}

static char *join(const char *a, const char *b) {
  size_t na = strlen(a), nb = strlen(b);
  char *r = malloc(na + nb + 2);
  if (!r) return NULL;
  memcpy(r, a, na);
  size_t k = na;
  if (k == 0 || r[k - 1] != '/') r[k++] = '/';
  memcpy(r + k, b, nb + 1);
  return r;
}

/* path made absolute with symlinks, `.` and `..` resolved: the longest prefix
 * that exists goes through realpath, the rest is appended lexically. NULL
 * when out of memory or the name is too long. */
static char *canonical(const char *path) {
  char cur[PATH_MAX];
  char buf[PATH_MAX];
  if (path[0] == '/') {
    if (strlen(path) >= sizeof buf) return NULL;
    snprintf(buf, sizeof buf, "%s", path);
  } else {
    if (!getcwd(cur, sizeof cur)) return NULL;
    size_t nc = strlen(cur), np = strlen(path);
    if (nc + np + 2 > sizeof buf) return NULL;
    memcpy(buf, cur, nc);
    buf[nc] = '/';
    memcpy(buf + nc + 1, path, np + 1);
  }
  snprintf(cur, sizeof cur, "/");
  int exists = 1;
  char *save = NULL;
  for (char *c = strtok_r(buf, "/", &save); c; c = strtok_r(NULL, "/", &save)) {
    if (strcmp(c, ".") == 0) continue;
    if (strcmp(c, "..") == 0) {   /* cur is resolved (or lexical past the existing part): its parent is lexical */
      char *s = strrchr(cur, '/');
      if (s == cur) cur[1] = 0;
      else if (s) *s = 0;
      continue;
    }
    size_t n = strlen(cur), nc = strlen(c);
    if (n + nc + 2 > sizeof cur) return NULL;
    if (n > 1) cur[n++] = '/';
    memcpy(cur + n, c, nc + 1);
    if (exists) {
      char res[PATH_MAX];
      struct stat st;
      if (lstat(cur, &st) == 0 && realpath(cur, res)) memcpy(cur, res, strlen(res) + 1);
      else exists = 0;   /* missing, or a dangling link: the rest is lexical */
    }
  }
  return dup_str(cur);
}

static jnd_status node_make(const char *path, node *n) {
  memset(n, 0, sizeof *n);
  n->canon = canonical(path);
  n->given = dup_str(path);
  if (!n->canon || !n->given) {
    free(n->canon);
    free(n->given);
    return jnd_fail(JND_ERR_ARG, "%s: cannot resolve the path", path);
  }
  struct stat st;
  if (stat(n->canon, &st) == 0) {
    n->exists = 1;
    n->dev = st.st_dev;
    n->ino = st.st_ino;
  }
  return JND_OK;
}

/* 1 when path lies strictly inside folder dir (both canonical) */
static int under(const char *path, const char *dir) {
  size_t n = strlen(dir);
  if (n == 1) return path[1] != 0;   /* "/" holds everything but itself */
  return strncmp(path, dir, n) == 0 && path[n] == '/';
}

static int same(const node *a, const node *b) {
  return strcmp(a->canon, b->canon) == 0 || (a->exists && b->exists && a->dev == b->dev && a->ino == b->ino);
}

jnd_status jnd_output_open(jnd_output **out) {
  *out = calloc(1, sizeof **out);
  return *out ? JND_OK : jnd_fail(JND_ERR_NOMEM, "out of memory");
}

static int grow(void **p, int *cap, int n, size_t size) {
  if (n < *cap) return 1;
  int c = *cap ? *cap * 2 : 8;
  void *q = realloc(*p, (size_t)c * size);
  if (!q) return 0;
  *p = q;
  *cap = c;
  return 1;
}

/* an input against the outputs registered so far */
static jnd_status check_pair(const node *in, const output *o) {
  if (same(in, &o->n))
    return jnd_fail(JND_ERR_ARG, "%s: is the input %s (jnd never writes over an input)", o->n.given, in->given);
  if (o->is_dir && under(in->canon, o->n.canon))
    return jnd_fail(JND_ERR_ARG, "%s: the output folder holds the input %s (choose another folder)", o->n.given,
                    in->given);
  return JND_OK;
}

jnd_status jnd_output_add_input(jnd_output *w, const char *path) {
  if (!path || !*path || strcmp(path, "-") == 0) return JND_OK;
  struct stat st;
  if (stat(path, &st) != 0 || !S_ISREG(st.st_mode)) return JND_OK;   /* the reader reports a missing file */
  node n;
  jnd_status s = node_make(path, &n);
  if (s) return s;
  for (int k = 0; k < w->n_in; k++)
    if (same(&w->in[k], &n)) {   /* already known */
      free(n.canon);
      free(n.given);
      return JND_OK;
    }
  for (int k = 0; k < w->n_out; k++)
    if ((s = check_pair(&n, &w->out[k])) != JND_OK) {
      free(n.canon);
      free(n.given);
      return s;
    }
  if (!grow((void **)&w->in, &w->cap_in, w->n_in, sizeof *w->in)) {
    free(n.canon);
    free(n.given);
    return jnd_fail(JND_ERR_NOMEM, "out of memory");
  }
  w->in[w->n_in++] = n;
  return JND_OK;
}

/* mkdir -p of dir, remembering each folder made so that abort removes it */
static jnd_status make_dirs(jnd_output *w, const char *dir, const char *given) {
  char buf[PATH_MAX];
  if (strlen(dir) >= sizeof buf) return jnd_fail(JND_ERR_ARG, "%s: the path is too long", given);
  snprintf(buf, sizeof buf, "%s", dir);
  size_t len = strlen(buf);
  for (size_t i = 1; i <= len; i++) {
    if (buf[i] != '/' && buf[i] != 0) continue;
    char keep = buf[i];
    buf[i] = 0;
    struct stat st;
    if (stat(buf, &st) != 0) {
      if (mkdir(buf, 0777) != 0) {
        jnd_status s = jnd_fail(JND_ERR_IO, "%s: cannot create the folder %s (%s)", given, buf, strerror(errno));
        return s;
      }
      char *d = dup_str(buf);
      if (!d || !grow((void **)&w->made, &w->cap_made, w->n_made, sizeof *w->made)) {
        free(d);
        return jnd_fail(JND_ERR_NOMEM, "out of memory");
      }
      w->made[w->n_made++] = d;
    } else if (!S_ISDIR(st.st_mode)) {
      return jnd_fail(JND_ERR_IO, "%s: cannot create the folder: %s is a file", given, buf);
    }
    buf[i] = keep;
  }
  return JND_OK;
}

static char *parent_of(const char *canon) {
  char *p = dup_str(canon);
  if (!p) return NULL;
  char *s = strrchr(p, '/');
  if (s == p) p[1] = 0;
  else if (s) *s = 0;
  return p;
}

static char *staging_name(const char *canon) {
  char suffix[48];
  snprintf(suffix, sizeof suffix, ".jnd-partial-%ld", (long)getpid());
  size_t n = strlen(canon);
  char *r = malloc(n + sizeof suffix);
  if (r) snprintf(r, n + sizeof suffix, "%s%s", canon, suffix);
  return r;
}

static jnd_status add_output(jnd_output *w, const char *path, int is_dir, const char **staged) {
  if (staged) *staged = NULL;
  if (!path || !*path) return jnd_fail(JND_ERR_ARG, "an output needs a name");
  if (!is_dir && strcmp(path, "-") == 0) {   /* standard output: nothing to stage */
    if (staged) *staged = "-";
    return JND_OK;
  }
  if (w->committed) return jnd_fail(JND_ERR_ARG, "%s: the run's outputs are already published", path);
  output o;
  memset(&o, 0, sizeof o);
  o.is_dir = is_dir;
  o.inside = -1;
  jnd_status s = node_make(path, &o.n);
  if (s) return s;
  for (int k = 0; k < w->n_in && !s; k++) s = check_pair(&w->in[k], &o);
  struct stat st;
  if (!s && o.n.exists && stat(o.n.canon, &st) == 0) {
    if (is_dir && !S_ISDIR(st.st_mode)) s = jnd_fail(JND_ERR_ARG, "%s: is a file, not a folder", path);
    if (!is_dir && S_ISDIR(st.st_mode)) s = jnd_fail(JND_ERR_ARG, "%s: is a folder, not a file", path);
  }
  for (int k = 0; k < w->n_out && !s; k++) {
    const output *p = &w->out[k];
    if (same(&p->n, &o.n))
      s = jnd_fail(JND_ERR_ARG, "%s: is also the output %s of this run", path, p->n.given);
    else if (!p->is_dir && under(o.n.canon, p->n.canon))
      s = jnd_fail(JND_ERR_ARG, "%s: lies inside the output file %s of this run", path, p->n.given);
    else if (under(p->n.canon, o.n.canon))
      s = jnd_fail(JND_ERR_ARG, "%s: holds the output %s of this run (name the folder first)", path, p->n.given);
    else if (p->is_dir && under(o.n.canon, p->n.canon) && (o.inside < 0 || under(p->n.canon, w->out[o.inside].n.canon)))
      o.inside = k;   /* the innermost folder */
  }
  if (!s) {
    if (o.inside >= 0) {
      const output *p = &w->out[o.inside];
      o.staged = join(p->staged, o.n.canon + strlen(p->n.canon) + 1);
    } else {
      o.staged = staging_name(o.n.canon);
    }
    if (!o.staged) s = jnd_fail(JND_ERR_NOMEM, "out of memory");
  }
  if (!s && !grow((void **)&w->out, &w->cap_out, w->n_out, sizeof *w->out)) s = jnd_fail(JND_ERR_NOMEM, "out of memory");
  if (!s) {
    /* the staging area now: an unwritable target is found before any work */
    char *parent = parent_of(o.staged);
    s = parent ? make_dirs(w, parent, path) : jnd_fail(JND_ERR_NOMEM, "out of memory");
    free(parent);
    if (!s && is_dir) {
      if (o.inside >= 0) s = make_dirs(w, o.staged, path);
      else if (mkdir(o.staged, 0777) != 0) s = jnd_fail(JND_ERR_IO, "%s: cannot write in its folder (%s)", path, strerror(errno));
    } else if (!s) {
      int fd = open(o.staged, O_WRONLY | O_CREAT | O_EXCL, 0666);
      if (fd < 0) s = jnd_fail(JND_ERR_IO, "%s: cannot write in its folder (%s)", path, strerror(errno));
      else {
        close(fd);
        unlink(o.staged);   /* written by the run, published only if it was */
      }
    }
  }
  if (s) {
    free(o.n.canon);
    free(o.n.given);
    free(o.staged);
    return s;
  }
  w->out[w->n_out++] = o;
  if (staged) *staged = o.staged;
  return JND_OK;
}

jnd_status jnd_output_check_dir(jnd_output *w, const char *path) {
  node n;
  jnd_status s = node_make(path, &n);
  if (s) return s;
  output o = {.n = n, .is_dir = 1, .inside = -1};
  for (int k = 0; k < w->n_in && !s; k++) s = check_pair(&w->in[k], &o);
  free(n.canon);
  free(n.given);
  return s;
}

jnd_status jnd_output_add_file(jnd_output *w, const char *path, const char **staged) {
  return add_output(w, path, 0, staged);
}

jnd_status jnd_output_add_dir(jnd_output *w, const char *path, const char **staged) {
  return add_output(w, path, 1, staged);
}

static int remove_one(const char *p, const struct stat *st, int flag, struct FTW *f) {
  (void)st, (void)flag, (void)f;
  remove(p);
  return 0;
}

static void remove_tree(const char *dir) {
  nftw(dir, remove_one, 16, FTW_DEPTH | FTW_PHYS);
}

/* the marker's list of files (relative paths), one a line; NULL if none */
static char *marker_read(const char *dir) {
  char *p = join(dir, MARKER);
  unsigned char *data = NULL;
  size_t n = 0;
  int ok = p && jnd_read_file(p, 1u << 24, &data, &n) == JND_OK;
  free(p);
  if (!ok) return NULL;
  char *t = realloc(data, n + 1);
  if (!t) {
    free(data);
    return NULL;
  }
  t[n] = 0;
  return t;
}

/* appends the regular files under root/rel (relative names, one a line) */
static int list_files(const char *root, const char *rel, jnd_buf *b) {
  char *dir = rel[0] ? join(root, rel) : dup_str(root);
  DIR *d = dir ? opendir(dir) : NULL;
  if (!d) {
    free(dir);
    return 0;
  }
  struct dirent *e;
  int ok = 1;
  while ((e = readdir(d)) != NULL && ok) {
    if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
    if (!rel[0] && strcmp(e->d_name, MARKER) == 0) continue;
    char *r = rel[0] ? join(rel, e->d_name) : dup_str(e->d_name);
    char *full = r ? join(root, r) : NULL;
    struct stat st;
    if (!full || lstat(full, &st) != 0) ok = 0;
    else if (S_ISDIR(st.st_mode)) ok = list_files(root, r, b);
    else {
      jnd_buf_put(b, r, strlen(r));
      jnd_buf_put(b, "\n", 1);
    }
    free(r);
    free(full);
  }
  closedir(d);
  free(dir);
  return ok && !b->failed;
}

static int listed(const char *list, const char *name) {
  size_t n = strlen(name);
  for (const char *l = list; l && *l;) {
    const char *e = strchr(l, '\n');
    size_t k = e ? (size_t)(e - l) : strlen(l);
    if (k == n && strncmp(l, name, n) == 0) return 1;
    l = e ? e + 1 : l + k;
  }
  return 0;
}

/* moves the staged folder's files into the existing folder dst one by one;
 * the old marker's files this run did not write go (they were jnd's) */
static jnd_status merge_into(const output *o) {
  jnd_buf mine = {0};
  if (!list_files(o->staged, "", &mine)) {
    jnd_buf_free(&mine);
    return jnd_fail(JND_ERR_IO, "%s: cannot list the staged files", o->n.given);
  }
  jnd_buf_put(&mine, "", 1);
  char *old = marker_read(o->n.canon);
  /* the old run's files this run does not rewrite: removed */
  for (const char *l = old; l && *l;) {
    const char *e = strchr(l, '\n');
    size_t k = e ? (size_t)(e - l) : strlen(l);
    char name[PATH_MAX];
    if (k < sizeof name && k > 0) {
      memcpy(name, l, k);
      name[k] = 0;
      if (!strstr(name, "..") && !listed((char *)mine.p, name)) {
        char *full = join(o->n.canon, name);
        if (full) {
          remove(full);
          /* its folders, when now empty */
          for (char *s = strrchr(full, '/'); s && s > full + strlen(o->n.canon); s = strrchr(full, '/')) {
            *s = 0;
            if (rmdir(full) != 0) break;
          }
        }
        free(full);
      }
    }
    l = e ? e + 1 : l + k;
  }
  free(old);
  jnd_status s = JND_OK;
  for (const char *l = (char *)mine.p; *l && !s;) {
    const char *e = strchr(l, '\n');
    size_t k = (size_t)(e - l);
    char name[PATH_MAX];
    if (k >= sizeof name) break;
    memcpy(name, l, k);
    name[k] = 0;
    char *from = join(o->staged, name), *to = join(o->n.canon, name);
    char *dir = to ? parent_of(to) : NULL;
    if (!from || !to || !dir) s = jnd_fail(JND_ERR_NOMEM, "out of memory");
    else if (jnd_make_dirs(dir) != JND_OK || rename(from, to) != 0)
      s = jnd_fail(JND_ERR_IO, "%s: cannot publish %s (%s)", o->n.given, name, strerror(errno));
    free(from);
    free(to);
    free(dir);
    l = e + 1;
  }
  /* the marker lists what jnd wrote: this run's files */
  if (!s) {
    char *m = join(o->n.canon, MARKER);
    s = m ? jnd_write_file_atomic(m, mine.p, strlen((char *)mine.p)) : jnd_fail(JND_ERR_NOMEM, "out of memory");
    free(m);
  }
  jnd_buf_free(&mine);
  return s;
}

jnd_status jnd_output_commit(jnd_output *w) {
  if (w->committed) return JND_OK;
  jnd_status s = JND_OK;
  /* folders first, then files (neither kind holds the other: an output inside
   * a folder is staged inside it) */
  for (int pass = 0; pass < 2; pass++)
    for (int k = 0; k < w->n_out && !s; k++) {
      output *o = &w->out[k];
      if (o->inside >= 0 || o->is_dir != (pass == 0)) continue;
      struct stat st;
      if (!o->is_dir) {
        if (lstat(o->staged, &st) != 0) continue;   /* the run did not write it */
        if (rename(o->staged, o->n.canon) != 0) s = jnd_fail(JND_ERR_IO, "%s: cannot publish (%s)", o->n.given, strerror(errno));
      } else if (stat(o->n.canon, &st) != 0) {
        jnd_buf list = {0};
        char *m = join(o->staged, MARKER);
        if (!m || !list_files(o->staged, "", &list)) s = jnd_fail(JND_ERR_IO, "%s: cannot list the staged files", o->n.given);
        if (!s) s = jnd_write_file_atomic(m, list.p ? (char *)list.p : "", list.n);
        if (!s && rename(o->staged, o->n.canon) != 0)
          s = jnd_fail(JND_ERR_IO, "%s: cannot publish (%s)", o->n.given, strerror(errno));
        free(m);
        jnd_buf_free(&list);
      } else {
        s = merge_into(o);
        if (!s) remove_tree(o->staged);
      }
    }
  if (!s) w->committed = w->finished = 1;   /* the folders made now hold the outputs */
  return s;
}

void jnd_output_abort(jnd_output *w) {
  if (!w || w->finished) return;
  w->finished = 1;
  for (int k = w->n_out - 1; k >= 0; k--) {
    output *o = &w->out[k];
    if (o->inside >= 0) continue;
    if (o->is_dir) remove_tree(o->staged);
    else remove(o->staged);
  }
  for (int k = w->n_made - 1; k >= 0; k--) rmdir(w->made[k]);   /* only if empty: never a user's file */
}

void jnd_output_free(jnd_output *w) {
  if (!w) return;
  jnd_output_abort(w);
  for (int k = 0; k < w->n_in; k++) {
    free(w->in[k].canon);
    free(w->in[k].given);
  }
  for (int k = 0; k < w->n_out; k++) {
    free(w->out[k].n.canon);
    free(w->out[k].n.given);
    free(w->out[k].staged);
  }
  for (int k = 0; k < w->n_made; k++) free(w->made[k]);
  free(w->in);
  free(w->out);
  free(w->made);
  free(w);
}
