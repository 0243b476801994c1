/* libFuzzer target: the views parser behind `jnd render --cameras`
 * (jnd_views_parse) on arbitrary text. Parsed views must be usable by the
 * renderer: a field of view in (0°, 180°), finite eye and target apart, at
 * most JND_MAX_LIGHTS lights; a refusal returns no views and a message. */
#include <string.h>

#include "fuzz.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const double centre[3] = {0, 0, 0};
  jnd_view *views = NULL;
  int n = 0;
  jnd_status s = jnd_views_parse("fuzz.json", (const char *)data, size, centre, 45, &views, &n);
  if (s != JND_OK) {
    if (views || n) abort();
    if (!jnd_last_error()[0]) abort();
    return 0;
  }
  if (!views || n < 1) abort();
  for (int i = 0; i < n; i++) {
    const jnd_camera *c = &views[i].camera;
    if (!(c->fov_y_deg > 0 && c->fov_y_deg < 180)) abort();
    double d = 0;
    for (int k = 0; k < 3; k++) {
      if (!isfinite(c->eye[k]) || !isfinite(c->target[k])) abort();
      d += (c->eye[k] - c->target[k]) * (c->eye[k] - c->target[k]);
    }
    if (!(d > 0)) abort();
    if (views[i].nlights > JND_MAX_LIGHTS) abort();
  }
  free(views);
  return 0;
}
