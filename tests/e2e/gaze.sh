#!/usr/bin/env bash
# jnd gaze: the table L(d, ecc) from a chain made on the fly and from a
# chain read back from `jnd lod`'s MSFT_lod model, its files (json, csv,
# png) agreeing, monotone, determinism across thread counts, and bad input
# (one line naming the flag or file, exit 2, nothing written).
set -uo pipefail
. "$(dirname "$0")/lib.bash"
need_renderer
SMALL=(--map-size 32 --orientations 2 --distances 20,40,80 --eccentricities 0,10,30 --min-px 48 --max-px 64 --quiet)

expect_exit 0 "builtin:sphere runs" "$JND" gaze builtin:sphere -o "$T/a" "${SMALL[@]}" --threads 1
check "gaze.json has the fields issue 13 names, monotone, agreeing with gaze.csv" python3 - "$T/a" <<'PY'
import csv, json, sys
d = sys.argv[1]
r = json.load(open(d + "/gaze.json"))
assert r["command"] == "gaze" and "jnd_version" in r and "inputs" in r and "parameters" in r
res = r["result"]
D, E, L = res["distances_m"], res["eccentricities_deg"], res["level"]
assert D == [20, 40, 80] and E == [0, 10, 30]
assert len(L) == 3 and all(len(row) == 3 for row in L)
n = len(res["triangles"])
assert n >= 2 and all(a > b for a, b in zip(res["triangles"], res["triangles"][1:]))
for i in range(3):
    for j in range(3):
        assert 0 <= L[i][j] < n
        if i + 1 < 3: assert L[i + 1][j] >= L[i][j]
        if j + 1 < 3: assert L[i][j + 1] >= L[i][j]
        k = res["level_raw"][i][j]
        assert L[i][j] <= k and res["p_spatial"][i][j][k] < 0.75 and res["p_switch"][i][j][k] < 0.75
        # 002's threshold 0.75 by default: the raw level is the coarsest below it
        for c in range(k + 1, n):
            assert res["p_spatial"][i][j][c] >= 0.75 or res["p_switch"][i][j][c] >= 0.75, (i, j, c, k)
assert r["parameters"]["threshold"] == 0.75, r["parameters"]
assert L[0][0] < L[-1][-1], L
rows = list(csv.DictReader(open(d + "/gaze.csv")))
assert len(rows) == 9
for row in rows:
    i, j = D.index(float(row["distance_m"])), E.index(float(row["eccentricity_deg"]))
    assert int(row["level"]) == L[i][j]
assert open(d + "/gaze.png", "rb").read(8) == b"\x89PNG\r\n\x1a\n"
# a near object (the window capped at --max-px 64) is judged on windows at the display's ppd
red, ppd, disp, win = res["reduced_ppd"], res["ppd"], res["display_ppd"], res["windowed"]
assert len(red) == 3 and len(win) == 3 and win[0] == 1, (win, ppd, disp)
for k in range(3):
    assert red[k] is False and abs(ppd[k] - disp) < 0.01 * disp, (k, red, ppd, disp)
    assert win[k] == 0 or res["side_px"][k] == 64
PY
expect_exit 0 "--whole-near judges near objects whole" "$JND" gaze builtin:sphere -o "$T/whole" "${SMALL[@]}" --whole-near
check "and flags them judged at reduced ppd" python3 - "$T/whole/gaze.json" <<'PY'
import json, sys
res = json.load(open(sys.argv[1]))["result"]
red, ppd, disp = res["reduced_ppd"], res["ppd"], res["display_ppd"]
assert red[0] is True and res["windowed"] == [0, 0, 0], (red, res["windowed"])
for k in range(3):
    assert red[k] == (ppd[k] < 0.99 * disp), (k, red, ppd, disp)
PY
expect_exit 0 "the same with 2 threads" "$JND" gaze builtin:sphere -o "$T/b" "${SMALL[@]}" --threads 2
check "same table whatever the thread count" cmp "$T/a/gaze.csv" "$T/b/gaze.csv"

