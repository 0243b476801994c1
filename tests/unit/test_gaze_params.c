/* Fitted parameters of 002's models read back (jnd gaze --params): each
 * value lands in its own field, the ranges docs/gaze.md gives are open or
 * closed where it says, a fit report holds w_g at 1, a report of one model
 * leaves the other's fields alone, and a refused file changes nothing. No
 * rendering: a few milliseconds. */
#include <math.h>

#include "jnd.h"
#include "test.h"

/* a spatial fit report with the given gamma and k_s (others fixed), as
 * jnd gaze fit writes it */
static jnd_status parse_spatial(const char *k_s, const char *gamma, const char *alpha, jnd_gaze_model *m) {
  char text[1024];
  snprintf(text, sizeof text,
           "{\"command\": \"gaze fit\", \"parameters\": {\"b\": 3.5}, \"result\": {\"model\": \"spatial\","
           " \"parameters\": {\"alpha\": {\"value\": %s}, \"beta\": {\"value\": 0.2}, \"s_deg\": {\"value\": -90},"
           " \"w_vdp\": {\"value\": 0}, \"k_s\": {\"value\": %s}, \"gamma\": {\"value\": %s}}}}",
           alpha, k_s, gamma);
  return jnd_gaze_model_parse("sp.json", text, strlen(text), m);
}

static jnd_gaze_model marked(void) {
  jnd_gaze_model m;
  jnd_gaze_model_defaults(&m);
  m.w_g = 7, m.w_t = 8, m.gamma_t = 9;
  return m;
}

TEST(each_fitted_value_lands_in_its_own_field) {
  jnd_gaze_model m = marked();
  CHECK_OK(parse_spatial("1.5", "3.25", "4.5", &m));
  CHECK(m.alpha == 4.5 && m.beta == 0.2 && m.s_deg == -90 && m.w_vdp == 0 && m.k_s == 1.5 && m.gamma == 3.25);
  CHECK(m.b == 3.5);
  CHECK(m.w_g == 1);                     /* the fit holds w_g at 1 (docs/gaze.md "Fitting") */
  CHECK(m.w_t == 8 && m.gamma_t == 9);   /* a spatial report leaves the temporal model alone */
  const char *tm = "{\"result\": {\"model\": \"temporal\", \"parameters\": {\"w_t\": {\"value\": 2.5}, \"gamma_t\": 5.5}}}";
  jnd_gaze_model before = m;
  CHECK_OK(jnd_gaze_model_parse("tm.json", tm, strlen(tm), &m));
  CHECK(m.w_t == 2.5 && m.gamma_t == 5.5);
  CHECK(m.alpha == before.alpha && m.gamma == before.gamma && m.b == before.b && m.w_g == before.w_g);
  /* the combined form: its own w_g, the floor from "fixed" */
  const char *both = "{\"fixed\": {\"w_g\": 2, \"b\": 0}, \"spatial\": {\"parameters\": {\"alpha\": 1, \"beta\": 2,"
                     " \"s_deg\": 3, \"w_vdp\": 4, \"k_s\": 5, \"gamma\": 6}}, \"temporal\": {\"parameters\":"
                     " {\"w_t\": 0, \"gamma_t\": 7}}}";
  CHECK_OK(jnd_gaze_model_parse("both.json", both, strlen(both), &m));
  CHECK(m.w_g == 2 && m.b == 0 && m.alpha == 1 && m.beta == 2 && m.s_deg == 3 && m.w_vdp == 4 && m.k_s == 5 &&
        m.gamma == 6 && m.w_t == 0 && m.gamma_t == 7);
}

/* docs/gaze.md: k_s >= 1 (1: the terms add), gamma > 0, alpha > 0, s_deg in
 * [−90, 90], w_vdp, b and w_t >= 0, w_g > 0 */
TEST(ranges_are_open_or_closed_at_their_ends) {
  jnd_gaze_model m = marked();
  CHECK_OK(parse_spatial("1", "3", "4", &m));          /* k_s = 1 is the sum */
  CHECK(m.k_s == 1);
  m = marked();
  CHECK_STATUS(parse_spatial("0.999", "3", "4", &m), JND_ERR_FORMAT);
  CHECK(strstr(jnd_last_error(), "k_s") != NULL && strstr(jnd_last_error(), "[1,") != NULL);
  CHECK_STATUS(parse_spatial("1.5", "0", "4", &m), JND_ERR_FORMAT);   /* gamma > 0 */
  CHECK(strstr(jnd_last_error(), "gamma") != NULL && strstr(jnd_last_error(), "(0,") != NULL);
  CHECK_STATUS(parse_spatial("1.5", "3", "0", &m), JND_ERR_FORMAT);   /* alpha > 0 */
  CHECK_STATUS(parse_spatial("1.5", "3", "1e7", &m), JND_ERR_FORMAT); /* above its top */
  CHECK_OK(parse_spatial("1.5", "1000", "1e6", &m));                   /* the tops are valid */
  const char *wg0 = "{\"fixed\": {\"w_g\": 0, \"b\": 0}, \"spatial\": {\"parameters\": {\"alpha\": 1, \"beta\": 2,"
                    " \"s_deg\": 3, \"w_vdp\": 4, \"k_s\": 5, \"gamma\": 6}}}";
  CHECK_STATUS(jnd_gaze_model_parse("wg.json", wg0, strlen(wg0), &m), JND_ERR_FORMAT);
  CHECK(strstr(jnd_last_error(), "fixed.w_g") != NULL);
}

TEST(a_refused_file_changes_nothing) {
  jnd_gaze_model m = marked(), before = m;
  /* gamma refused after alpha, beta, ... were read */
  CHECK_STATUS(parse_spatial("1.5", "-1", "4.5", &m), JND_ERR_FORMAT);
  CHECK(memcmp(&m, &before, sizeof m) == 0);
  const char *half = "{\"spatial\": {\"parameters\": {\"alpha\": 1, \"beta\": 2, \"s_deg\": 3, \"w_vdp\": 4, \"k_s\": 5,"
                     " \"gamma\": 6}}}";   /* no "fixed" */
  CHECK_STATUS(jnd_gaze_model_parse("half.json", half, strlen(half), &m), JND_ERR_FORMAT);
  CHECK(memcmp(&m, &before, sizeof m) == 0);
  const char *both = "{\"result\": {\"model\": \"both\"}}";
  CHECK_STATUS(jnd_gaze_model_parse("x.json", both, strlen(both), &m), JND_ERR_FORMAT);
  CHECK(strstr(jnd_last_error(), "x.json") == jnd_last_error());
}

RUN_TESTS(each_fitted_value_lands_in_its_own_field, ranges_are_open_or_closed_at_their_ends, a_refused_file_changes_nothing)
