/* Running a shard of a manifest: each asset's command is a child process of
 * the jnd program, so that an asset that crashes, runs out of memory or hangs
 * takes only itself down, and the library never calls the command-line code
 * (the child is `jnd COMMAND ...`, the same program a user runs by hand).
 *   1. write the plan (OUT/_batch/manifest.json) and pick the shard's rows
 *   2. per row, in order: a row error is a failure; a complete asset (its
 *      record says it finished for the same row, asset file and jnd) is
 *      skipped; else its command starts in OUT/_batch/work/<id>/out, working
 *      folder the manifest's, stderr to a log, at most `jobs` at once
 *   3. when one ends: exit 0 (or 1 where that means "above the criterion")
 *      with its JSON report written is a result: the old OUT/<id> moves aside,
 *      the new one is renamed in, then the record is written atomically —
 *      the record is the commit, so a crash anywhere leaves the old result
 *      or the new one, never a half one that looks complete
 *   4. anything else (exit 2, a signal, the timeout) records the failure:
 *      exit status and the last line of stderr; the rest go on */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <sched.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "batch/batch.h"
#include "core/core.h"
#include "tasks/report.h"

#define MAX_JOBS 256

void jnd_batch_defaults(jnd_batch_params *p) {
  memset(p, 0, sizeof *p);
  p->shards = 1;
  p->jobs = 1;
}

static int cpu_count(void) {
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0) return CPU_COUNT(&set);
  long n = sysconf(_SC_NPROCESSORS_ONLN);
  return n > 0 ? (int)n : 1;
}

static int is_builtin(const char *asset) { return strcmp(asset, "builtin") == 0 || strncmp(asset, "builtin:", 8) == 0; }

static int is_image_name(const char *path) {
  static const char *const ext[] = {".png", ".jpg", ".jpeg", ".exr", ".hdr"};
  size_t n = strlen(path);
  for (size_t i = 0; i < sizeof ext / sizeof ext[0]; i++) {
    size_t e = strlen(ext[i]);
    if (n > e && strcasecmp(path + n - e, ext[i]) == 0) return 1;
  }
  return 0;
}

/* what makes a finished run still valid: the row, the asset file, jnd */
static char *fingerprint(const jnd_batch_manifest *m, const jnd_batch_row *r) {
  jnd_text t = {0};
  jnd_text_printf(&t, "jnd %s | %s | %s | %s", jnd_version(), r->command, r->asset, r->options);
  if (!is_builtin(r->asset)) {
    char *path = r->asset[0] == '/' ? strdup(r->asset) : jnd_path_join(m->base_dir, r->asset);
    struct stat st;
    if (path && stat(path, &st) == 0)
      jnd_text_printf(&t, " | %lld bytes, modified %lld.%09ld", (long long)st.st_size, (long long)st.st_mtim.tv_sec,
                      (long)st.st_mtim.tv_nsec);
    free(path);
  }
  return jnd_text_take(&t);
}

typedef struct {
  const jnd_batch_manifest *m;
  const jnd_batch_params *p;
  char *out;          /* OUT, absolute */
  char *records, *logs, *work;
  int done, total, failed;
  double t0;
  jnd_batch_totals *tot;
} run_ctx;

typedef struct {
  int row;
  pid_t pid;
  double t0;
  int timed_out;
  char *work;         /* OUT/_batch/work/<id> */
  char *fp;
} slot;

static char *path3(const char *a, const char *b, const char *c) {
  char *ab = jnd_path_join(a, b);
  if (!ab || !c) return ab;
  char *abc = jnd_path_join(ab, c);
  free(ab);
  return abc;
}

static void emit(run_ctx *c, const jnd_batch_row *r, jnd_asset_status st, int skipped, int exit_status,
                 const char *error, double seconds) {
  c->done++;
  if (st == JND_ASSET_FAILED) c->failed++;
  if (c->tot) {
    if (skipped) c->tot->skipped++;
    if (st == JND_ASSET_OK) c->tot->ok++;
    else if (st == JND_ASSET_ABOVE) c->tot->above++;
    else if (st == JND_ASSET_FAILED) c->tot->failed++;
  }
  if (!c->p->progress) return;
  jnd_batch_event e = {.id = r->id, .command = r->command, .status = st, .skipped = skipped,
                       .exit_status = exit_status, .error = error, .seconds = seconds, .done = c->done,
                       .total = c->total, .failed = c->failed, .elapsed_s = jnd_seconds() - c->t0};
  c->p->progress(c->p->progress_user, &e);
}

