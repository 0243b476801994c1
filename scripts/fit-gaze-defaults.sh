#!/usr/bin/env bash
# Fits the default parameters of `jnd gaze` (jnd_gaze_model_defaults,
# src/tasks/gaze.c) to synthetic observers whose answers come from jnd's own
# vision model: jnd ships no study (docs/gaze.md "Defaults").
#
# Step 1 is `jnd gaze observers`: the shared meshes' chains rendered at 3
# sizes x 2 orientations x 7 eccentricities x 3 levels; for each stimulus the
# spatial model's terms and the switch's, and 40 seeded Bernoulli answers
# from the probability the vision model gives to the whole change (the
# silhouette and the shading as it sees them) and to the switch.
# Step 2 is `jnd gaze fit` on each file: maximum likelihood, intervals and
# 4-fold cross-validation. The result, in the form of
# scripts/gaze-defaults.json (committed; tests/e2e/gaze_defaults.sh checks the
# shipped defaults against it), goes to OUTDIR/gaze-defaults.json and the
# lines for jnd_gaze_model_defaults() to stdout.
#
# usage: scripts/fit-gaze-defaults.sh JND [OUTDIR]
#   JND_SHARED: the shared data folder (default ../shared from the repository)
set -euo pipefail
JND=${1:?usage: fit-gaze-defaults.sh JND [OUTDIR]}
here=$(cd "$(dirname "$0")" && pwd)
meshes=${JND_SHARED:-$here/../../shared}/data/meshes
out=${2:-$(mktemp -d)}
mkdir -p "$out"
for m in teapot spot stanford-bunny; do
  [ -f "$meshes/$m.obj" ] || { echo "fit-gaze-defaults: $meshes/$m.obj is missing" >&2; exit 2; }
done

echo "== synthetic observers from jnd's vision model" >&2
"$JND" gaze observers "$meshes/teapot.obj" "$meshes/spot.obj" "$meshes/stanford-bunny.obj" -o "$out/observers" \
  --sizes 1.5,4,12 --eccentricities 0,5,10,20,30,45,60 --orientations 2 --answers 40 --seed 1 --max-px 576 --quiet
echo "== fit: spatial model" >&2
"$JND" gaze fit "$out/observers/spatial.csv" -o "$out/spatial" --folds 4 --seed 1 --quiet
echo "== fit: temporal model" >&2
"$JND" gaze fit "$out/observers/temporal.csv" -o "$out/temporal" --folds 4 --seed 1 --quiet

# the committed form: each parameter rounded to 4 significant digits (what
# the defaults carry; the knee s_deg, in degrees, to 0.01: the fit may put it
# on its bound 0, which the logit only approaches), its interval, and the
# fits' figures
jq -n --slurpfile s "$out/spatial/gaze_fit.json" --slurpfile t "$out/temporal/gaze_fit.json" '
  def r4: if . == null then null else (. | tostring | tonumber) as $x
    | if $x == 0 then 0 else ($x | fabs | log10 | floor) as $e | (pow(10; 3 - $e)) as $k
      | ($x * $k | round) / $k end end;
  def r2: if . == null then null else (. * 100 | round) / 100 end;
  def fit($f): {parameters: ($f.result.parameters | with_entries(if .key == "s_deg"
                  then .value |= {value: (.value | r2), ci_lo: (.ci_lo | r2), ci_hi: (.ci_hi | r2)}
                  else .value |= {value: (.value | r4), ci_lo: (.ci_lo | r4), ci_hi: (.ci_hi | r4)} end)),
                trials: $f.result.trials, stimuli: $f.result.stimuli,
                all_data: ($f.result.all_data | map_values(r4)),
                cross_validation: ($f.result.cross_validation | {pearson_r_mean, pearson_r_sd, mae_mean, mae_sd} | map_values(r4))};
  {fixed: {w_g: 1, b: $s[0].parameters.b}, spatial: fit($s[0]), temporal: fit($t[0])}' > "$out/gaze-defaults.json"

echo "== for jnd_gaze_model_defaults() (wrote $out/gaze-defaults.json):"
jq -r '(.fixed | to_entries[]), (.spatial.parameters | to_entries[]), (.temporal.parameters | to_entries[])
       | "  m->\(.key) = \(if (.value | type) == "object" then .value.value else .value end);"' "$out/gaze-defaults.json"
jq -r '"== 4-fold cross-validation: spatial r = \(.spatial.cross_validation.pearson_r_mean) ± \(.spatial.cross_validation.pearson_r_sd), MAE \(.spatial.cross_validation.mae_mean) ± \(.spatial.cross_validation.mae_sd); temporal r = \(.temporal.cross_validation.pearson_r_mean) ± \(.temporal.cross_validation.pearson_r_sd), MAE \(.temporal.cross_validation.mae_mean) ± \(.temporal.cross_validation.mae_sd)"' "$out/gaze-defaults.json"