# the chain gaze made is written beside the table, and it is the chain the table's levels index
check "the made chain is written: its levels' triangles are the table's" python3 - "$T/a" <<'PY'
import json, struct, sys
d = sys.argv[1]
r = json.load(open(d + "/gaze.json"))["result"]
assert r["chain_model"] == "model/builtin_sphere.glb", r["chain_model"]
b = open(d + "/" + r["chain_model"], "rb").read()
n, = struct.unpack_from("<I", b, 12)
g = json.loads(b[20:20 + n])
ids = g["nodes"][0]["extensions"]["MSFT_lod"]["ids"]
assert len(ids) + 1 == len(r["triangles"]), (ids, r["triangles"])
tris = []
for node in [0] + ids:
    m = g["meshes"][g["nodes"][node]["mesh"]]
    tris.append(sum(g["accessors"][p["indices"]]["count"] // 3 for p in m["primitives"]))
assert tris == r["triangles"], (tris, r["triangles"])
PY

# a chain from jnd lod, read back through MSFT_lod
expect_exit 0 "jnd lod writes a chain" "$JND" lod builtin:sphere -o "$T/lod" --errors 0.004,0.02,0.08 --chain-only \
  --map-size 32 --quiet
expect_exit 0 "gaze on jnd lod's model" "$JND" gaze "$T/lod/model/builtin_sphere.glb" -o "$T/c" "${SMALL[@]}"
check "its table has the chain's 4 levels" python3 -c "
import json; r = json.load(open('$T/c/gaze.json'))
assert len(r['result']['triangles']) == 4, r['result']['triangles']
assert r['inputs']['chain'].startswith('input') and r['result']['chain_model'].endswith('lod/model/builtin_sphere.glb')"

# bad input: one line naming the flag or file, exit 2, nothing written
for args in "--eccentricities 0,95" "--eccentricities 10,5" "--distances 0,20" "--distances 1" \
            "--threshold 0.3" "--orientations 0"; do
  # shellcheck disable=SC2086
  expect_exit 2 "refused: $args" "$JND" gaze builtin:sphere -o "$T/bad" --map-size 32 $args
  check "one line naming the flag ($args)" bash -c "one() { [ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -q '^jnd: ${args%% *}' '$T/err.txt'; }; one"
  check "nothing written ($args)" test ! -e "$T/bad"
done
printf 'solid x\nendsolid x\n' >"$T/empty.obj"
expect_exit 2 "a model with nothing in it" "$JND" gaze "$T/empty.obj" -o "$T/bad"
check "one line" one_line_error
check "nothing written" test ! -e "$T/bad"
expect_exit 2 "a missing model" "$JND" gaze "$T/missing.glb" -o "$T/bad"
check "one line naming the file" bash -c "grep -q '^jnd: .*missing.glb' '$T/err.txt' && [ \$(wc -l <'$T/err.txt') -eq 1 ]"
# jnd gaze fit: synthetic observers of the temporal model (w_t 0.6, gamma_t 2.5)
python3 - "$T/trials.csv" <<'PY'
import math, random, sys
random.seed(3)
with open(sys.argv[1], "w") as f:
    f.write("t_jnd,seen\n")
    for s in range(120):
        t = 0.1 * 40 ** random.random()
        p = 0.5 + 0.5 / (1 + (0.6 * t) ** -2.5)
        for _ in range(50):
            f.write("%.6f,%d\n" % (t, random.random() < p))
PY
expect_exit 0 "gaze fit runs" "$JND" gaze fit "$T/trials.csv" -o "$T/fit" --quiet
check "gaze_fit.json: the parameters near the truth, 4 folds of r and MAE" python3 - "$T/fit/gaze_fit.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
assert r["command"] == "gaze fit"
res = r["result"]
assert res["model"] == "temporal" and res["trials"] == 6000 and res["stimuli"] == 120
w = res["parameters"]["w_t"]
assert w["ci_lo"] <= 0.6 <= w["ci_hi"] and abs(w["value"] - 0.6) < 0.1, w
cv = res["cross_validation"]
assert len(cv["pearson_r"]) == 4 and len(cv["mae"]) == 4 and cv["pearson_r_mean"] > 0.8 and cv["mae_mean"] < 0.1
assert res["all_data"]["pearson_r"] > 0.8
PY
printf 'xor_deg,v_jnd,seen\n0.1,1,1\n' >"$T/nocol.csv"
expect_exit 2 "a trial file without eccentricity_deg" "$JND" gaze fit "$T/nocol.csv" -o "$T/badfit"
check "one line naming the file and the column" bash -c "grep -q '^jnd: .*nocol.csv: missing column .eccentricity_deg' '$T/err.txt' && [ \$(wc -l <'$T/err.txt') -eq 1 ]"
printf 't_jnd,seen\n0.1,1\n0.2,yes\n' >"$T/answer.csv"
expect_exit 2 "an answer that is not 0/1" "$JND" gaze fit "$T/answer.csv" -o "$T/badfit"
check "one line naming the row" bash -c "grep -q '^jnd: .*answer.csv: row 3: seen' '$T/err.txt' && [ \$(wc -l <'$T/err.txt') -eq 1 ]"
check "nothing written" test ! -e "$T/badfit"
finish