/* step 2: the record says the asset finished for this very row: its status
 * (ok or above), or JND_ASSET_PENDING when it must run */
static jnd_asset_status complete(run_ctx *c, const jnd_batch_row *r, const char *fp) {
  char name[JND_BATCH_MAX_ID + 8];
  snprintf(name, sizeof name, "%s.json", r->id);
  char *rec = jnd_path_join(c->records, name);
  cJSON *doc = rec ? jnd_json_read(rec) : NULL;
  free(rec);
  if (!doc) return JND_ASSET_PENDING;
  const cJSON *st = cJSON_GetObjectItemCaseSensitive(doc, "status");
  const cJSON *f = cJSON_GetObjectItemCaseSensitive(doc, "fingerprint");
  jnd_asset_status s = JND_ASSET_PENDING;
  int ok = cJSON_IsString(st) && jnd_asset_status_parse(st->valuestring, &s) &&
           (s == JND_ASSET_OK || s == JND_ASSET_ABOVE) && cJSON_IsString(f) && strcmp(f->valuestring, fp) == 0;
  cJSON_Delete(doc);
  if (!ok) return JND_ASSET_PENDING;
  const jnd_batch_command *cmd = jnd_batch_command_find(r->command);
  char *json = path3(c->out, r->id, cmd ? cmd->json_name : NULL);
  struct stat sb;
  ok = json && stat(json, &sb) == 0 && S_ISREG(sb.st_mode);
  free(json);
  return ok ? s : JND_ASSET_PENDING;
}

/* a NULL-terminated list of n strdup'd strings, or NULL (freed) when one of
 * them could not be allocated */
static char **complete_words(char **v, int n) {
  for (int i = 0; i < n; i++)
    if (!v[i]) {
      jnd_words_free(n, v);
      jnd_fail(JND_ERR_NOMEM, "out of memory");
      return NULL;
    }
  return v;
}

/* the environment of the commands: threads shared out among the jobs, and
 * OpenMP threads that sleep while they wait, since several processes share
 * the cores and spinning takes time from the others (README, Scaling out) */
static char **child_env(const jnd_batch_params *p) {
  extern char **environ;
  int n = 0;
  while (environ[n]) n++;
  char **env = jnd_calloc((size_t)n + 3, sizeof *env);
  if (!env) return NULL;
  char threads[48] = "", *given = getenv("OMP_NUM_THREADS");
  if (p->threads > 0) snprintf(threads, sizeof threads, "OMP_NUM_THREADS=%d", p->threads);
  else if (!given || !*given) snprintf(threads, sizeof threads, "OMP_NUM_THREADS=%d", cpu_count() / p->jobs > 0 ? cpu_count() / p->jobs : 1);
  int k = 0;
  for (int i = 0; i < n; i++)
    if (!(threads[0] && strncmp(environ[i], "OMP_NUM_THREADS=", 16) == 0)) env[k++] = strdup(environ[i]);
  if (threads[0]) env[k++] = strdup(threads);
  if (!getenv("OMP_WAIT_POLICY")) env[k++] = strdup("OMP_WAIT_POLICY=passive");
  return complete_words(env, k);
}

/* the child's command line: jnd COMMAND [--model] ASSET OPTIONS OUT_ARGS --quiet */
static char **child_argv(const jnd_batch_command *cmd, const jnd_batch_row *r, const char *exe, const char *out_dir) {
  int n = 0, cap = r->argc + 16;
  char **argv = jnd_calloc((size_t)cap, sizeof *argv);
  if (!argv) return NULL;
  argv[n++] = strdup(exe);
  argv[n++] = strdup(cmd->name);
  if (cmd->asset_flag && !is_image_name(r->asset)) argv[n++] = strdup(cmd->asset_flag);
  argv[n++] = strdup(r->asset);
  for (int i = 0; i < r->argc; i++) argv[n++] = strdup(r->argv[i]);
  for (int i = 0; i < (int)(sizeof cmd->out_args / sizeof cmd->out_args[0]) && cmd->out_args[i]; i++) {
    const char *a = cmd->out_args[i], *ph = strstr(a, "{out}");
    if (!ph) {
      argv[n++] = strdup(a);
      continue;
    }
    jnd_text t = {0};
    jnd_text_putn(&t, a, (size_t)(ph - a));
    jnd_text_put(&t, out_dir);
    jnd_text_put(&t, ph + 5);
    argv[n++] = jnd_text_take(&t);
  }
  argv[n++] = strdup("--quiet");
  argv[n] = NULL;
  return complete_words(argv, n);
}

