#!/usr/bin/env bash
# Every task's report is produced by the library (issue 24): a program that
# links libjnd.so and calls jnd_<task>_run with no command line gets the
# same report, byte for byte, as the command with the same options, and the
# same files in its folder.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
need_renderer
: "${JND_TASK_RUNS:?JND_TASK_RUNS must point at the task_runs program}"

same_run() {   # NAME TASK INPUT -- COMMAND LINE AFTER THE TASK (with the input)
  # both into the same folder name (the report names it), one after the other
  local name=$1 task=$2 input=$3
  shift 4
  rm -rf "$T/out"
  expect_exit 0 "$name: the command runs" "$JND" "$task" "$@" -o "$T/out" --json "$T/$name.cli.json" --quiet
  mv "$T/out" "$T/$name.cli"
  # shellcheck disable=SC2086 # LIB_EXTRA: further arguments of the library call, words
  "$JND_TASK_RUNS" "$task" "$input" "$T/out" ${LIB_EXTRA:-} >"$T/$name.lib.json" 2>"$T/$name.lib.err"
  check "$name: the library call runs ($(head -c 200 "$T/$name.lib.err"))" [ $? -eq 0 ]
  mv "$T/out" "$T/$name.lib"
  check "$name: the returned report is the command's, byte for byte" cmp "$T/$name.cli.json" "$T/$name.lib.json"
  local file=$task.json   # the report in the folder: views.json for render
  [ "$task" = render ] && file=views.json
  check "$name: and the one in the folder" cmp "$T/$name.cli/$file" "$T/$name.lib/$file"
  check "$name: the same files in the folder" \
    diff <(cd "$T/$name.cli" && find . | sort) <(cd "$T/$name.lib" && find . | sort)
}

same_run texres_builtin texres builtin -- builtin --views 2 --size 96x96 --map-size 128 --samples 1 --confirm 0 --min-size 16
same_run lod_sphere lod builtin:sphere -- builtin:sphere --screens 320x240 --views 1 --map-size 64 --surface-samples 4096 \
  --judge-views 1 --max-px 96 --tolerance 0.5 --far-coverage 0.05
same_run render_sphere render builtin:sphere -- builtin:sphere --views 2 --size 64x48 --map-size 64 \
  --outputs color,depth,mask,motion,mip
same_run gaze_sphere gaze builtin:sphere -- builtin:sphere --map-size 32 --orientations 2 --distances 20,40,80 \
  --eccentricities 0,10,30 --min-px 48 --max-px 64
# gaze's other modes: synthetic observers, and a fit of their answers
expect_exit 0 "gaze observers: the command runs" "$JND" gaze observers builtin:sphere -o "$T/obs.cli" --map-size 32 \
  --sizes 3,8 --eccentricities 0,30 --orientations 1 --answers 5 --min-px 32 --max-px 64 --json "$T/obs.cli.json" --quiet
"$JND_TASK_RUNS" gaze-observers builtin:sphere "$T/obs.lib" >"$T/obs.lib.json" 2>"$T/obs.lib.err"
check "gaze observers: the library call runs ($(head -c 200 "$T/obs.lib.err"))" [ $? -eq 0 ]
check "gaze observers: the returned report is the command's, byte for byte" cmp "$T/obs.cli.json" "$T/obs.lib.json"
check "gaze observers: the same files" diff -r "$T/obs.cli" "$T/obs.lib"
expect_exit 0 "gaze fit: the command runs" "$JND" gaze fit "$T/obs.cli/temporal.csv" -o "$T/fit.cli" \
  --json "$T/fit.cli.json" --quiet
"$JND_TASK_RUNS" gaze-fit "$T/obs.cli/temporal.csv" "$T/fit.lib" >"$T/fit.lib.json" 2>"$T/fit.lib.err"
check "gaze fit: the library call runs ($(head -c 200 "$T/fit.lib.err"))" [ $? -eq 0 ]
check "gaze fit: the returned report is the command's, byte for byte" cmp "$T/fit.cli.json" "$T/fit.lib.json"
check "gaze fit: the same files" diff -r "$T/fit.cli" "$T/fit.lib"
# diff: two inputs and named files, no folder
"$JND" example -o "$T/ex" --size 160x120 >/dev/null 2>&1
expect_exit 1 "diff: the command runs (above --fail-above: exit 1)" "$JND" diff "$T/ex/reference.png" "$T/ex/test.png" \
  --display phone --fail-above 0.01 --map "$T/diff.cli.exr" --json "$T/diff.cli.json" --quiet
