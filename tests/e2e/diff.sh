#!/usr/bin/env bash
# jnd diff end to end: the synthetic pair, identical images, gating, determinism, bad input.
. "$(dirname "$0")/lib.bash"

expect_exit 0 help_exits_zero "$JND" diff --help
expect_exit 0 example_writes_a_pair "$JND" example -o "$T/ex" --size 320x240
expect_exit 0 diff_of_the_example_pair_runs "$JND" diff "$T/ex/reference.png" "$T/ex/test.png" --json "$T/d.json" --heatmap "$T/h.png" --quiet
check json_has_the_stable_fields jq -e '(.result.p_detect >= 0) and (.result.p_detect <= 1) and (.result.jnd_max > 0) and .jnd_version and .command == "diff" and .inputs and .parameters' "$T/d.json"
check heatmap_is_a_png bash -c "head -c 8 '$T/h.png' | od -An -c | grep -q 'P   N   G'"
check the_distorted_pair_is_visible jq -e '.result.p_detect > 0.5' "$T/d.json"

expect_exit 0 identical_images_run "$JND" diff "$T/ex/reference.png" "$T/ex/reference.png" --json "$T/same.json" --quiet
check identical_images_have_zero_jnd_and_p jq -e '.result.p_detect == 0 and .result.jnd_max == 0 and .result.p_max == 0' "$T/same.json"

expect_exit 1 fail_above_exits_one_when_visible "$JND" diff "$T/ex/reference.png" "$T/ex/test.png" --fail-above 0.2 --quiet
expect_exit 0 fail_above_exits_zero_when_invisible "$JND" diff "$T/ex/reference.png" "$T/ex/reference.png" --fail-above 0.2 --quiet

"$JND" diff "$T/ex/reference.png" "$T/ex/test.png" --threads 1 --json "$T/t1.json" --quiet
"$JND" diff "$T/ex/reference.png" "$T/ex/test.png" --threads 2 --json "$T/t2.json" --quiet
check json_is_byte_identical_across_thread_counts cmp -s "$T/t1.json" "$T/t2.json"

expect_exit 0 json_to_stdout "$JND" diff "$T/ex/reference.png" "$T/ex/test.png" --json - --quiet
check stdout_is_json jq -e '.result.p_detect' "$T/out.txt"
expect_exit 0 every_pooling_parses "$JND" diff "$T/ex/reference.png" "$T/ex/test.png" --pool p50 --display phone --gaze 10,10 --quiet

# an explicit quantity wins over the preset, whatever the order (issue 9:
# --ppd 40 --display phone reported the phone's 94.26)
for order in "--ppd 40 --display phone" "--display phone --ppd 40"; do
  "$JND" diff "$T/ex/reference.png" "$T/ex/test.png" $order --peak 300 --json "$T/order.json" --quiet
  check "explicit_ppd_and_peak_win_over_the_preset: $order" jq -e '.parameters.display.ppd == 40 and .parameters.display.peak_cdm2 == 300
    and .parameters.display.name == "phone"' "$T/order.json"
done
expect_exit 2 gaze_outside_the_image_is_refused "$JND" diff "$T/ex/reference.png" "$T/ex/test.png" --gaze 400,10
check gaze_refusal_is_one_line one_line_error

# float outputs and inputs: the JND map as EXR; a rendered motion map (EXR, X and Y) and weights
expect_exit 0 map_is_written "$JND" diff "$T/ex/reference.png" "$T/ex/test.png" --map "$T/jnd.exr" --quiet
check map_is_an_exr bash -c "head -c 4 '$T/jnd.exr' | od -An -tx1 | grep -q '76 2f 31 01'"
expect_exit 0 renders_for_motion "$JND" render builtin -o "$T/r" --views 1 --size 96x96 --outputs color,motion,exr --motion-orbit 20 --quiet
"$JND" example -o "$T/ex96" --size 96x96 2>/dev/null
"$JND" diff "$T/ex96/reference.png" "$T/ex96/test.png" --json "$T/still.json" --quiet
expect_exit 0 motion_map_is_read "$JND" diff "$T/ex96/reference.png" "$T/ex96/test.png" --motion "$T/r/view_000_motion.exr" --fps 60 --json "$T/moving.json" --quiet
check motion_changes_the_prediction bash -c "[ \"\$(jq .result.jnd_max '$T/still.json')\" != \"\$(jq .result.jnd_max '$T/moving.json')\" ]"
expect_exit 0 weights_are_read "$JND" diff "$T/ex96/reference.png" "$T/ex96/test.png" --weights "$T/r/view_000.png" --json "$T/weighted.json" --quiet
check weights_lower_the_jnd jq -e --slurpfile s "$T/still.json" '.result.jnd_max <= $s[0].result.jnd_max' "$T/weighted.json"
expect_exit 2 motion_map_of_another_size_exits_two "$JND" diff "$T/ex/reference.png" "$T/ex/test.png" --motion "$T/r/view_000_motion.exr"
check motion_size_error_is_one_line one_line_error

# bad input: one line "jnd: FILE: problem", exit 2, no partial outputs
expect_exit 2 missing_file_exits_two "$JND" diff "$T/nope.png" "$T/ex/test.png" --json "$T/x1.json"
check missing_file_error_is_one_line one_line_error
check missing_file_names_the_file grep -q "nope.png" "$T/err.txt"
check no_report_after_bad_input test ! -e "$T/x1.json"
printf 'hello, not an image' >"$T/text.png"
expect_exit 2 non_image_exits_two "$JND" diff "$T/text.png" "$T/ex/test.png"
check non_image_error_is_one_line one_line_error
head -c 3000 "$T/ex/reference.png" >"$T/trunc.png"
expect_exit 2 truncated_png_exits_two "$JND" diff "$T/trunc.png" "$T/ex/test.png" --heatmap "$T/x2.png"
check truncated_png_error_is_one_line one_line_error
check no_heatmap_after_bad_input test ! -e "$T/x2.png"
cp "$T/ex/reference.png" "$T/crc.png"
printf '\x00' | dd of="$T/crc.png" bs=1 seek=200 conv=notrunc 2>/dev/null
expect_exit 2 png_with_bad_crc_exits_two "$JND" diff "$T/crc.png" "$T/ex/test.png"
check bad_crc_is_named grep -q "CRC" "$T/err.txt"
: >"$T/empty.png"
expect_exit 2 empty_file_exits_two "$JND" diff "$T/empty.png" "$T/ex/test.png"
"$JND" example -o "$T/small" --size 128x96 2>/dev/null
expect_exit 2 mismatched_sizes_exit_two "$JND" diff "$T/ex/reference.png" "$T/small/test.png"
check mismatched_sizes_error_is_one_line one_line_error
expect_exit 2 unknown_option_exits_two "$JND" diff "$T/ex/reference.png" "$T/ex/test.png" --frobnicate
expect_exit 2 unknown_display_exits_two "$JND" diff "$T/ex/reference.png" "$T/ex/test.png" --display crt
expect_exit 2 bad_pooling_exits_two "$JND" diff "$T/ex/reference.png" "$T/ex/test.png" --pool p200
expect_exit 2 one_image_is_not_enough "$JND" diff "$T/ex/reference.png"
finish
