#!/usr/bin/env bash
# Every command that renders (render, texres, calibrate, pca, lod, pop, gaze,
# gaze observers) reads the view options through one parser: the same
# out-of-range value gets the same refusal from each (exit 2, one identical
# line), before anything is loaded or written; a command that has no use for
# an option says so in one line; and a size is described as WxH.
. "$(dirname "$0")/lib.bash"
echo "scene,mu,sigma,model,map" >"$T/t.csv"
echo "a,100,20,builtin,builtin/baseColor" >>"$T/t.csv"
cmds=("render builtin -o $T/x" "texres builtin -o $T/x" "calibrate $T/t.csv -o $T/x.json" "pca --model builtin --material builtin -o $T/x"
      "lod builtin -o $T/x" "pop builtin -o $T/x" "gaze builtin -o $T/x" "gaze observers builtin -o $T/x")
bad=("--views 0" "--views 5000" "--size 0x0" "--size 8x8" "--size 20,20" "--coverage 0" "--distance 0" "--fov 180"
     "--elevation 10,-10" "--lights 9" "--light-intensity -1" "--seed -1" "--samples 0" "--anisotropy 17"
     "--map-size 4" "--platform x" "--views")
for b in "${bad[@]}"; do
  ref=""
  for c in "${cmds[@]}"; do
    name="${c%% *} $b"
    expect_exit 2 "$name: exit 2" "$JND" $c $b
    check "$name: one line" one_line_error
    if [ -z "$ref" ]; then ref=$(cat "$T/err.txt"); else
      check "$name: the same refusal as ${cmds[0]%% *}" [ "$(cat "$T/err.txt")" = "$ref" ]; fi
  done
  check "no output written for $b" [ ! -e "$T/x" -a ! -e "$T/x.json" ]
done
# valid values of options a command renders without: refused, not ignored
for c in "lod builtin -o $T/x --size 64x64" "lod builtin -o $T/x --cameras c.json" "gaze builtin -o $T/x --views 4" \
         "gaze builtin -o $T/x --coverage 0.5" "gaze builtin -o $T/x --fov 30"; do
  expect_exit 2 "$c: exit 2" "$JND" $c
  check "$c: one line" one_line_error
  check "$c: says the option does not apply" grep -q "does not apply" "$T/err.txt"
  check "$c: nothing written" [ ! -e "$T/x" ]
done
expect_exit 2 "lod --coverage 2: exit 2" "$JND" lod builtin -o "$T/x" --coverage 2
check "lod --coverage 2: one line" one_line_error
check "lod --coverage 2: says the object must fit" grep -q "must fit on the screen" "$T/err.txt"
check "lod --coverage 2: nothing written" [ ! -e "$T/x" ]
"$JND" render builtin -o "$T/x" --size 0x0 2>"$T/err.txt"
check "a bad size names its format WxH" grep -q "is not WxH" "$T/err.txt"
finish
