#!/usr/bin/env bash
# jnd pop end to end: user frames (PNG) with displacement, depth and weight
# maps (OpenEXR), the report's fields, motion, disocclusion, determinism
# across thread counts, and bad input (exit 2, one line, nothing written).
. "$(dirname "$0")/lib.bash"
command -v python3 >/dev/null || skip "needs python3"

# frames as PNG and maps as uncompressed float OpenEXR (pngwrite.py, exrwrite.py)
PYTHONPATH="$(dirname "$0")" python3 -B - "$T" <<'PY'
import sys
from pngwrite import png
from exrwrite import exr
from popframes import background, patch
d = sys.argv[1]
W, H = 160, 120
bg = background(W, H)
blob = patch(bg, 0.25)  # a square of detail, a grating of 16-pixel period
png(f'{d}/expected.png', W, H, 3, bg)
png(f'{d}/new.png', W, H, 3, blob)
png(f'{d}/small.png', W - 10, H, 3, bg)
exr(f'{d}/fast.exr', W, H, {'X': lambda x, y: 32.0, 'Y': lambda x, y: 0.0})
exr(f'{d}/small_disp.exr', W, H - 2, {'X': lambda x, y: 1.0, 'Y': lambda x, y: 0.0})
exr(f'{d}/nan_disp.exr', W, H, {'X': lambda x, y: float('nan') if (x, y) == (5, 7) else 1.0, 'Y': lambda x, y: 0.0})
exr(f'{d}/bad_weights.exr', W, H, {'Y': lambda x, y: 1.5 if (x, y) == (3, 2) else 1.0})
exr(f'{d}/depth.exr', W, H, {'Z': lambda x, y: 5.0})
exr(f'{d}/prev_depth.exr', W, H, {'Z': lambda x, y: 1.0 if 50 <= x < 94 and 30 <= y < 74 else 5.0})
png(f'{d}/depth.png', W, H, 3, lambda x, y: (0.5, 0.5, 0.5))
PY

expect_exit 0 help_exits_zero "$JND" pop --help
expect_exit 0 identical_frames_run "$JND" pop "$T/expected.png" "$T/expected.png" -o "$T/same" --quiet
check report_has_the_envelope jq -e '.jnd_version and .command == "pop" and .inputs.new and .inputs.expected and .parameters.display and .result' "$T/same/pop.json"
check identical_frames_have_no_region jq -e '.result.region_count == 0 and .result.regions == [] and .result.max_rating == null and .result.detection_score == 1 and .result.coverage_score == "tiny" and .result.rating_score == "very low" and .result.max_delta_e94 == 0' "$T/same/pop.json"
check regions_png_is_written bash -c "head -c 8 '$T/same/regions.png' | od -An -c | grep -q 'P   N   G'"

expect_exit 0 a_pair_with_a_change_runs "$JND" pop "$T/new.png" "$T/expected.png" -o "$T/still" --quiet
check the_change_is_a_rated_region jq -e '.result.region_count >= 1 and (.result.regions[0] | (.pixels > 0) and (.sigma > 0) and (.rating | type == "number") and (.bbox | length == 4)) and .result.max_rating == .result.regions[0].rating and .result.max_delta_e94 > 0' "$T/still/pop.json"
check the_region_covers_the_change jq -e '.result.regions[0].bbox as $b | $b[0] <= 60 and $b[1] <= 40 and $b[2] >= 83 and $b[3] >= 63' "$T/still/pop.json"
check scores_are_named_levels jq -e '(.result.coverage_score | IN("tiny", "small", "large", "huge")) and (.result.rating_score | IN("very low", "low", "high", "very high")) and (.result.detection_score | IN(1, 2, 3, 4, 5))' "$T/still/pop.json"
check regions_png_has_a_legend_column python3 -c "
import struct, sys; b = open('$T/still/regions.png', 'rb').read(); w, h = struct.unpack('>II', b[16:24]); sys.exit(0 if w > 160 and h >= 120 else 1)"

expect_exit 0 moving_pair_runs "$JND" pop "$T/new.png" "$T/expected.png" -o "$T/fast" --displacement "$T/fast.exr" --fps 60 --quiet
check faster_motion_lowers_the_rating jq -e --slurpfile s "$T/still/pop.json" '.result.max_rating == null or .result.max_rating < $s[0].result.max_rating' "$T/fast/pop.json"
check the_displacement_is_reported jq -e '.inputs.displacement and .parameters.fps == 60' "$T/fast/pop.json"

expect_exit 0 depths_run "$JND" pop "$T/new.png" "$T/expected.png" -o "$T/occ" --depth "$T/depth.exr" --prev-depth "$T/prev_depth.exr" --depth-expected "$T/depth.exr" --prev-depth-expected "$T/prev_depth.exr" --quiet
check disoccluded_change_is_down_weighted jq -e --slurpfile s "$T/still/pop.json" '.result.weights.disocclusion.present and .result.weights.disocclusion.pixels_below_half > 0 and (.result.max_rating == null or .result.max_rating < $s[0].result.max_rating)' "$T/occ/pop.json"
expect_exit 0 flicker_inputs_run "$JND" pop "$T/new.png" "$T/expected.png" -o "$T/flick" --prev-frame "$T/expected.png" --prev-shading "$T/expected.png" --quiet
expect_exit 0 a_frame_file_may_also_be_the_weights "$JND" pop "$T/new.png" "$T/expected.png" -o "$T/fw" --weights "$T/new.png" --quiet
check flicker_weight_is_reported jq -e '.result.weights.flicker.present and .result.weights.flicker.min == 1' "$T/flick/pop.json"