"$JND_TASK_RUNS" diff "$T/ex/reference.png" "$T/ex/test.png" "$T/diff.lib.exr" >"$T/diff.lib.json" 2>"$T/diff.lib.err"
rc=$?
check "diff: the library call runs, above the threshold (exit $rc, $(head -c 200 "$T/diff.lib.err"))" [ "$rc" -eq 1 ]
check "diff: the returned report is the command's, byte for byte" cmp "$T/diff.cli.json" "$T/diff.lib.json"
check "diff: the same map" cmp "$T/diff.cli.exr" "$T/diff.lib.exr"
# csf: a data file in, the rows with their predictions out (named, no folder)
csf=$JND_SHARED/data/csf/csf_train.csv
if [ -f "$csf" ]; then
  expect_exit 0 "csf: the command runs" "$JND" csf "$csf" --dataset colorfest --dataset hansen2009 --every 8 \
    --cross-validate --fit-only sensitivity --iterations 2 -o "$T/csf.cli.csv" --json "$T/csf.cli.json" --quiet
  "$JND_TASK_RUNS" csf "$csf" "$T/csf.lib.csv" >"$T/csf.lib.json" 2>"$T/csf.lib.err"
  check "csf: the library call runs ($(head -c 200 "$T/csf.lib.err"))" [ $? -eq 0 ]
  check "csf: the returned report is the command's, byte for byte" cmp "$T/csf.cli.json" "$T/csf.lib.json"
  check "csf: the same rows written" cmp "$T/csf.cli.csv" "$T/csf.lib.csv"
fi
# pop: the frame form (two frames in, a folder out) and the asset form (the switch rendered, the table decided)
PYTHONPATH="$(dirname "$0")" python3 -B - "$T" <<'PY'
import sys
from pngwrite import png
from popframes import background, patch
bg = background(160, 120)
png(sys.argv[1] + '/expected.png', 160, 120, 3, bg)
png(sys.argv[1] + '/new.png', 160, 120, 3, patch(bg, 0.25))  # a square of detail: regions to rate
PY
"$JND" pop "$T/new.png" "$T/expected.png" -o "$T/pop.cli" --maps --fail-above 0.5 --max-regions 3 \
  --json "$T/pop.cli.json" --quiet
rc_cli=$?
"$JND_TASK_RUNS" pop "$T/new.png" "$T/expected.png" "$T/pop.lib" >"$T/pop.lib.json" 2>"$T/pop.lib.err"
rc_lib=$?
check "pop frames: the library call exits as the command, above --fail-above: 1 ($rc_lib, $rc_cli: $(head -c 200 "$T/pop.lib.err"))" \
  [ "$rc_lib$rc_cli" = 11 ]
check "pop frames: the returned report is the command's, byte for byte" cmp "$T/pop.cli.json" "$T/pop.lib.json"
check "pop frames: the same files" diff -r "$T/pop.cli" "$T/pop.lib"
same_run pop_asset pop builtin -- builtin --size 64x64 --views 1 --map-size 64 --errors 0.1 --speeds 0,240 --tolerance 0.3
gltf=/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf
[ -f "$gltf" ] || skip "needs assimp's glTF2 sample models (assimp-testmodels)"
same_run texres_gltf texres "$gltf" -- "$gltf" --views 2 --size 96x96 --map-size 128 --samples 1 --confirm 0 --min-size 16
same_run pca_builtin pca builtin -- --model builtin --material builtin --map-size 128 --views 2 --size 96x96 \
  --anisotropy 1 --no-bc
maps=$(ls "$JND_SHARED"/data/texsets/*/*.jpg 2>/dev/null | head -3)
if [ -n "$maps" ]; then
  # shellcheck disable=SC2086
  LIB_EXTRA=$maps same_run pca_maps pca - -- $maps --psnr 40 --write-maps
fi

# calibrate writes one file, the calibration, which is its report
cat >"$T/rates.csv" <<'CSV'
scene,model,map,resolution,rate
albedo,builtin,builtin/baseColor,128,0.0
albedo,builtin,builtin/baseColor,64,0.5
albedo,builtin,builtin/baseColor,32,0.95
normal,builtin,builtin/normal,128,0.0
normal,builtin,builtin/normal,64,0.8
normal,builtin,builtin/normal,32,1.0
CSV
expect_exit 0 "calibrate: the command runs" "$JND" calibrate "$T/rates.csv" -o "$T/cal.json" --json "$T/cal.cli.json" \
  --folds 2 --map-size 128 --views 2 --size 96x96 --quiet
mv "$T/cal.json" "$T/cal.cli.file.json"
"$JND_TASK_RUNS" calibrate "$T/rates.csv" "$T/cal.json" >"$T/cal.lib.json" 2>"$T/cal.lib.err"
check "calibrate: the library call runs ($(head -c 200 "$T/cal.lib.err"))" [ $? -eq 0 ]
check "calibrate: the returned report is the command's, byte for byte" cmp "$T/cal.cli.json" "$T/cal.lib.json"
check "calibrate: and the file written" cmp "$T/cal.cli.file.json" "$T/cal.json"

# a refusal is the library's too: the folder that holds the model is not an
# output folder; one line naming both, exit 2, nothing written
mkdir -p "$T/box"
cp "$(dirname "$gltf")"/* "$T/box/"
before=$(cd "$T/box" && find . -printf '%p %s %T@\n' | sort)
"$JND_TASK_RUNS" texres "$T/box/BoxTextured.gltf" "$T/box" >/dev/null 2>"$T/refused.err"
rc=$?
check "a folder holding the input is refused: exit 2 (got $rc)" [ "$rc" -eq 2 ]
check "one line naming the folder ($(head -c 200 "$T/refused.err"))" \
  bash -c "[ \$(wc -l <'$T/refused.err') -eq 1 ] && grep -q '$T/box' '$T/refused.err'"
check "nothing written" [ "$before" = "$(cd "$T/box" && find . -printf '%p %s %T@\n' | sort)" ]
finish
