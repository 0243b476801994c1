#!/usr/bin/env bash
# jnd diff end to end: the synthetic pair, identical images, gating, determinism, bad input.
. "$(dirname "$0")/lib.bash"
need_renderer

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
expect_exit 0 display_and_gaze_run "$JND" diff "$T/ex/reference.png" "$T/ex/test.png" --display phone --gaze 10,10 --json "$T/phone.json" --quiet
check display_and_gaze_are_the_ones_asked_for \
  jq -e '.parameters.display.name == "phone" and .parameters.display.peak_cdm2 == 500 and .parameters.gaze == [10, 10]' "$T/phone.json"

# A faint pair (16-bit PNG: three windowed 4 cpd gratings of 0.06, 0.10 and
# 0.14% of the signal on grey) whose JNDs lie around 1, where P depends on
# the slope β and the percentiles differ: the defaults as used, not only as
# written in the report.
command -v python3 >/dev/null || skip "needs python3"
PYTHONPATH="$(dirname "$0")" python3 - "$T" <<'PY'
import math, sys
from pngwrite import png
d = sys.argv[1]
blobs = [(48, 48, 0.0006), (128, 48, 0.0010), (208, 48, 0.0014)]
def test(x, y):
    v = 0.5 + sum(a * math.exp(-((x - cx) ** 2 + (y - cy) ** 2) / (2 * 14 ** 2)) * math.cos(2 * math.pi * 0.1 * (x - cx))
                  for cx, cy, a in blobs)
    return (v, v, v)
png(f'{d}/faint_ref.png', 256, 96, 3, lambda x, y: (0.5, 0.5, 0.5), bits=16)
png(f'{d}/faint_test.png', 256, 96, 3, test, bits=16)
PY
F=("$T/faint_ref.png" "$T/faint_test.png")

# An 8-bit RGB PNG decodes straight to the display's luminances (issue 29):
# the same picture at 8 and at 16 bits, either as the reference, is the same
# image on the display, and so is an 8-bit RGBA one whose alpha is opaque.
PYTHONPATH="$(dirname "$0")" python3 - "$T" <<'PY'
import sys
from pngwrite import png
d = sys.argv[1]
f = lambda x, y: (((x * 7 + y * 3) % 256) / 255, ((x * 5) % 256) / 255, ((y * 11) % 256) / 255)
png(f'{d}/bits8.png', 64, 48, 3, f)
png(f'{d}/bits16.png', 64, 48, 3, f, bits=16)
png(f'{d}/bits8a.png', 64, 48, 4, lambda x, y: f(x, y) + (1.0,))
PY
for pair in "bits16 bits8" "bits8 bits16" "bits8a bits8" "bits8 bits8a"; do
  set -- $pair
  "$JND" diff "$T/$1.png" "$T/$2.png" --json "$T/bits.json" --quiet
  check "an_8_bit_png_is_the_same_image_as_${1}_against_${2}" jq -e '.result.jnd_max == 0' "$T/bits.json"
done
expect_exit 0 faint_pair_runs "$JND" diff "${F[@]}" --json "$T/faint.json" --quiet
check faint_pair_has_jnds_around_one jq -e '.result.jnd_max > 0.5 and .result.jnd_max < 2 and .result.p_p93 > 0.02 and .result.p_p93 < 0.98' "$T/faint.json"
check default_pooling_p93_and_beta_3_5_are_reported \
  jq -e '.parameters.pooling == "p93" and .result.pooling == "p93" and .parameters.beta == 3.5' "$T/faint.json"
check default_pooling_is_p93_as_used jq -e '.result.p_detect == .result.p_p93' "$T/faint.json"
# 000 eq. 4: P = 1 − 0.5^(JND^β); P is monotonic in JND, so P's p93 is P of the JND p93 (to interpolation)
check p_follows_000_eq4_with_beta_3_5 jq -e '
  ((.result.p_max - (1 - pow(0.5; pow(.result.jnd_max; 3.5)))) | fabs) < 1e-4 and
  ((.result.p_p93 - (1 - pow(0.5; pow(.result.jnd_p93; 3.5)))) | fabs) < 1e-3' "$T/faint.json"
# every pooling: the reported name and the value of that pooling
for pool in p50:p_p50 p93:p_p93 p99:p_p99 max:p_max mean:p_mean; do
  "$JND" diff "${F[@]}" --pool "${pool%%:*}" --json "$T/pool.json" --quiet
  check "pooling_${pool%%:*}_reports_its_name_and_value" jq -e --slurpfile d "$T/faint.json" \
    --arg name "${pool%%:*}" --arg field "${pool#*:}" \
    '.parameters.pooling == $name and .result.p_detect == $d[0].result[$field]' "$T/pool.json"
