/* A manifest row's options are one shell-quoted string ("--views 8 --maps
 * 'body/baseColor'"). They are split into words the way a POSIX shell splits
 * them (quotes, backslashes), but never expanded: no shell runs, so text
 * that a shell would expand or interpret ($HOME, *.png, ~, ;, |, >) is refused
 * unquoted instead of being passed on with a meaning the user did not get. */
#include <stdlib.h>
#include <string.h>

#include "batch/batch.h"
#include "core/core.h"

#define MAX_WORDS 4096
#define MAX_OPTIONS_BYTES (64 << 10)

void jnd_words_free(int argc, char **argv) {
  if (!argv) return;
  for (int i = 0; i < argc; i++) free(argv[i]);
  free(argv);
}

static int add_word(jnd_text *w, int *argc, char ***argv, int *cap) {
  if (*argc == MAX_WORDS) return -1;
  if (*argc == *cap) {
    int nc = *cap ? *cap * 2 : 8;
    char **na = realloc(*argv, sizeof *na * (size_t)nc);
    if (!na) return 0;
    *argv = na;
    *cap = nc;
  }
  char *s = jnd_text_take(w);
  if (!s) return 0;
  (*argv)[(*argc)++] = s;
  return 1;
}

jnd_status jnd_shell_split(const char *s, int *argc_out, char ***argv_out) {
  *argc_out = 0;
  *argv_out = NULL;
  if (strlen(s) > MAX_OPTIONS_BYTES)
    return jnd_fail(JND_ERR_LIMIT, "options are longer than %d bytes", MAX_OPTIONS_BYTES);
  int argc = 0, cap = 0;
  char **argv = NULL;
  jnd_text w = {0};
  int in_word = 0;
  const char *why = NULL;
  char bad[2] = {0, 0};
  for (const char *p = s;; p++) {
    char c = *p;
    if (c == 0 || c == ' ' || c == '\t' || c == '\n' || c == '\r') {
      if (in_word) {
        int r = add_word(&w, &argc, &argv, &cap);
        if (r <= 0) {
          why = r < 0 ? "more than 4096 words" : "out of memory";
          break;
        }
        in_word = 0;
      }
      if (c == 0) break;
      continue;
    }
    if (c == '\'') {
      const char *e = strchr(p + 1, '\'');
      if (!e) {
        why = "a ' is not closed";
        break;
      }
      jnd_text_putn(&w, p + 1, (size_t)(e - p - 1));
      if (!w.s) jnd_text_put(&w, ""); /* '' is an empty word */
      in_word = 1;
      p = e;
      continue;
    }
    if (c == '"') {
      p++;
      for (; *p && *p != '"'; p++) {
        if (*p == '\\' && p[1] && strchr("\"\\$`\n", p[1])) {
          p++;
        } else if (*p == '$' || *p == '`') {
          bad[0] = *p;
          why = "expands inside double quotes, which jnd batch does not do: use single quotes";
          break;
        }
        jnd_text_putn(&w, p, 1);
      }
      if (why) break;
      if (!*p) {
        why = "a \" is not closed";
        break;
      }
      if (!w.s) jnd_text_put(&w, "");
      in_word = 1;
      continue;
    }
    if (c == '\\') {
      if (!p[1]) {
        why = "a \\ ends the options";
        break;
      }
      p++;
      jnd_text_putn(&w, p, 1);
      in_word = 1;
      continue;
    }
    if (strchr("$`;&|<>()*?[", c) || (!in_word && (c == '~' || c == '#'))) {
      bad[0] = c;
      why = "is shell syntax that jnd batch does not interpret (no shell runs): quote it";
      break;
    }
    jnd_text_putn(&w, p, 1);
    in_word = 1;
  }
  if (!why && w.failed) why = "out of memory";
  jnd_text_free(&w);
  if (why) {
    jnd_words_free(argc, argv);
    if (bad[0]) return jnd_fail(JND_ERR_FORMAT, "options: '%s' %s", bad, why);
    return jnd_fail(JND_ERR_FORMAT, "options: %s", why);
  }
  *argc_out = argc;
  *argv_out = argv;
  return JND_OK;
}

char *jnd_shell_join(int argc, char *const *argv) {
  jnd_text t = {0};
  for (int i = 0; i < argc; i++) {
    if (i) jnd_text_put(&t, " ");
    jnd_text_shell(&t, argv[i]);
  }
  return jnd_text_take(&t);
}