/* step 2: start one asset's command; JND_OK with s->pid set */
static jnd_status start(run_ctx *c, int row, slot *s) {
  const jnd_batch_row *r = &c->m->rows[row];
  const jnd_batch_command *cmd = jnd_batch_command_find(r->command);
  memset(s, 0, sizeof *s);
  s->row = row;
  s->work = jnd_path_join(c->work, r->id);
  char *out = s->work ? jnd_path_join(s->work, "out") : NULL;
  char *log = s->work ? jnd_path_join(s->work, "log.txt") : NULL;
  jnd_status st = out && log ? JND_OK : JND_ERR_NOMEM;
  /* what an interrupted run left here is not a result: start clean */
  if (st == JND_OK) st = jnd_remove_tree(s->work);
  if (st == JND_OK) st = jnd_mkdirs(out);
  char **argv = st == JND_OK ? child_argv(cmd, r, c->p->jnd_exe ? c->p->jnd_exe : "jnd", out) : NULL;
  if (st == JND_OK && !argv) st = JND_ERR_NOMEM;
  int fd = -1;
  if (st == JND_OK && (fd = open(log, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666)) < 0)
    st = jnd_fail(JND_ERR_IO, "%s: %s", log, strerror(errno));
  char **env = st == JND_OK ? child_env(c->p) : NULL;
  if (st == JND_OK && !env) st = JND_ERR_NOMEM;
  if (st == JND_OK) {
    s->t0 = jnd_seconds();
    pid_t pid = fork();
    if (pid < 0) {
      st = jnd_fail(JND_ERR_INTERNAL, "cannot start a process for %s: %s", r->id, strerror(errno));
    } else if (pid == 0) {
      /* the child: only async-signal-safe calls and exec from here */
      int null = open("/dev/null", O_RDONLY);
      if (null >= 0) dup2(null, 0);
      dup2(fd, 1);
      dup2(fd, 2);
      if (chdir(c->m->base_dir) != 0) {
        const char msg[] = "jnd: batch: cannot enter the manifest's folder\n";
        (void)!write(2, msg, sizeof msg - 1);
        _exit(127);
      }
      execvpe(argv[0], argv, env);
      const char msg[] = "jnd: batch: cannot run the jnd program (--jnd / jnd_exe)\n";
      (void)!write(2, msg, sizeof msg - 1);
      _exit(127);
    } else {
      s->pid = pid;
    }
  }
  if (fd >= 0) close(fd);
  if (env) {
    int n = 0;
    while (env[n]) n++;
    jnd_words_free(n, env);
  }
  if (argv) {
    int n = 0;
    while (argv[n]) n++;
    jnd_words_free(n, argv);
  }
  free(out);
  free(log);
  return st;
}

/* the last line of the command's stderr that says something */
static void last_line(const char *log, char *buf, size_t n) {
  buf[0] = 0;
  FILE *f = fopen(log, "rb");
  if (!f) return;
  char line[1024];
  while (fgets(line, sizeof line, f)) {
    size_t l = strlen(line);
    while (l && (line[l - 1] == '\n' || line[l - 1] == '\r' || line[l - 1] == ' ')) line[--l] = 0;
    if (l) snprintf(buf, n, "%s", line);
  }
  fclose(f);
}

