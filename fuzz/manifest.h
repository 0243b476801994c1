/* Shared by fuzz_manifest_csv and fuzz_manifest_json: what a parsed manifest
 * promises whatever the bytes were. Every row has its four strings; a row
 * without an error has a valid id, a known command and its option words, and
 * no other such row has the same id (ignoring case); a row's error is one
 * line naming the manifest. A refusal leaves nothing and says why. */
#ifndef JND_FUZZ_MANIFEST_H
#define JND_FUZZ_MANIFEST_H
#include <ctype.h>
#include <string.h>
#include <strings.h>

#include "batch/batch.h"
#include "fuzz.h"

static inline void fuzz_check_manifest(jnd_status s, jnd_batch_manifest *m, const char *name) {
  if (s != JND_OK) {
    if (m->rows || m->nrows) abort();
    if (!jnd_last_error()[0]) abort();
    return;
  }
  if (m->nrows < 1 || !m->rows) abort();
  for (int i = 0; i < m->nrows; i++) {
    const jnd_batch_row *r = &m->rows[i];
    if (!r->id || !r->asset || !r->command || !r->options) abort();
    if (r->error) {
      if (strncmp(r->error, name, strlen(name)) != 0 || strchr(r->error, '\n')) abort();
      continue;
    }
    if (!jnd_batch_command_find(r->command)) abort();
    if (!isalnum((unsigned char)r->id[0]) || strlen(r->id) > JND_BATCH_MAX_ID) abort();
    if (r->argc < 0 || (r->argc > 0 && !r->argv)) abort();
    for (int k = 0; k < r->argc; k++)
      if (!r->argv[k]) abort();
    for (int j = 0; j < i; j++)
      if (!m->rows[j].error && strcasecmp(m->rows[j].id, r->id) == 0) abort();
  }
  jnd_batch_manifest_free(m);
}
#endif
