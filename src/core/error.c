/* Errors as values: each function returns a jnd_status, and the message of the
 * last failure on the calling thread is kept for jnd_last_error(). */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "core/core.h"

static _Thread_local char last_error[1024];

jnd_status jnd_fail(jnd_status status, const char *fmt, ...) {
  /* formatted apart first: an argument may be jnd_last_error() itself
   * (a message that adds the file's name to a deeper one) */
  char buf[sizeof last_error];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  memcpy(last_error, buf, sizeof buf);
  /* one line: a message never carries a newline into the user's terminal */
  for (char *p = last_error; *p; p++)
    if (*p == '\n' || *p == '\r') *p = ' ';
  return status;
}

const char *jnd_last_error(void) { return last_error; }

const char *jnd_version(void) { return JND_VERSION_STRING; }
