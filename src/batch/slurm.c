/* A batch on a Slurm cluster: the scheduler the cluster already runs does the
 * scheduling, never jnd. A job array has one task per shard; each task runs
 * `jnd batch --shard $SLURM_ARRAY_TASK_ID/N` on whatever node Slurm gives it
 * (all of them see OUT on a shared file system); a second job, dependent on
 * the whole array finishing well (afterok), merges and writes the report.
 * Every value that goes into a script is checked or shell-quoted, so a
 * manifest path or a flag cannot inject a line into it. */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "batch/batch.h"
#include "core/core.h"

void jnd_slurm_defaults(jnd_slurm_params *p) {
  memset(p, 0, sizeof *p);
  p->shards = 1;
  p->cpus_per_task = 1;
  p->job_name = "jnd-batch";
}

static int only(const char *s, const char *allowed) { return s && *s && strspn(s, allowed) == strlen(s); }

#define DIGITS "0123456789"
#define NAME_CHARS "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.-"

/* sbatch's time formats: M, M:S, H:M:S, D-H, D-H:M, D-H:M:S */
static int time_valid(const char *t) {
  if (!only(t, DIGITS ":-") || strlen(t) > 16) return 0;
  const char *dash = strchr(t, '-');
  if (dash && (dash == t || strchr(dash + 1, '-') || !dash[1])) return 0;
  int colons = 0;
  for (const char *c = t; *c; c++) {
    if (*c == ':') {
      colons++;
      if (c == t || c[-1] == ':' || c[-1] == '-' || !c[1]) return 0;
    }
  }
  return colons <= 2;
}

static jnd_status check(const jnd_slurm_params *sp) {
  if (sp->shards < 1 || sp->shards > 100000) return jnd_fail(JND_ERR_ARG, "slurm: --shards %d is outside 1..100000", sp->shards);
  if (sp->array_limit < 0) return jnd_fail(JND_ERR_ARG, "slurm: --array-limit %d is negative", sp->array_limit);
  if (sp->cpus_per_task < 1 || sp->cpus_per_task > 4096)
    return jnd_fail(JND_ERR_ARG, "slurm: --cpus-per-task %d is outside 1..4096", sp->cpus_per_task);
  if (sp->mem) {
    size_t n = strspn(sp->mem, DIGITS);
    if (n == 0 || (sp->mem[n] && (!strchr("KMGTkmgt", sp->mem[n]) || sp->mem[n + 1])))
      return jnd_fail(JND_ERR_ARG, "slurm: --mem '%s': expected a size such as 4000, 500M or 4G", sp->mem);
  }
  if (sp->time && !time_valid(sp->time))
    return jnd_fail(JND_ERR_ARG, "slurm: --time '%s': expected minutes, H:M:S or D-H:M:S", sp->time);
  const char *names[3] = {sp->partition, sp->account, sp->job_name};
  const char *what[3] = {"--partition", "--account", "--job-name"};
  for (int i = 0; i < 3; i++)
    if (names[i] && !only(names[i], NAME_CHARS ","))
      return jnd_fail(JND_ERR_ARG, "slurm: %s '%s' holds characters a Slurm name does not", what[i], names[i]);
  if (sp->gres && !only(sp->gres, NAME_CHARS ":,"))
    return jnd_fail(JND_ERR_ARG, "slurm: --gres '%s' holds characters a GRES does not", sp->gres);
  for (int i = 0; i < sp->nextra; i++) {
    const char *e = sp->extra[i];
    if (strncmp(e, "--", 2) != 0 || !isalpha((unsigned char)e[2]) || strpbrk(e, "\n\r"))
      return jnd_fail(JND_ERR_ARG, "slurm: '%s' is not one sbatch option of the form --name=value", e);
  }
  return JND_OK;
}

static char *absolute(const char *path) {
  if (path[0] == '/') return strdup(path);
  char cwd[PATH_MAX];
  if (!getcwd(cwd, sizeof cwd)) return NULL;
  return jnd_path_join(cwd, path);
}

static void header(jnd_text *t, const jnd_slurm_params *sp, const char *name, const char *log) {
  jnd_text_printf(t, "#!/bin/bash\n# written by jnd %s (jnd batch --slurm); docs/batch.md\n", jnd_version());
  jnd_text_printf(t, "#SBATCH --job-name=%s\n", name);
  jnd_text_printf(t, "#SBATCH --output=%s\n", log);
  if (sp->time) jnd_text_printf(t, "#SBATCH --time=%s\n", sp->time);
  if (sp->partition) jnd_text_printf(t, "#SBATCH --partition=%s\n", sp->partition);
  if (sp->account) jnd_text_printf(t, "#SBATCH --account=%s\n", sp->account);
}