done
"$JND" diff "${F[@]}" --pool minkowski --json "$T/pool.json" --quiet
# the Minkowski (2.4) mean of P lies strictly between the mean and the maximum of a non-constant map
check pooling_minkowski_lies_between_mean_and_max jq -e --slurpfile d "$T/faint.json" \
  '.parameters.pooling == "minkowski" and .result.p_detect > $d[0].result.p_mean and .result.p_detect < $d[0].result.p_max' "$T/pool.json"

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
check weights_lower_the_jnd jq -e --slurpfile s "$T/still.json" '.result.jnd_max < $s[0].result.jnd_max' "$T/weighted.json"
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
# valid chunks and CRCs around a corrupt deflate stream: an 8-bit RGB file,
# read as codes (jnd_png_decode_rgb8) — and a 16-bit one beside it, read as
# planes — is refused in one line naming it, with nothing written
python3 -B - "$T" <<'PY3'
import struct, sys, zlib
t = sys.argv[1]
def png(path, bits):
    w, h = 64, 48
    raw = b"".join(b"\0" + bytes((x * 3 + y) & 255 for x in range(w * 3 * bits // 8)) for y in range(h))
    z = bytearray(zlib.compress(raw))
    for i in range(10, len(z) - 8, 7):
        z[i] ^= 0x5A
    def chunk(k, d):
        return struct.pack(">I", len(d)) + k + d + struct.pack(">I", zlib.crc32(k + d) & 0xFFFFFFFF)
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, bits, 2, 0, 0, 0))
                          + chunk(b"IDAT", bytes(z)) + chunk(b"IEND", b""))
png(t + "/baddata8.png", 8)
png(t + "/baddata16.png", 16)
PY3
"$JND" example -o "$T/s64" --size 64x48 2>/dev/null
for bits in 8 16; do
  expect_exit 2 "corrupt_${bits}_bit_deflate_exits_two" "$JND" diff "$T/baddata$bits.png" "$T/s64/test.png" --json "$T/bd$bits.json"
  check "corrupt_${bits}_bit_deflate_error_is_one_line" one_line_error
  check "corrupt_${bits}_bit_deflate_names_the_file" grep -q "baddata$bits.png: corrupt PNG" "$T/err.txt"
  check "no_report_after_corrupt_${bits}_bit_deflate" test ! -e "$T/bd$bits.json"
done
: >"$T/empty.png"
expect_exit 2 empty_file_exits_two "$JND" diff "$T/empty.png" "$T/ex/test.png"
"$JND" example -o "$T/small" --size 128x96 2>/dev/null
expect_exit 2 mismatched_sizes_exit_two "$JND" diff "$T/ex/reference.png" "$T/small/test.png"
check mismatched_sizes_error_is_one_line one_line_error
# an EXR at the default --exr-scale whose brightest pixel is a few units (written relative, 1 = white) is said
# to be read as cd/m2, in one line per file; not with --exr-scale, nor for an absolute one, nor with --quiet
PYTHONPATH="$(dirname "$0")" python3 -B - "$T" <<'PY2'
import sys
from exrwrite import exr
t = sys.argv[1]
exr(t + "/rel_a.exr", 32, 32, {"R": lambda x, y: 0.5, "G": lambda x, y: 0.5, "B": lambda x, y: 0.5})
exr(t + "/rel_b.exr", 32, 32, {"R": lambda x, y: 0.5 + 0.2 * (x % 2), "G": lambda x, y: 0.5, "B": lambda x, y: 0.5})
exr(t + "/abs_a.exr", 32, 32, {"R": lambda x, y: 100.0, "G": lambda x, y: 100.0, "B": lambda x, y: 100.0})
exr(t + "/abs_b.exr", 32, 32, {"R": lambda x, y: 100 + 20 * (x % 2), "G": lambda x, y: 100.0, "B": lambda x, y: 100.0})
PY2
expect_exit 0 relative_exr_runs "$JND" diff "$T/rel_a.exr" "$T/rel_b.exr"
check relative_exr_at_the_default_scale_is_said_once_per_file bash -c "[ \$(grep -c '^jnd: warning: .*rel_[ab].exr: .*--exr-scale' '$T/err.txt') -eq 2 ]"
expect_exit 0 relative_exr_with_a_scale_runs "$JND" diff "$T/rel_a.exr" "$T/rel_b.exr" --exr-scale 200
check no_warning_with_exr_scale bash -c "! grep -q 'warning' '$T/err.txt'"
expect_exit 0 absolute_exr_runs "$JND" diff "$T/abs_a.exr" "$T/abs_b.exr"
check no_warning_for_an_absolute_exr bash -c "! grep -q 'warning' '$T/err.txt'"
expect_exit 2 unknown_option_exits_two "$JND" diff "$T/ex/reference.png" "$T/ex/test.png" --frobnicate
expect_exit 2 unknown_display_exits_two "$JND" diff "$T/ex/reference.png" "$T/ex/test.png" --display crt
expect_exit 2 bad_pooling_exits_two "$JND" diff "$T/ex/reference.png" "$T/ex/test.png" --pool p200
expect_exit 2 one_image_is_not_enough "$JND" diff "$T/ex/reference.png"
finish