static jnd_status write_record(run_ctx *c, const jnd_batch_row *r, const slot *s, jnd_asset_status st, int code,
                               int sig, const char *error, double seconds, const char *command_line) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "jnd_version", jnd_version());
  cJSON_AddStringToObject(o, "id", r->id);
  cJSON_AddStringToObject(o, "command", r->command);
  cJSON_AddStringToObject(o, "asset", r->asset);
  cJSON_AddStringToObject(o, "options", r->options);
  cJSON_AddStringToObject(o, "status", jnd_asset_status_name(st));
  if (sig) { /* killed: no exit status */
    cJSON_AddNullToObject(o, "exit_status");
    cJSON_AddNumberToObject(o, "signal", sig);
  } else {
    cJSON_AddNumberToObject(o, "exit_status", code);
  }
  if (error) cJSON_AddStringToObject(o, "error", error);
  cJSON_AddNumberToObject(o, "seconds", round(seconds * 1000) / 1000);
  char host[256] = "";
  gethostname(host, sizeof host - 1);
  cJSON_AddStringToObject(o, "host", host);
  cJSON_AddStringToObject(o, "command_line", command_line ? command_line : "");
  char log[JND_BATCH_MAX_ID + 32];
  snprintf(log, sizeof log, JND_BATCH_DIR "/logs/%s.log", r->id);
  cJSON_AddStringToObject(o, "log", log);
  cJSON_AddStringToObject(o, "fingerprint", s->fp);
  char name[JND_BATCH_MAX_ID + 8];
  snprintf(name, sizeof name, "%s.json", r->id);
  char *path = jnd_path_join(c->records, name);
  jnd_status res = path ? jnd_json_write(path, o) : JND_ERR_NOMEM;
  free(path);
  cJSON_Delete(o);
  return res;
}

/* how the asset's command can be run again by hand: its words, with the
 * work folder shown as the result's folder */
static char *command_line(run_ctx *c, const jnd_batch_row *r, const jnd_batch_command *cmd) {
  char *dst = jnd_path_join(c->out, r->id);
  char **argv = dst ? child_argv(cmd, r, "jnd", dst) : NULL;
  free(dst);
  if (!argv) return NULL;
  int n = 0;
  while (argv[n]) n++;
  char *line = jnd_shell_join(n - 1, argv); /* without the trailing --quiet */
  jnd_words_free(n, argv);
  return line;
}

/* steps 3 and 4 */
static jnd_status finish(run_ctx *c, slot *s, int wstatus) {
  const jnd_batch_row *r = &c->m->rows[s->row];
  const jnd_batch_command *cmd = jnd_batch_command_find(r->command);
  double seconds = jnd_seconds() - s->t0;
  int code = -1, sig = 0;
  if (WIFEXITED(wstatus)) code = WEXITSTATUS(wstatus);
  else if (WIFSIGNALED(wstatus)) sig = WTERMSIG(wstatus);
  jnd_asset_status st = code == 0 || (code == 1 && cmd->exit1_complete) ? JND_ASSET_OK : JND_ASSET_FAILED;
  if (code == 1 && st == JND_ASSET_OK) st = JND_ASSET_ABOVE;
  char *out = jnd_path_join(s->work, "out"), *log = jnd_path_join(s->work, "log.txt");
  char *json = out ? jnd_path_join(out, cmd->json_name) : NULL;
  char *dst = jnd_path_join(c->out, r->id), *old = jnd_path_join(s->work, "old");
  char logname[JND_BATCH_MAX_ID + 8];
  snprintf(logname, sizeof logname, "%s.log", r->id);
  char *log_dst = jnd_path_join(c->logs, logname);
  char *line = command_line(c, r, cmd);
  if (!out || !log || !json || !dst || !old || !log_dst || !line) {
    free(out), free(log), free(json), free(dst), free(old), free(log_dst), free(line);
    return JND_ERR_NOMEM;
  }
  char error[600] = "", tail[512];
  last_line(log, tail, sizeof tail);
  if (st != JND_ASSET_FAILED) {
    cJSON *doc = jnd_json_read(json);
    if (!doc) {
      st = JND_ASSET_FAILED;
      snprintf(error, sizeof error, "%s exited %d but its report is missing or unreadable: %s", cmd->name, code,
               jnd_last_error());
    }
    cJSON_Delete(doc);
  } else if (s->timed_out) {
    snprintf(error, sizeof error, "timed out after %g s (killed)", c->p->timeout_s);
  } else if (sig) {
    snprintf(error, sizeof error, "killed by signal %d (%s)%s%s", sig, strsignal(sig), tail[0] ? ": " : "", tail);
  } else if (tail[0]) {
    snprintf(error, sizeof error, "%s", tail);
  } else {
    snprintf(error, sizeof error, "exit status %d without a message", code);
  }
  jnd_status res = JND_OK;
  if (rename(log, log_dst) != 0) res = jnd_fail(JND_ERR_IO, "%s: cannot write: %s", log_dst, strerror(errno));
  if (res == JND_OK && st != JND_ASSET_FAILED) {
    struct stat sb;
    if (lstat(dst, &sb) == 0 && rename(dst, old) != 0)
      res = jnd_fail(JND_ERR_IO, "%s: cannot move the previous result aside: %s", dst, strerror(errno));
    if (res == JND_OK && rename(out, dst) != 0) {
      res = jnd_fail(JND_ERR_IO, "%s: cannot move the result in: %s", dst, strerror(errno));
      rename(old, dst); /* the previous result goes back where it was */
    }
  }
  if (res == JND_OK)
    res = write_record(c, r, s, st, code, sig, st == JND_ASSET_FAILED ? error : NULL, seconds, line);
  if (res == JND_OK) res = jnd_remove_tree(s->work);
  if (res == JND_OK)
    emit(c, r, st, 0, sig || s->timed_out ? -1 : code, st == JND_ASSET_FAILED ? error : NULL, seconds);
  free(out), free(log), free(json), free(dst), free(old), free(log_dst), free(line);
  return res;
}

