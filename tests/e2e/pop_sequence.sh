#!/usr/bin/env bash
# jnd pop over a sequence of frames (--frames FIRST,LAST with %0Nd paths):
# the frame table in pop.json and frames.csv, the worst frame's report and
# picture, per-frame maps, determinism across thread counts, and bad input
# (a missing frame, a frame of another size, a path without a frame number:
# exit 2, one line, nothing written).
. "$(dirname "$0")/lib.bash"
command -v python3 >/dev/null || skip "needs python3"

# frames 1..4 of a level switch: EXPECTED is the same textured background
# each frame; NEW adds nothing (1), a faint grating (2), a strong one (3),
# nothing again (4). Frame 3 moves fast (32 px a frame), the others are still.
PYTHONPATH="$(dirname "$0")" python3 -B - "$T" <<'PY'
import sys
from pngwrite import png
from exrwrite import exr
from popframes import background, patch
d = sys.argv[1]
W, H = 160, 120
bg = background(W, H)
blob = lambda a: patch(bg, a)
for n, a in ((1, 0), (2, 0.12), (3, 0.3), (4, 0)):
    png(f'{d}/expected_{n:04d}.png', W, H, 3, bg)
    png(f'{d}/new_{n:04d}.png', W, H, 3, blob(a) if a else bg)
    v = 32.0 if n == 3 else 0.0
    exr(f'{d}/motion_{n}.exr', W, H, {'X': lambda x, y, v=v: v, 'Y': lambda x, y: 0.0})
png(f'{d}/mask.png', W, H, 3, lambda x, y: (1, 1, 1) if 40 <= x < 120 else (0, 0, 0))
# frame 5 has its frames but no displacement map
png(f'{d}/expected_0005.png', W, H, 3, bg)
png(f'{d}/new_0005.png', W, H, 3, bg)
PY
mkdir -p "$T/sz"
cp "$T/new_0003.png" "$T/sz/new_1.png"; cp "$T/expected_0003.png" "$T/sz/expected_1.png"
PYTHONPATH="$(dirname "$0")" python3 -B -c "
from pngwrite import png
png('$T/sz/new_2.png', 150, 120, 3, lambda x, y: (0.5, 0.5, 0.5))
png('$T/sz/expected_2.png', 150, 120, 3, lambda x, y: (0.4, 0.5, 0.5))"

expect_exit 0 a_sequence_runs "$JND" pop "$T/new_%04d.png" "$T/expected_%04d.png" --frames 1,4 -o "$T/seq" --quiet
J=$T/seq/pop.json
check the_table_has_a_row_per_frame jq -e '[.result.frames[].frame] == [1, 2, 3, 4] and .inputs.frames == [1, 4] and .result.outputs.frames == "frames.csv"' "$J"
check unchanged_frames_have_no_region jq -e '[.result.frames[0, 3] | .regions == 0 and .max_rating == null and .detection_score == 1 and .max_delta_e94 == 0 and .jnd_max == 0] == [true, true]' "$J"
check changed_frames_have_rated_regions jq -e '[.result.frames[1, 2] | .regions >= 1 and (.max_rating | type == "number") and .max_delta_e94 > 0] == [true, true]' "$J"
check the_stronger_change_is_the_worst_frame jq -e '.result.worst_frame == 3 and .result.frames[2].max_rating > .result.frames[1].max_rating' "$J"
check the_report_is_the_worst_frames jq -e '.result.max_rating == .result.frames[2].max_rating and .result.region_count == .result.frames[2].regions and .result.detection_score == .result.frames[2].detection_score' "$J"
check the_csv_has_the_same_rows python3 -c "
import csv, json, sys
rows = list(csv.DictReader(open('$T/seq/frames.csv')))
fr = json.load(open('$J'))['result']['frames']
ok = [r['frame'] for r in rows] == ['1', '2', '3', '4'] and rows[0]['max_rating'] == '' and all(
    int(r['regions']) == f['regions'] and int(r['detection_score']) == f['detection_score'] and
    (r['max_rating'] == '' if f['max_rating'] is None else abs(float(r['max_rating']) - f['max_rating']) < 1e-5)
    for r, f in zip(rows, fr))
