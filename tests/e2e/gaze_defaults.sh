#!/usr/bin/env bash
# jnd gaze's default parameters are the fit scripts/fit-gaze-defaults.sh
# prints (committed as scripts/gaze-defaults.json): the table's report
# carries the defaults it used, and each must equal the committed fit.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
fit="$(dirname "$0")/../../scripts/gaze-defaults.json"

expect_exit 0 "a one-cell table runs with the defaults" "$JND" gaze builtin:sphere -o "$T/a" --map-size 32 \
  --orientations 1 --distances 20 --eccentricities 10 --min-px 32 --max-px 32 --quiet
check "the defaults equal the committed fit" python3 - "$T/a/gaze.json" "$fit" <<'PY'
import json, sys
used = json.load(open(sys.argv[1]))["parameters"]["model"]
fit = json.load(open(sys.argv[2]))
want = dict(fit["fixed"])
for part in ("spatial", "temporal"):
    for k, v in fit[part]["parameters"].items():
        want[k] = v["value"]
assert set(want) == set(used), (sorted(want), sorted(used))
for k, v in want.items():
    assert abs(used[k] - v) <= 1e-9 * max(1, abs(v)), (k, used[k], v)
# the fit's figures are there for docs/gaze.md
for part in ("spatial", "temporal"):
    cv = fit[part]["cross_validation"]
    assert 0 < cv["pearson_r_mean"] <= 1 and 0 <= cv["mae_mean"] < 0.5, cv
PY
finish
