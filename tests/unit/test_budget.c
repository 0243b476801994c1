/* jnd budget's step 7 (docs/budget.md): the separate candidate — texres's
 * sizes, pca's packing, lod's level, each chosen on its own views — is
 * taken instead of the joint choice only where it costs less (or the joint
 * choice is seen) and is unnoticed at p on the judge's views and on the
 * held-out views of every level of its chain. */
#include "test.h"

#include "jnd.h"
#include "tasks/tasks.h"

/* a joint choice (index 0) of cost joint and the separate one (index 1) of
 * cost sep, both verified on two levels that pass */
typedef struct {
  jnd_budget_candidate cand[2];
  jnd_budget_level chosen_levels[2], separate_levels[2];
  jnd_budget_result r;
} fixture;

static void make(fixture *f, double joint, double sep) {
  memset(f, 0, sizeof *f);
  f->cand[0] = (jnd_budget_candidate){.level = 0, .scale = -1, .cost = joint, .statistic = 0.05, .pass = 1,
                                      .searched_pass = 1};
  f->cand[1] = (jnd_budget_candidate){.level = 1, .scale = -2, .cost = sep, .statistic = 0.15, .pass = 1,
                                      .searched_pass = 0};
  for (int j = 0; j < 2; j++) {
    f->chosen_levels[j] = (jnd_budget_level){.level = j, .views = 4, .statistic = 0.05, .pass = 1};
    f->separate_levels[j] = (jnd_budget_level){.level = 1 + j, .views = 4, .statistic = 0.12, .pass = 1};
  }
  f->r.mode = 0;
  f->r.ncandidates = 2;
  f->r.candidates = f->cand;
  f->r.chosen = 0;
  f->r.separate = 1;
  f->r.levels = f->chosen_levels;
  f->r.nlevels = 2;
  f->r.separate_levels = f->separate_levels;
  f->r.nseparate_levels = 2;
  f->r.passes = 1;
}

TEST(the_separate_candidate_is_taken_where_it_is_cheaper_and_unnoticed_over_the_margin) {
  fixture f;
  make(&f, 1000, 900);
  CHECK(budget_take_separate(&f.r) == 1);
}

TEST(a_separate_candidate_that_costs_as_much_or_more_is_not_taken) {
  fixture f;
  make(&f, 1000, 1000);
  CHECK(budget_take_separate(&f.r) == 0);
  make(&f, 1000, 1100);
  CHECK(budget_take_separate(&f.r) == 0);
}

TEST(a_separate_candidate_seen_on_the_judges_views_is_not_taken) {
  fixture f;
  make(&f, 1000, 900);
  f.cand[1].statistic = 0.25;
  f.cand[1].pass = 0;
  CHECK(budget_take_separate(&f.r) == 0);
}

TEST(a_separate_candidate_seen_on_any_levels_held_out_views_is_not_taken) {
  for (int j = 0; j < 2; j++) {
    fixture f;
    make(&f, 1000, 900);
    f.separate_levels[j].pass = 0;
    f.separate_levels[j].statistic = 0.3;
    CHECK(budget_take_separate(&f.r) == 0);
  }
  fixture f;
  make(&f, 1000, 900);
  f.r.nseparate_levels = 0;   /* not verified */
  CHECK(budget_take_separate(&f.r) == 0);
}

TEST(a_dearer_separate_candidate_is_taken_where_the_joint_choice_is_seen) {
  fixture f;
  make(&f, 1000, 1100);
  f.r.passes = 0;
  f.chosen_levels[0].pass = 0;
  CHECK(budget_take_separate(&f.r) == 1);
  f.cand[1].pass = 0;   /* both seen: the joint choice stands (exit 1) */
  CHECK(budget_take_separate(&f.r) == 0);
}

TEST(budget_mode_and_a_choice_that_is_the_separate_one_take_nothing) {
  fixture f;
  make(&f, 1000, 900);
  f.r.mode = 1;
  CHECK(budget_take_separate(&f.r) == 0);
  make(&f, 1000, 900);
  f.r.chosen = 1;
  CHECK(budget_take_separate(&f.r) == 0);
}

RUN_TESTS(the_separate_candidate_is_taken_where_it_is_cheaper_and_unnoticed_over_the_margin,
          a_separate_candidate_that_costs_as_much_or_more_is_not_taken,
          a_separate_candidate_seen_on_the_judges_views_is_not_taken,
          a_separate_candidate_seen_on_any_levels_held_out_views_is_not_taken,
          a_dearer_separate_candidate_is_taken_where_the_joint_choice_is_seen,
          budget_mode_and_a_choice_that_is_the_separate_one_take_nothing)