sys.exit(0 if ok else 1)"
check regions_png_is_written test -s "$T/seq/regions.png"

# the worst frame's report is what the pair form says about that frame
expect_exit 0 the_worst_frame_alone_runs "$JND" pop "$T/new_0003.png" "$T/expected_0003.png" -o "$T/pair3" --quiet
check the_worst_frames_regions_match_its_pair jq -e --slurpfile p "$T/pair3/pop.json" '.result.regions == $p[0].result.regions and .result.max_delta_e94 == $p[0].result.max_delta_e94' "$J"
check the_worst_frames_picture_matches_its_pair cmp -s "$T/seq/regions.png" "$T/pair3/regions.png"

# maps take a frame number too (%d, unpadded); a path without one serves every frame
expect_exit 0 per_frame_maps_run "$JND" pop "$T/new_%04d.png" "$T/expected_%04d.png" --frames 1,4 --displacement "$T/motion_%d.exr" --mask "$T/mask.png" -o "$T/mov" --quiet
check motion_lowers_the_moving_frames_rating jq -e --slurpfile s "$J" '(.result.frames[2].max_rating == null or .result.frames[2].max_rating < $s[0].result.frames[2].max_rating) and ((.result.frames[1].max_rating - $s[0].result.frames[1].max_rating) | fabs < 1e-4)' "$T/mov/pop.json"
check the_mask_serves_every_frame jq -e '.inputs.mask and ([.result.frames[] | .coverage] | all(. <= 1))' "$T/mov/pop.json"

"$JND" pop "$T/new_%04d.png" "$T/expected_%04d.png" --frames 1,4 -o "$T/t1" --threads 1 --quiet
"$JND" pop "$T/new_%04d.png" "$T/expected_%04d.png" --frames 1,4 -o "$T/t2" --threads 2 --quiet
check the_table_is_byte_identical_across_thread_counts cmp -s "$T/t1/pop.json" "$T/t2/pop.json"
check the_csv_is_byte_identical_across_thread_counts cmp -s "$T/t1/frames.csv" "$T/t2/frames.csv"
expect_exit 1 fail_above_sees_the_worst_frame "$JND" pop "$T/new_%04d.png" "$T/expected_%04d.png" --frames 1,4 -o "$T/fa" --fail-above 0 --quiet

# bad input: exit 2, one line naming the problem, no output folder
refused() { # refused NAME WORD ARGS...
  local name=$1 word=$2; shift 2
  rm -rf "$T/bad"
  expect_exit 2 "$name" "$JND" pop "$@" --quiet
  check "${name}_is_one_line" one_line_error
  check "${name}_names_it" grep -q -- "$word" "$T/err.txt"
  check "${name}_writes_nothing" test ! -e "$T/bad"
}
refused a_missing_frame new_0006.png "$T/new_%04d.png" "$T/expected_%04d.png" --frames 3,6 -o "$T/bad"
refused a_frame_of_another_size "new_2.png" "$T/sz/new_%d.png" "$T/sz/expected_%d.png" --frames 1,2 -o "$T/bad"
refused a_missing_map_frame motion_5.exr "$T/new_%04d.png" "$T/expected_%04d.png" --frames 1,5 --displacement "$T/motion_%d.exr" -o "$T/bad"
refused new_without_a_frame_number "frame number" "$T/new_0001.png" "$T/expected_%04d.png" --frames 1,2 -o "$T/bad"
refused a_pattern_with_another_field "%s" "$T/new_%s.png" "$T/expected_%04d.png" --frames 1,2 -o "$T/bad"
refused a_pattern_with_two_fields "frame number field" "$T/new_%04d_%d.png" "$T/expected_%04d.png" --frames 1,2 -o "$T/bad"
refused frames_backwards "FIRST,LAST" "$T/new_%04d.png" "$T/expected_%04d.png" --frames 4,1 -o "$T/bad"
refused frames_not_a_pair "FIRST,LAST" "$T/new_%04d.png" "$T/expected_%04d.png" --frames 4 -o "$T/bad"
refused frames_in_the_asset_form "--frames" builtin --frames 1,2 -o "$T/bad"
finish
