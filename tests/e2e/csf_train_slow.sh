#!/usr/bin/env bash
# The model against the 785 human thresholds of csf_train's nine data sets
# (issue 10). The headline is leave-one-data-set-out cross-validation: each
# data set predicted by the constants refitted on the other eight, searching
# the same rows (every second of each set) as the fit of the defaults
# (scripts/fit-model.sh). The issue's targets are <= 5 dB over static rows
# (the model gives 4.89, docs/model.md) and <= 7 dB over all rows (5.45; the
# bound is what the model achieves, a little above). Training: 4.25 static,
# 3.84 all rows.
. "$(dirname "$0")/lib.bash"
shared_data || skip "no shared data"
D="$JND_SHARED/data/csf/csf_train.csv"
expect_exit 0 cross_validation_runs "$JND" csf "$D" --cross-validate --search-every 2 -o "$T/pred.csv" --json "$T/r.json" --quiet
jq -c '.result | del(.derived_directions)' "$T/r.json"
check every_row_is_predicted jq -e '.result.rows == 785 and .result.skipped == 0' "$T/r.json"
check nine_data_sets_each_cross_validated \
  jq -e '(.result.datasets | length) == 9 and ([.result.datasets[] | select(.cv_rmse_db > 0)] | length) == 9' "$T/r.json"
check kong2018_and_hansen2009_directions_are_derived \
  jq -e '.result.derived_direction_rows == 267 and ([.result.derived_directions[].dataset] | unique) == ["hansen2009", "kong2018"]' "$T/r.json"
check every_row_has_a_cross_validated_prediction bash -c "! awk -F, 'NR > 1 && \$(NF-2) == \"NaN\"' '$T/pred.csv' | grep -q ."
check the_constants_of_each_fold_are_reported \
  jq -e '(.parameters.constants | length) as $n | $n > 10 and ([.parameters.constants[] | select(.without | length == 9)] | length) == $n' "$T/r.json"
# each fold moves away from the all-data fit it starts from (a fold that
# kept it would predict its left-out set with constants fitted on that set)
check every_fold_moves_from_the_all_data_fit \
  jq -e '.parameters.constants as $c | ($c.sensitivity.without | keys) | all(. as $ds | [$c[] | select(((.without[$ds] / .value) - 1 | fabs) > 1e-6)] | length > 0)' "$T/r.json"
# the chromatic centre falls slower than Kelly's exponential (q = 1) by
# every fold's data, colorfest's (the only chromatic set above 8 cpd) left out too
check chroma_tail_below_0_8_in_every_fold jq -e '[.parameters.constants.chroma_tail.without[]] | length == 9 and max < 0.8' "$T/r.json"
check training_rmse_static_at_most_4_35_db jq -e '.result.rmse_db_static <= 4.35' "$T/r.json"
check training_rmse_all_rows_at_most_3_95_db jq -e '.result.rmse_db <= 3.95' "$T/r.json"
check loso_rmse_static_at_most_5_db jq -e '.result.cv_rmse_db_static <= 5.0' "$T/r.json"
check loso_rmse_all_rows_at_most_5_6_db jq -e '.result.cv_rmse_db <= 5.6' "$T/r.json"
finish