jnd_status jnd_slurm_scripts(const jnd_batch_manifest *m, const char *glob_command, const char *glob_options,
                             const jnd_batch_params *run, const jnd_slurm_params *sp, char **array_script,
                             char **merge_script) {
  *array_script = *merge_script = NULL;
  jnd_status s = check(sp);
  if (s != JND_OK) return s;
  if (!run->out_dir || !run->out_dir[0]) return jnd_fail(JND_ERR_ARG, "slurm: no output folder");
  char *out = absolute(run->out_dir), *exe = absolute(run->jnd_exe ? run->jnd_exe : "jnd");
  char *logdir = out ? jnd_path_join(out, JND_BATCH_DIR "/slurm") : NULL;
  if (run->jnd_exe && !strchr(run->jnd_exe, '/')) { /* a bare name: found on the nodes' PATH */
    free(exe);
    exe = strdup(run->jnd_exe);
  }
  if (!out || !exe || !logdir) {
    free(out), free(exe), free(logdir);
    return jnd_fail(JND_ERR_NOMEM, "out of memory");
  }
  if (strpbrk(out, " \t\n\r'\"\\%")) {
    /* #SBATCH lines are not shell lines: no quoting to hide these in */
    s = jnd_fail(JND_ERR_ARG, "slurm: %s: the output folder's path holds a blank, quote, backslash or %%, which "
                 "an #SBATCH --output line cannot carry", out);
    free(out), free(exe), free(logdir);
    return s;
  }
  jnd_text a = {0}, b = {0}, log = {0};
  /* ---- the array: one task per shard ---- */
  jnd_text_printf(&log, "%s/shard-%%a.log", logdir);
  header(&a, sp, sp->job_name ? sp->job_name : "jnd-batch", log.s ? log.s : "");
  jnd_text_printf(&a, "#SBATCH --array=0-%d", sp->shards - 1);
  if (sp->array_limit > 0) jnd_text_printf(&a, "%%%d", sp->array_limit);
  jnd_text_printf(&a, "\n#SBATCH --ntasks=1\n#SBATCH --cpus-per-task=%d\n", sp->cpus_per_task);
  if (sp->mem) jnd_text_printf(&a, "#SBATCH --mem=%s\n", sp->mem);
  if (sp->gres) jnd_text_printf(&a, "#SBATCH --gres=%s\n", sp->gres);
  for (int i = 0; i < sp->nextra; i++) jnd_text_printf(&a, "#SBATCH %s\n", sp->extra[i]);
  int jobs = run->jobs > 0 ? run->jobs : 1;
  jnd_text_put(&a,
               "set -u\n"
               "# Tasks may share a node: OpenMP threads sleep while they wait, and the\n"
               "# asset commands of this task use the CPUs Slurm gave it, no more.\n"
               "export OMP_WAIT_POLICY=passive\n");
  if (run->threads > 0) jnd_text_printf(&a, "export OMP_NUM_THREADS=%d\n", run->threads);
  else
    jnd_text_printf(&a, "threads=$(( ${SLURM_CPUS_PER_TASK:-1} / %d ))\n[ \"$threads\" -ge 1 ] || threads=1\n"
                        "export OMP_NUM_THREADS=$threads\n", jobs);
  jnd_text_put(&a, "cd ");
  jnd_text_shell(&a, m->base_dir);
  jnd_text_put(&a, " || exit 2\nexec ");
  jnd_text_shell(&a, exe);
  jnd_text_put(&a, " batch ");
  if (glob_command) {
    /* the pattern relative to the folder it was given in, so that the assets
     * and ids are the same as a local run's */
    size_t nb = strlen(m->base_dir);
    const char *pat = m->source;
    if (strncmp(pat, m->base_dir, nb) == 0 && pat[nb] == '/') pat += nb + 1;
    jnd_text_shell(&a, pat);
    jnd_text_put(&a, " --command ");
    jnd_text_shell(&a, glob_command);
    jnd_text_put(&a, " --options ");
    jnd_text_shell(&a, glob_options ? glob_options : "");
  } else {
    jnd_text_shell(&a, m->source);
  }
  jnd_text_put(&a, " -o ");
  jnd_text_shell(&a, out);
  jnd_text_printf(&a, " --shard \"$SLURM_ARRAY_TASK_ID/%d\" --jobs %d", sp->shards, jobs);
  if (run->timeout_s > 0) jnd_text_printf(&a, " --timeout %g", run->timeout_s);
  if (run->force) jnd_text_put(&a, " --force");
  jnd_text_put(&a, "\n");
  /* ---- the merge, after every task ended well ---- */
  log.len = 0;
  jnd_text_printf(&log, "%s/merge.log", logdir);
  char merge_name[160];
  snprintf(merge_name, sizeof merge_name, "%s-merge", sp->job_name ? sp->job_name : "jnd-batch");
  header(&b, sp, merge_name, log.s ? log.s : "");
  jnd_text_put(&b, "#SBATCH --ntasks=1\n#SBATCH --cpus-per-task=1\n");
  for (int i = 0; i < sp->nextra; i++) jnd_text_printf(&b, "#SBATCH %s\n", sp->extra[i]);
  jnd_text_put(&b, "set -eu\n");
  jnd_text_shell(&b, exe);
  jnd_text_put(&b, " batch merge ");
  jnd_text_shell(&b, out);
  jnd_text_put(&b, "\nexec ");
  jnd_text_shell(&b, exe);
  jnd_text_put(&b, " report ");
  jnd_text_shell(&b, out);
  jnd_text_put(&b, "\n");
  jnd_text_free(&log);
  free(out), free(exe), free(logdir);
  *array_script = jnd_text_take(&a);
  *merge_script = jnd_text_take(&b);
  if (!*array_script || !*merge_script) {
    free(*array_script), free(*merge_script);
    *array_script = *merge_script = NULL;
    return JND_ERR_NOMEM;
  }
  return JND_OK;
}

