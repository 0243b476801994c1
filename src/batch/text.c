/* A growing text buffer for the files the batch layer writes (HTML pages,
 * CSV, job scripts, JSON paths), with the escapes each of them needs. A
 * failed allocation sets a sticky flag instead of failing every append; the
 * caller checks it once, when the text is complete. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "batch/batch.h"
#include "core/core.h"

static int grow(jnd_text *t, size_t more) {
  if (t->failed) return 0;
  if (t->len + more + 1 <= t->cap) return 1;
  size_t cap = t->cap ? t->cap : 256;
  while (cap < t->len + more + 1) {
    if (cap > ((size_t)1 << 40)) {
      t->failed = 1;
      return 0;
    }
    cap *= 2;
  }
  char *p = realloc(t->s, cap);
  if (!p) {
    t->failed = 1;
    return 0;
  }
  t->s = p;
  t->cap = cap;
  return 1;
}

void jnd_text_free(jnd_text *t) {
  free(t->s);
  memset(t, 0, sizeof *t);
}

void jnd_text_putn(jnd_text *t, const char *s, size_t n) {
  if (!grow(t, n)) return;
  memcpy(t->s + t->len, s, n);
  t->len += n;
  t->s[t->len] = 0;
}

void jnd_text_put(jnd_text *t, const char *s) { jnd_text_putn(t, s, strlen(s)); }

void jnd_text_printf(jnd_text *t, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  char small[256];
  int n = vsnprintf(small, sizeof small, fmt, ap);
  va_end(ap);
  if (n < 0) {
    t->failed = 1;
    return;
  }
  if ((size_t)n < sizeof small) {
    jnd_text_putn(t, small, (size_t)n);
    return;
  }
  if (!grow(t, (size_t)n)) return;
  va_start(ap, fmt);
  vsnprintf(t->s + t->len, (size_t)n + 1, fmt, ap);
  va_end(ap);
  t->len += (size_t)n;
}

void jnd_text_html(jnd_text *t, const char *s) {
  for (; s && *s; s++) switch (*s) {
      case '&': jnd_text_put(t, "&amp;"); break;
      case '<': jnd_text_put(t, "&lt;"); break;
      case '>': jnd_text_put(t, "&gt;"); break;
      case '"': jnd_text_put(t, "&quot;"); break;
      case '\'': jnd_text_put(t, "&#39;"); break;
      default: jnd_text_putn(t, s, 1);
    }
}

/* RFC 4180: a field with a comma, quote or line break is quoted, quotes doubled */
void jnd_text_csv(jnd_text *t, const char *s) {
  if (!s) return;
  if (!strpbrk(s, ",\"\r\n")) {
    jnd_text_put(t, s);
    return;
  }
  jnd_text_put(t, "\"");
  for (; *s; s++) jnd_text_put(t, *s == '"' ? "\"\"" : (char[2]){*s, 0});
  jnd_text_put(t, "\"");
}

/* a word a POSIX shell reads back as itself: bare when it is only safe
 * characters, else in single quotes with each ' written as '\'' */
void jnd_text_shell(jnd_text *t, const char *s) {
  if (*s && strspn(s, "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-.,/:=+@%") == strlen(s)) {
    jnd_text_put(t, s);
    return;
  }
  jnd_text_put(t, "'");
  for (; *s; s++) {
    if (*s == '\'') jnd_text_put(t, "'\\''");
    else jnd_text_putn(t, s, 1);
  }
  jnd_text_put(t, "'");
}

char *jnd_text_take(jnd_text *t) {
  if (t->failed) {
    jnd_text_free(t);
    jnd_fail(JND_ERR_NOMEM, "out of memory");
    return NULL;
  }
  if (!t->s) {
    if (!grow(t, 0)) return NULL;
    t->s[0] = 0;
  }
  char *s = t->s;
  memset(t, 0, sizeof *t);
  return s;
}
