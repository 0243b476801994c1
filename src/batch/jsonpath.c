/* Paths into a command's JSON report, so that the table of commands can say
 * where a number is ("result.memory.before_bytes") instead of each command
 * carrying code to find it: dots step into objects, [] steps into every
 * element of a list, [N] into one. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "batch/batch.h"

static int select_from(const cJSON *node, const char *path, const cJSON **out, int max, int found) {
  if (!node) return found;
  while (*path == '.') path++;
  if (!*path) {
    if (found < max) out[found] = node;
    return found + 1;
  }
  if (*path == '[') {
    const char *close = strchr(path, ']');
    if (!close || !cJSON_IsArray(node)) return found;
    if (close == path + 1) {
      const cJSON *e;
      cJSON_ArrayForEach(e, node) found = select_from(e, close + 1, out, max, found);
      return found;
    }
    char *end;
    long i = strtol(path + 1, &end, 10);
    if (end != close || i < 0) return found;
    return select_from(cJSON_GetArrayItem(node, (int)i), close + 1, out, max, found);
  }
  size_t n = strcspn(path, ".[");
  char key[128];
  if (n >= sizeof key || !cJSON_IsObject(node)) return found;
  memcpy(key, path, n);
  key[n] = 0;
  return select_from(cJSON_GetObjectItemCaseSensitive(node, key), path + n, out, max, found);
}

int jnd_json_select(const cJSON *root, const char *path, const cJSON **out, int max) {
  return select_from(root, path, out, max, 0);
}

double jnd_json_number(const cJSON *root, const char *path) {
  if (!path) return NAN;
  if (strncmp(path, "max:", 4) == 0) {
    /* the largest of the numbers the path selects */
    const cJSON *v[1024];
    int n = jnd_json_select(root, path + 4, v, 1024);
    double m = NAN;
    for (int i = 0; i < n && i < 1024; i++)
      if (cJSON_IsNumber(v[i]) && !(v[i]->valuedouble <= m)) m = v[i]->valuedouble;
    return m;
  }
  const cJSON *v[1];
  if (jnd_json_select(root, path, v, 1) != 1 || !cJSON_IsNumber(v[0])) return NAN;
  return v[0]->valuedouble;
}
