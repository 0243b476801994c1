#!/usr/bin/env bash
# jnd gaze's default parameters are the fit scripts/fit-gaze-defaults.sh
# prints (committed as scripts/gaze-defaults.json): the table's report
# carries the defaults it used, and each must equal the committed fit.
# --params loads fitted parameters (a jnd gaze fit report, or that file);
# a bad one is one line and exit 2, nothing written.
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

ONE=(--map-size 32 --orientations 1 --distances 20 --eccentricities 10 --min-px 32 --max-px 32 --quiet)
# a spatial and a temporal fit report, as jnd gaze fit writes them, with values unlike the defaults
python3 - "$T" <<'PY'
import json, sys
t = sys.argv[1]
sp = {"jnd_version": "x", "command": "gaze fit", "inputs": {}, "parameters": {"b": 3.5},
      "result": {"model": "spatial", "parameters": {k: {"value": v, "ci_lo": None, "ci_hi": None} for k, v in
                 dict(alpha=4.5, beta=0.2, s_deg=12.5, w_vdp=0.7, k_s=1.5, gamma=3.25).items()}}}
tm = {"command": "gaze fit", "parameters": {}, "result": {"model": "temporal",
      "parameters": {"w_t": {"value": 2.5}, "gamma_t": {"value": 5.5}}}}
json.dump(sp, open(t + "/sp.json", "w"))
json.dump(tm, open(t + "/tm.json", "w"))
bad = dict(sp); bad["result"] = dict(sp["result"]); bad["result"]["parameters"] = dict(sp["result"]["parameters"])
del bad["result"]["parameters"]["gamma"]
json.dump(bad, open(t + "/missing.json", "w"))
bad["result"]["parameters"]["gamma"] = {"value": -1}
json.dump(bad, open(t + "/negative.json", "w"))
open(t + "/notjson.json", "w").write("{alpha: 2")
PY
expect_exit 0 "--params takes a spatial and a temporal fit" "$JND" gaze builtin:sphere -o "$T/p" "${ONE[@]}" \
  --params "$T/sp.json" --params "$T/tm.json"
check "the table used the fitted parameters" python3 - "$T/p/gaze.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))["parameters"]["model"]
want = dict(alpha=4.5, beta=0.2, s_deg=12.5, w_vdp=0.7, k_s=1.5, gamma=3.25, b=3.5, w_g=1, w_t=2.5, gamma_t=5.5)
assert all(abs(m[k] - v) < 1e-12 for k, v in want.items()), m
PY
expect_exit 0 "--params takes the committed defaults file" "$JND" gaze builtin:sphere -o "$T/q" "${ONE[@]}" \
  --params "$fit"
check "which gives the defaults" python3 -c "import json,sys; a,b=(json.load(open(f))['parameters']['model'] for f in sys.argv[1:]); assert a==b" "$T/a/gaze.json" "$T/q/gaze.json"
for f in missing negative notjson absent; do
  expect_exit 2 "--params $f is refused" "$JND" gaze builtin:sphere -o "$T/bad_$f" "${ONE[@]}" --params "$T/$f.json"
  check "--params $f: one line naming the file" bash -c "one_line_error() { [ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -q '^jnd: .*$f.json' '$T/err.txt'; }; one_line_error"
  check "--params $f: nothing written" test ! -e "$T/bad_$f"
done
finish