/* runs sbatch with args; its job id (the --parsable answer up to ';') into id */
static jnd_status sbatch(char *const *args, char *id, size_t n) {
  int fds[2];
  if (pipe(fds) != 0) return jnd_fail(JND_ERR_IO, "sbatch: %s", strerror(errno));
  pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]), close(fds[1]);
    return jnd_fail(JND_ERR_IO, "sbatch: cannot start: %s", strerror(errno));
  }
  if (pid == 0) {
    dup2(fds[1], 1);
    dup2(fds[1], 2);
    close(fds[0]);
    close(fds[1]);
    execvp("sbatch", args);
    const char msg[] = "sbatch is not on PATH (is this a Slurm submit host?)\n";
    (void)!write(2, msg, sizeof msg - 1);
    _exit(127);
  }
  close(fds[1]);
  char buf[4096];
  size_t len = 0;
  ssize_t got;
  while ((got = read(fds[0], buf + len, sizeof buf - 1 - len)) > 0 || (got < 0 && errno == EINTR))
    if (got > 0) len += (size_t)got;
  close(fds[0]);
  buf[len] = 0;
  int ws;
  while (waitpid(pid, &ws, 0) < 0 && errno == EINTR) {
  }
  /* the last line it printed: the id, or what went wrong */
  while (len && (buf[len - 1] == '\n' || buf[len - 1] == '\r')) buf[--len] = 0;
  char *line = strrchr(buf, '\n');
  line = line ? line + 1 : buf;
  if (!WIFEXITED(ws) || WEXITSTATUS(ws) != 0)
    return jnd_fail(JND_ERR_IO, "sbatch failed: %s", line[0] ? line : "no message");
  size_t k = strspn(line, DIGITS);
  if (k == 0 || k >= n || (line[k] && line[k] != ';'))
    return jnd_fail(JND_ERR_IO, "sbatch answered '%s', not a job id", line);
  memcpy(id, line, k);
  id[k] = 0;
  return JND_OK;
}

jnd_status jnd_slurm_submit(const char *out_dir, const char *array_script, const char *merge_script,
                            char *array_job, char *merge_job, size_t n) {
  char *dir = jnd_path_join(out_dir, JND_BATCH_DIR "/slurm");
  char *pa = dir ? jnd_path_join(dir, "array.sh") : NULL, *pm = dir ? jnd_path_join(dir, "merge.sh") : NULL;
  jnd_status s = pa && pm ? JND_OK : JND_ERR_NOMEM;
  if (s == JND_OK) s = jnd_mkdirs(dir);
  if (s == JND_OK) s = jnd_write_file_atomic(pa, array_script, strlen(array_script));
  if (s == JND_OK) s = jnd_write_file_atomic(pm, merge_script, strlen(merge_script));
  if (s == JND_OK) {
    char *args[] = {"sbatch", "--parsable", pa, NULL};
    s = sbatch(args, array_job, n);
  }
  if (s == JND_OK) {
    char dep[96];
    snprintf(dep, sizeof dep, "--dependency=afterok:%s", array_job);
    char *args[] = {"sbatch", "--parsable", dep, pm, NULL};
    s = sbatch(args, merge_job, n);
  }
  free(dir), free(pa), free(pm);
  return s;
}
