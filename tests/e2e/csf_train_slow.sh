#!/usr/bin/env bash
# The model against the 349 static human thresholds of csf_train (issue: pooled RMSE <= 5 dB).
. "$(dirname "$0")/lib.bash"
shared_data || skip "no shared data"
D="$JND_SHARED/data/csf/csf_train.csv"
expect_exit 0 csf_train_runs "$JND" csf "$D" --static-only -o "$T/pred.csv" --json "$T/r.json" --quiet
jq '.result' "$T/r.json"
check pooled_static_rmse_is_at_most_5_db jq -e '.result.rmse_db_static <= 5.0' "$T/r.json"
check every_static_row_is_predicted jq -e '.result.rows == 349' "$T/r.json"
finish
