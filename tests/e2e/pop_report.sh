#!/usr/bin/env bash
# jnd pop's report (src/tasks/pop_report.c), its numbers from a second route:
# the frame's size, the object's pixels (no mask: every pixel), the covered
# pixels the sum of the regions', the coverage their ratio, each region's R
# from its Σ by 004's R = ln(0.375 Σ) / ln(2.25), the largest R the largest
# region's. Tiny frames, no renderer.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
command -v python3 >/dev/null || skip "needs python3"
command -v jq >/dev/null || skip "needs jq"

PYTHONPATH="$(dirname "$0")" python3 -B - "$T" <<'PY'
import sys
from pngwrite import png
from popframes import background, patch
d = sys.argv[1]
W, H = 96, 72
bg = background(W, H)
png(f'{d}/expected.png', W, H, 3, bg)
png(f'{d}/new.png', W, H, 3, patch(bg, 0.25))
PY
expect_exit 0 pop_runs "$JND" pop "$T/expected.png" "$T/new.png" -o "$T/p" --quiet
R=$T/p/pop.json
check size_is_the_frames jq -e '.result.width == 96 and .result.height == 72' "$R"
check a_region_is_found jq -e '.result.region_count >= 1 and (.result.regions | length) == .result.region_count' "$R"
check object_is_every_pixel_without_a_mask jq -e '.result.object_pixels == 96 * 72' "$R"
check covered_is_the_regions_pixels jq -e '.result.covered_pixels == ([.result.regions[].pixels] | add)' "$R"
check coverage_is_covered_over_object jq -e \
  '((.result.coverage - .result.covered_pixels / .result.object_pixels) | fabs) < 1e-12' "$R"
check rating_from_sigma_by_004 jq -e \
  '[.result.regions[] | ((.rating - ((0.375 * .sigma | log) / (2.25 | log))) | fabs) < 1e-9 * ((.rating | fabs) + 1)] | all' "$R"
check max_rating_is_the_largest jq -e '.result.max_rating == ([.result.regions[].rating] | max)' "$R"
check boxes_inside_the_frame jq -e '[.result.regions[] | .bbox as $b | $b[0] >= 0 and $b[1] >= 0 and $b[2] < 96 and $b[3] < 72
  and $b[0] <= $b[2] and $b[1] <= $b[3] and .pixels <= ($b[2] - $b[0] + 1) * ($b[3] - $b[1] + 1)] | all' "$R"

echo "$((checks - fails)) passed, $fails failed"
[ "$fails" -eq 0 ]
