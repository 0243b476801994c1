#!/usr/bin/env bash
# jnd diff's report (src/tasks/diff_report.c), each field from a second
# route: the size from the PNG it read, the rate from the size and the time,
# the bands' peaks in proportion to the pixels per degree (and the coarsest
# the last above 0.5 cpd of octave bands), the gate's flag from P and the
# exit status, the percentiles in their order. Tiny inputs, no renderer.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
command -v python3 >/dev/null || skip "needs python3"
command -v jq >/dev/null || skip "needs jq"

# a 96 x 64 grey ramp, and the same with a disc one code darker (P about 0.66) (non-square, so that width and height differ)
PYTHONPATH="$(dirname "$0")" python3 - "$T" <<'PY'
import sys
from pngwrite import png
t = sys.argv[1]
ramp = lambda x, y: (0.3 + 0.4 * x / 95,) * 3
disc = lambda x, y: tuple(v - (0.004 if (x - 60) ** 2 + (y - 30) ** 2 < 100 else 0) for v in ramp(x, y))
png(t + "/ref.png", 96, 64, 3, ramp)
png(t + "/test.png", 96, 64, 3, disc)
PY
D=("$T/ref.png" "$T/test.png")

expect_exit 0 diff_runs "$JND" diff "${D[@]}" --timings --json "$T/d.json" --quiet
check size_is_the_pngs jq -e '.result.width == 96 and .result.height == 64 and .inputs.reference_format == "png"' "$T/d.json"
check rate_is_pixels_over_time jq -e \
  '((.result.timings.megapixels_per_s - 96 * 64 / 1e6 / .result.timings.total_s) | fabs) <= 1e-9 * .result.timings.megapixels_per_s' "$T/d.json"
check percentiles_in_order jq -e '.result as $r | $r.p_p50 <= $r.p_p93 and $r.p_p93 <= $r.p_p99 and $r.p_p99 <= $r.p_max
  and $r.p_mean <= $r.p_max and $r.jnd_mean <= $r.jnd_max and $r.jnd_p93 <= $r.jnd_max and $r.p_max > 0' "$T/d.json"

# the gate: above_threshold is P > the gate, and so is exit status 1
lo=$(jq '.result.p_detect / 2' "$T/d.json") hi=$(jq '[0.999, .result.p_detect * 1.2 + 0.01] | min' "$T/d.json")
expect_exit 1 gate_below_p_exits_one "$JND" diff "${D[@]}" --fail-above "$lo" --json "$T/lo.json" --quiet
check gate_below_p_is_above jq -e --argjson g "$lo" '.result.above_threshold == true and .parameters.fail_above == $g' "$T/lo.json"
expect_exit 0 gate_above_p_exits_zero "$JND" diff "${D[@]}" --fail-above "$hi" --json "$T/hi.json" --quiet
check gate_above_p_is_not_above jq -e '.result.above_threshold == false' "$T/hi.json"
check no_gate_no_flag jq -e '.result | has("above_threshold") | not' "$T/d.json"

# the bands: each band's peak in cpd is its cycles per pixel times the ppd
# (doubling the ppd doubles every band), and from the seventh on each is an
# octave below the one before (src/vision/model.c's self-similar bands)
"$JND" diff "${D[@]}" --ppd 60 --json "$T/b60.json" --quiet
"$JND" diff "${D[@]}" --ppd 120 --json "$T/b120.json" --quiet
check bands_scale_with_ppd jq -e --slurpfile a "$T/b60.json" '
  .result.bands_cpd as $b | $a[0].result.bands_cpd as $h | ($h | length) >= 1 and ($b | length) >= ($h | length) and
  ([range(0; $h | length) | (($b[.] - 2 * $h[.]) | fabs) <= 2e-4] | all)' "$T/b120.json"
check bands_past_the_table_are_octaves jq -e '.result.bands_cpd as $b | ($b | length) >= 8 and
  ([range(6; $b | length) | (($b[.] - $b[. - 1] / 2) | fabs) <= 2e-4] | all)' "$T/b120.json"
check display_ppd_reported jq -e '.parameters.display.ppd == 120' "$T/b120.json"

echo "$((checks - fails)) passed, $fails failed"
[ "$fails" -eq 0 ]
