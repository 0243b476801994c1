#!/usr/bin/env bash
# Fits the vision model's constants to ../shared/data/csf/csf_train.csv (the
# only data they may be fitted on) and measures the fit the honest way:
# leave-one-data-set-out cross-validation. docs/model.md records the result.
#
# Step 1 is `jnd csf --fit`: maximum a posteriori over every constant of
# `jnd csf --list-constants` (Levenberg-Marquardt on the model itself, each
# constant with a prior from the literature). It prints the constants for
# jnd_model_defaults() (src/vision/model.c) with their uncertainty.
# Step 2 is `jnd csf --cross-validate` with those constants: each data set is
# predicted by every constant refitted without it, from the priors (the
# fitted defaults reach no fold; they give the training figure), searching
# every 8th row as e2e.csf_train_slow does.
#
# usage: scripts/fit-model.sh JND [DATA.csv] [SEARCH_EVERY]
#   SEARCH_EVERY: fits search on every N-th row of each data set (default 2);
#   every reported error uses all rows.
set -euo pipefail
JND=${1:?usage: fit-model.sh JND [DATA.csv] [SEARCH_EVERY]}
DATA=${2:-$(dirname "$0")/../../shared/data/csf/csf_train.csv}
EVERY=${3:-2}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

echo "== fit on all rows (search on every $EVERY-th row)" >&2
"$JND" csf "$DATA" --fit --search-every "$EVERY" --json "$work/fit.json"
sets=()
while IFS= read -r line; do sets+=(--set "$line"); done < <(jq -r '.parameters.constants | to_entries[] | "\(.key)=\(.value.value)"' "$work/fit.json")

echo "== leave-one-data-set-out with the fitted constants" >&2
"$JND" csf "$DATA" "${sets[@]}" --cross-validate --search-every 8 --json "$work/cv.json"

echo "== for jnd_model_defaults():"
jq -r '.parameters.constants | to_entries[] | "  p->\(.key) = \(.value.value);  /* ±\(((.value.sd_ln // 0) * 100 | round))% */"' "$work/fit.json"
echo "== leave-one-data-set-out RMSE: static $(jq .result.cv_rmse_db_static "$work/cv.json") dB, all $(jq .result.cv_rmse_db "$work/cv.json") dB"