static jnd_status check_params(const jnd_batch_params *p) {
  if (!p->out_dir || !p->out_dir[0]) return jnd_fail(JND_ERR_ARG, "batch: no output folder");
  if (p->shards < 1 || p->shard < 0 || p->shard >= p->shards)
    return jnd_fail(JND_ERR_ARG, "shard %d/%d: the index must be in 0..count-1", p->shard, p->shards);
  if (p->jobs < 1 || p->jobs > MAX_JOBS) return jnd_fail(JND_ERR_ARG, "batch: jobs %d is outside 1..%d", p->jobs, MAX_JOBS);
  if (p->threads < 0 || p->threads > 1024) return jnd_fail(JND_ERR_ARG, "batch: threads %d is outside 0..1024", p->threads);
  if (!(p->timeout_s >= 0) || p->timeout_s > 1e7) return jnd_fail(JND_ERR_ARG, "batch: timeout %g s is out of range", p->timeout_s);
  return JND_OK;
}

static jnd_status prepare(run_ctx *c, const jnd_batch_manifest *m, const jnd_batch_params *p) {
  jnd_status s = jnd_mkdirs(p->out_dir);
  if (s != JND_OK) return s;
  char real[PATH_MAX];
  if (!realpath(p->out_dir, real)) return jnd_fail(JND_ERR_IO, "%s: %s", p->out_dir, strerror(errno));
  c->out = strdup(real);
  c->records = c->out ? path3(c->out, JND_BATCH_DIR, "records") : NULL;
  c->logs = c->out ? path3(c->out, JND_BATCH_DIR, "logs") : NULL;
  c->work = c->out ? path3(c->out, JND_BATCH_DIR, "work") : NULL;
  if (!c->records || !c->logs || !c->work) return JND_ERR_NOMEM;
  if ((s = jnd_mkdirs(c->records)) != JND_OK || (s = jnd_mkdirs(c->logs)) != JND_OK || (s = jnd_mkdirs(c->work)) != JND_OK)
    return s;
  /* step 1: every shard writes the same plan; merge reads it */
  cJSON *plan = jnd_batch_plan_json(m);
  char *path = path3(c->out, JND_BATCH_DIR, "manifest.json");
  s = plan && path ? jnd_json_write(path, plan) : JND_ERR_NOMEM;
  cJSON_Delete(plan);
  free(path);
  return s;
}

