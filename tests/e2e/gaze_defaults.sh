#!/usr/bin/env bash
# jnd gaze's default parameters are the fit scripts/fit-gaze-defaults.sh
# prints (committed as scripts/gaze-defaults.json): the table's report
# carries the defaults it used, and each must equal the committed fit.
# --params loads fitted parameters (a jnd gaze fit report, or that file);
# a bad one is one line and exit 2, nothing written. jnd gaze observers
# (what the script fits the defaults to) writes trials jnd gaze fit reads,
# the same for any thread count, and refuses bad input.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
need_renderer
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

OBS=(--map-size 32 --sizes 3,8 --eccentricities 0,30 --orientations 1 --answers 5 --min-px 32 --max-px 64 --quiet)
expect_exit 0 "observers run" "$JND" gaze observers builtin:sphere -o "$T/obs1" "${OBS[@]}" --threads 1
expect_exit 0 "observers run on 2 threads" "$JND" gaze observers builtin:sphere -o "$T/obs2" "${OBS[@]}" --threads 2
check "the same trials whatever the thread count" cmp "$T/obs1/spatial.csv" "$T/obs2/spatial.csv"
check "the trials: one row per answer, probabilities from the vision model falling with eccentricity" \
  python3 - "$T/obs1" <<'PY'
import csv, json, sys
d = sys.argv[1]
sp, tm = list(csv.DictReader(open(d + "/spatial.csv"))), list(csv.DictReader(open(d + "/temporal.csv")))
r = json.load(open(d + "/observers.json"))
n = r["result"]["stimuli"]
assert n == 2 * 2 * 3 and len(sp) == 5 * n and len(tm) == 5 * n, (n, len(sp), len(tm))
assert "eccentricity_deg" not in tm[0] and "t_jnd" in tm[0]
for row in sp:
    assert row["seen"] in ("0", "1") and 0.5 <= float(row["p_true"]) <= 1
# an observer's chance of a correct answer is 2AFC's: 0.5 + 0.5·P(JND) with 000 eq. 4's
# P = 1 − 2^(−JND^β), β 3.5, from the stimulus's own JND (whole change; the switch for temporal)
beta = r["parameters"]["model"]["beta"] if "beta" in r["parameters"].get("model", {}) else 3.5
for rows, col in ((sp, "jnd_whole"), (tm, "t_jnd")):
    for row in rows:
        j = float(row[col])
        want = 0.5 + 0.5 * (1 - 2 ** (-(j ** beta))) if j > 0 else 0.5
        assert abs(float(row["p_true"]) - want) < 2e-4, (col, j, row["p_true"], want)
assert len({row["p_true"] for row in sp}) > 2 and {row["p_true"] for row in sp} != {row["p_true"] for row in tm}
# per size and level, the whole change is seen less at 30 degrees than looked at
key = lambda row: (row["size_deg"], row["level"])
at = {}
for row in sp: at[(key(row), row["eccentricity_deg"])] = float(row["jnd_whole"])
for (k, e), j in at.items():
    if e == "0": assert at[(k, "30")] < j, (k, j, at[(k, "30")])
PY
expect_exit 0 "jnd gaze fit reads them" "$JND" gaze fit "$T/obs1/temporal.csv" --quiet
expect_exit 2 "observers: sizes that do not ascend" "$JND" gaze observers builtin:sphere -o "$T/obs_bad" --sizes 8,3 --quiet
check "one line naming the flag" bash -c "[ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -q '^jnd: --sizes' '$T/err.txt'"
check "nothing written" test ! -e "$T/obs_bad"
expect_exit 2 "observers: a model that does not exist" "$JND" gaze observers "$T/none.obj" -o "$T/obs_bad" --quiet
check "one line naming the file" bash -c "[ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -q '^jnd: .*none.obj' '$T/err.txt'"
check "nothing written" test ! -e "$T/obs_bad"
finish
