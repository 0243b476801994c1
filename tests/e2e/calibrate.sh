#!/usr/bin/env bash
# jnd calibrate: thresholds CSV (mu/sigma or per-resolution rates), image series
# rendered from an asset or given as prepared pairs, the calibration file that
# jnd diff and jnd texres accept, and bad input.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
need_renderer
SMALL=(--map-size 128 --views 2 --size 96x96 --quiet)
command -v python3 >/dev/null || skip "needs python3"

# scenes from the builtin asset's maps, thresholds as per-resolution rates
cat >"$T/rates.csv" <<'CSV'
scene,model,map,resolution,rate
albedo,builtin,builtin/baseColor,128,0.0
albedo,builtin,builtin/baseColor,96,0.1
albedo,builtin,builtin/baseColor,64,0.5
albedo,builtin,builtin/baseColor,32,0.95
normal,builtin,builtin/normal,128,0.0
normal,builtin,builtin/normal,96,0.3
normal,builtin,builtin/normal,64,0.8
normal,builtin,builtin/normal,32,1.0
rough,builtin,builtin/metallicRoughness,128,0.0
rough,builtin,builtin/metallicRoughness,96,0.0
rough,builtin,builtin/metallicRoughness,64,0.2
rough,builtin,builtin/metallicRoughness,32,0.7
CSV
expect_exit 0 "calibrate from rendered series" "$JND" calibrate "$T/rates.csv" -o "$T/cal.json" --folds 2 --histogram "$T/hist.png" "${SMALL[@]}"
check "the report holds a calibration and the per-fold errors" python3 - "$T/cal.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
assert r["command"] == "calibrate"
c = r["result"]["calibration"]
assert 90 <= c["percentile"] <= 99 and c["scale"] > 0 and "bias" in c and c["beta"] > 0
assert len(r["result"]["fold_mae_px"]) == 2 and len(r["result"]["scenes"]) == 3
for s in r["result"]["scenes"]:
    assert s["mu"] > 0 and "predicted_px" in s and "heldout_error_px" in s
PY
check "an error histogram is written" test -s "$T/hist.png"

# the calibration is accepted by jnd diff and jnd texres
"$JND" example -o "$T/ex" --quiet 2>/dev/null || "$JND" example -o "$T/ex" >/dev/null 2>&1
expect_exit 0 "jnd diff --calibration" "$JND" diff "$T/ex/reference.png" "$T/ex/test.png" --calibration "$T/cal.json" --json "$T/diff.json" --quiet
check "diff pools with the calibration's percentile" python3 - "$T/diff.json" "$T/cal.json" <<'PY'
import json, sys
d, c = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))["result"]["calibration"]
assert d["result"]["pooling"] == "p%g" % c["percentile"], (d["result"]["pooling"], c)
PY
"$JND" texres builtin -o "$T/t" --calibration "$T/cal.json" --no-matrix --samples 1 "${SMALL[@]}"
check "jnd texres --calibration runs (exit 0 or 1)" [ $? -le 1 ]

# prepared image pairs: renderings of the builtin asset with a shrunk albedo
for s in 128 64 32; do
  "$JND" render builtin --map-size 128 --views 1 --size 64x64 --quiet -o "$T/p$s" --scale "builtin/baseColor=${s}x${s}"
done
"$JND" render builtin --map-size 128 --views 1 --size 64x64 --quiet -o "$T/pref"
{
  echo "scene,resolution,reference,test"
  for sc in one two; do for s in 128 64 32; do echo "$sc,$s,pref/view_000.png,p$s/view_000.png"; done; done
} >"$T/pairs.csv"
printf 'scene,mu,sigma\none,60,15\ntwo,80,20\n' >"$T/mu.csv"
expect_exit 0 "calibrate from image pairs" "$JND" calibrate "$T/mu.csv" --pairs "$T/pairs.csv" -o "$T/cal2.json" --folds 2 --quiet
check "its calibration loads in diff" "$JND" diff "$T/ex/reference.png" "$T/ex/test.png" --calibration "$T/cal2.json" --quiet

# bad input: one line, exit 2
printf 'scene,resolution\na,128\n' >"$T/nocols.csv"
expect_exit 2 "a CSV with missing columns: exit 2" "$JND" calibrate "$T/nocols.csv" -o "$T/x.json"
check "one line naming the file" bash -c "[ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -q 'nocols.csv: missing column' '$T/err.txt'"
printf 'scene,mu,sigma\na,100,10\n' >"$T/noseries.csv"
expect_exit 2 "no image series: exit 2" "$JND" calibrate "$T/noseries.csv" -o "$T/x.json"
check "one line" one_line_error
printf 'scene,model,map,mu,sigma\na,builtin,builtin/albedo,100,10\n' >"$T/badmap.csv"
expect_exit 2 "an unknown map: exit 2" "$JND" calibrate "$T/badmap.csv" -o "$T/x.json" "${SMALL[@]}"
check "one line" one_line_error
printf 'scene,mu,sigma\na,abc,10\n' >"$T/nan.csv"
expect_exit 2 "a non-number: exit 2" "$JND" calibrate "$T/nan.csv" --pairs "$T/pairs.csv" -o "$T/x.json"
check "one line" one_line_error
echo '{"calibration": {"percentile": 95}}' >"$T/badcal.json"
expect_exit 2 "diff with an incomplete calibration: exit 2" "$JND" diff "$T/ex/reference.png" "$T/ex/test.png" --calibration "$T/badcal.json"
check "one line" one_line_error
check "nothing written for bad input" [ ! -e "$T/x.json" ]
check "--help prints the usage" bash -c "'$JND' calibrate --help | grep -q -- --pairs"
finish