jnd_status jnd_batch_run(const jnd_batch_manifest *m, const jnd_batch_params *p, jnd_batch_totals *totals) {
  jnd_batch_totals local;
  if (!totals) totals = &local;
  memset(totals, 0, sizeof *totals);
  jnd_status s = check_params(p);
  if (s != JND_OK) return s;
  run_ctx c = {.m = m, .p = p, .tot = totals, .t0 = jnd_seconds()};
  slot *slots = jnd_calloc((size_t)p->jobs, sizeof *slots);
  int *rows = jnd_calloc((size_t)m->nrows + 1, sizeof *rows);
  if (!slots || !rows) s = JND_ERR_NOMEM;
  if (s == JND_OK) s = prepare(&c, m, p);
  int nrows = 0;
  for (int i = 0; i < m->nrows; i++)
    if (i % p->shards == p->shard) rows[nrows++] = i;
  c.total = totals->assets = nrows;
  int next = 0, running = 0;
  while (s == JND_OK && (next < nrows || running > 0)) {
    /* fill the free slots */
    while (s == JND_OK && next < nrows && running < p->jobs) {
      const jnd_batch_row *r = &m->rows[rows[next++]];
      if (r->error) {
        emit(&c, r, JND_ASSET_FAILED, 0, -2, r->error, 0);
        continue;
      }
      char *fp = fingerprint(m, r);
      if (!fp) {
        s = JND_ERR_NOMEM;
        break;
      }
      jnd_asset_status done = p->force ? JND_ASSET_PENDING : complete(&c, r, fp);
      if (done != JND_ASSET_PENDING) {
        emit(&c, r, done, 1, done == JND_ASSET_ABOVE ? 1 : 0, NULL, 0);
        free(fp);
        continue;
      }
      int k = 0;
      while (slots[k].pid) k++;
      s = start(&c, rows[next - 1], &slots[k]);
      slots[k].fp = fp;
      if (s == JND_OK) {
        running++;
        totals->ran++;
      } else {
        free(slots[k].work);
        free(fp);
        memset(&slots[k], 0, sizeof slots[k]);
      }
    }
    /* reap what ended; kill what ran out of time */
    int reaped = 0;
    for (int k = 0; k < p->jobs && running > 0; k++) {
      if (!slots[k].pid) continue;
      int ws;
      pid_t w = waitpid(slots[k].pid, &ws, WNOHANG);
      if (w == slots[k].pid) {
        jnd_status fs = finish(&c, &slots[k], ws);
        if (s == JND_OK) s = fs;
        free(slots[k].work);
        free(slots[k].fp);
        memset(&slots[k], 0, sizeof slots[k]);
        running--;
        reaped++;
      } else if (p->timeout_s > 0 && !slots[k].timed_out && jnd_seconds() - slots[k].t0 > p->timeout_s) {
        kill(slots[k].pid, SIGKILL);
        slots[k].timed_out = 1;
      }
    }
    if (!reaped && running > 0) nanosleep(&(struct timespec){0, 20 * 1000 * 1000}, NULL);
    if (s != JND_OK) {
      /* a run-wide error: let the running commands finish, so that nothing is left behind half-written */
      for (int k = 0; k < p->jobs; k++)
        if (slots[k].pid) {
          int ws;
          waitpid(slots[k].pid, &ws, 0);
          free(slots[k].work);
          free(slots[k].fp);
          memset(&slots[k], 0, sizeof slots[k]);
        }
      running = 0;
    }
  }
  totals->pending = totals->assets - totals->ok - totals->above - totals->failed;
  free(slots);
  free(rows);
  free(c.out);
  free(c.records);
  free(c.logs);
  free(c.work);
  return s;
}

char *jnd_batch_run_report(const jnd_batch_manifest *m, const jnd_batch_params *p, const jnd_batch_totals *t) {
  cJSON *r = report_new("batch");
  cJSON_AddStringToObject(report_section(r, "inputs"), "manifest", m->source);
  cJSON *par = report_section(r, "parameters");
  cJSON_AddNumberToObject(par, "shard", p->shard);
  cJSON_AddNumberToObject(par, "shards", p->shards);
  cJSON_AddNumberToObject(par, "jobs", p->jobs);
  cJSON_AddNumberToObject(par, "timeout_s", p->timeout_s);
  cJSON_AddBoolToObject(par, "force", p->force);
  cJSON *res = report_section(r, "result");
  cJSON_AddNumberToObject(res, "assets", t->assets);
  cJSON_AddNumberToObject(res, "ran", t->ran);
  cJSON_AddNumberToObject(res, "skipped", t->skipped);
  cJSON_AddNumberToObject(res, "ok", t->ok);
  cJSON_AddNumberToObject(res, "above", t->above);
  cJSON_AddNumberToObject(res, "failed", t->failed);
  char *text = report_text(r);
  cJSON_Delete(r);
  return text;
}