"$JND" pop "$T/new.png" "$T/expected.png" -o "$T/t1" --displacement "$T/fast.exr" --threads 1 --quiet
"$JND" pop "$T/new.png" "$T/expected.png" -o "$T/t2" --displacement "$T/fast.exr" --threads 2 --quiet
check report_is_byte_identical_across_thread_counts cmp -s "$T/t1/pop.json" "$T/t2/pop.json"
check picture_is_byte_identical_across_thread_counts cmp -s "$T/t1/regions.png" "$T/t2/regions.png"

expect_exit 0 maps_are_written "$JND" pop "$T/new.png" "$T/expected.png" -o "$T/maps" --maps --weights "$T/depth.png" --quiet
check jnd_and_weight_maps_are_exr bash -c "head -c 4 '$T/maps/jnd.exr' | od -An -tx1 | grep -q '76 2f 31 01' && test -s '$T/maps/weights.exr'"
expect_exit 1 fail_above_exits_one "$JND" pop "$T/new.png" "$T/expected.png" -o "$T/fa" --fail-above -5 --quiet
expect_exit 0 fail_above_passes_identical "$JND" pop "$T/expected.png" "$T/expected.png" -o "$T/fb" --fail-above 1 --quiet
expect_exit 0 json_to_stdout "$JND" pop "$T/new.png" "$T/expected.png" -o "$T/js" --json - --quiet --display phone
check stdout_is_the_report jq -e '.command == "pop" and .parameters.display.name == "phone"' "$T/out.txt"

# a switch is a change in place: the flicker task whatever --task says
# (docs/pop.md "The viewing task"). A whole frame 4 codes greener: side by side
# its mean colour is capped at ΔE00 (diff's JND is lower), flickered it is
# not; pop's JND is the flickered one under either --task
PYTHONPATH="$(dirname "$0")" python3 -B - "$T" <<'PY'
import sys
from pngwrite import png
png(f'{sys.argv[1]}/grey.png', 256, 256, 3, lambda x, y: (0.5, 0.5, 0.5))
png(f'{sys.argv[1]}/greener.png', 256, 256, 3, lambda x, y: (0.5, 0.515, 0.5))
PY
for task in flicker side-by-side; do
  "$JND" diff "$T/grey.png" "$T/greener.png" --task $task --json "$T/d_$task.json" --quiet
  expect_exit 0 "pop_runs_with_task_$task" "$JND" pop "$T/greener.png" "$T/grey.png" -o "$T/t_$task" --task $task --json "$T/p_$task.json"
done
check pop_says_it_does_not_take_side_by_side grep -q 'judged in the flicker task, not --task side-by-side' "$T/err.txt"
check pop_reports_the_flicker_task_whatever_task_says jq -e -s 'all(.[]; .parameters.display.task == "flicker")' "$T/p_side-by-side.json" "$T/p_flicker.json"
check the_shift_is_less_visible_side_by_side jq -e -s '.[0].result.jnd_max < 0.95 * .[1].result.jnd_max' "$T/d_side-by-side.json" "$T/d_flicker.json"
check pop_judges_as_diff_flickered jq -e -s '.[0].result.jnd_max == .[2].result.jnd_max and .[1].result.jnd_max == .[2].result.jnd_max' \
  "$T/p_side-by-side.json" "$T/p_flicker.json" "$T/d_flicker.json"

# bad input: exit 2, one line naming the file, nothing written
refused() { # refused NAME WORD ARGS...: exit 2, one line mentioning WORD, no output folder
  local name=$1 word=$2; shift 2
  rm -rf "$T/bad"
  expect_exit 2 "$name" "$JND" pop "$@"
  check "${name}_is_one_line" one_line_error
  check "${name}_names_it" grep -q -- "$word" "$T/err.txt"
  check "${name}_writes_nothing" test ! -e "$T/bad"
}
refused frames_of_different_sizes small.png "$T/small.png" "$T/expected.png" -o "$T/bad"
refused displacement_of_another_size small_disp.exr "$T/new.png" "$T/expected.png" -o "$T/bad" --displacement "$T/small_disp.exr"
refused displacement_with_nan nan_disp.exr "$T/new.png" "$T/expected.png" -o "$T/bad" --displacement "$T/nan_disp.exr"
refused weight_outside_0_1 bad_weights.exr "$T/new.png" "$T/expected.png" -o "$T/bad" --weights "$T/bad_weights.exr"
refused depth_not_exr depth.png "$T/new.png" "$T/expected.png" -o "$T/bad" --depth "$T/depth.png" --prev-depth "$T/prev_depth.exr"
refused depth_without_previous_depth depth.exr "$T/new.png" "$T/expected.png" -o "$T/bad" --depth "$T/depth.exr"
refused missing_frame nope.png "$T/nope.png" "$T/expected.png" -o "$T/bad"
refused unknown_option frobnicate "$T/new.png" "$T/expected.png" -o "$T/bad" --frobnicate
refused asset_options_in_the_frame_form "asset form" "$T/new.png" "$T/expected.png" -o "$T/bad" --orbit 30
refused no_output_folder "-o OUT" "$T/new.png" "$T/expected.png"
finish
