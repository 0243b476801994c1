#!/usr/bin/env bash
# The model against the 785 human thresholds of csf_train's nine data sets
# (issues 10 and 26). The headline is honest leave-one-data-set-out
# cross-validation: each data set predicted by every constant refitted on
# the other eight alone, each fold starting from the literature's priors
# (not from the defaults, which were fitted on all nine), its rows never
# searched. Folds search every 8th row of each set, each search row weighed
# as the 8 it stands for (a fold costs about 100 passes over its rows;
# docs/model.md gives the cost and the figures: 5.36 static, 5.85 all rows,
# about 1 120 CPU-s, some 9-10 min on two idle cores). The
# issue's targets: <= 5.5 dB over static rows and <= 6.5 dB over all rows.
# Training (the defaults on every row): 4.25 static, 3.84 all rows.
. "$(dirname "$0")/lib.bash"
shared_data || skip "no shared data"
D="$JND_SHARED/data/csf/csf_train.csv"
expect_exit 0 cross_validation_runs "$JND" csf "$D" --cross-validate --search-every 8 -o "$T/pred.csv" --json "$T/r.json" --quiet
jq -c '.result | del(.derived_directions)' "$T/r.json"
jq -c '.parameters.constants | map_values(.without)' "$T/r.json"
check every_row_is_predicted jq -e '.result.rows == 785 and .result.skipped == 0' "$T/r.json"
check nine_data_sets_each_cross_validated \
  jq -e '(.result.datasets | length) == 9 and ([.result.datasets[] | select(.cv_rmse_db > 0 and (.cv_bias_db | type) == "number")] | length) == 9' "$T/r.json"
check kong2018_and_hansen2009_directions_are_derived \
  jq -e '.result.derived_direction_rows == 267 and ([.result.derived_directions[].dataset] | unique) == ["hansen2009", "kong2018"]' "$T/r.json"
check every_row_has_a_cross_validated_prediction bash -c "! awk -F, 'NR > 1 && \$(NF-2) == \"NaN\"' '$T/pred.csv' | grep -q ."
check the_constants_of_each_fold_are_reported \
  jq -e '(.parameters.constants | length) as $n | $n > 10 and ([.parameters.constants[] | select(.without | length == 9)] | length) == $n' "$T/r.json"
# every fold fits: it leaves the priors it starts from (a fold that stayed
# there would predict with the literature's constants, not a fit)
check every_fold_moves_from_the_priors \
  jq -e '.parameters.constants as $c | ($c.sensitivity.without | keys) | all(. as $ds | [$c[] | select(((.without[$ds] / .prior) - 1 | fabs) > 0.05)] | length >= 5)' "$T/r.json"
check training_rmse_static_at_most_4_35_db jq -e '.result.rmse_db_static <= 4.35' "$T/r.json"
check training_rmse_all_rows_at_most_3_95_db jq -e '.result.rmse_db <= 3.95' "$T/r.json"
check loso_rmse_static_at_most_5_5_db jq -e '.result.cv_rmse_db_static <= 5.5' "$T/r.json"
check loso_rmse_all_rows_at_most_6_5_db jq -e '.result.cv_rmse_db <= 6.5' "$T/r.json"
finish
