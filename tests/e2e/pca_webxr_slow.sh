#!/usr/bin/env bash
# jnd pca --p (rendered choice) on a real asset: the oculus-touch-v3 controller of the
# MIT-licensed npm package @webxr-input-profiles/assets (pinned and cached by
# scripts/install-deps.sh, never fetched by the test), its material's own maps
# as the set. The chosen encoding must store less than the original maps and
# the report must list rendered P per view for it. Skips (exit 77) when the
# cache is missing.
. "$(dirname "$0")/lib.bash"
need_webxr_assets
need_renderer
F="$ASSETS/dist/profiles/oculus-touch-v3/left.glb"
[ -f "$F" ] || { bad "oculus-touch-v3/left.glb is in the package"; finish; }
# the first material with maps, as `jnd render --list-maps` names it
MAT=$("$JND" render "$F" -o "$T/list" --list-maps 2>/dev/null | awk 'NR == 1 { sub("/[^/]*$", "", $1); print $1 }')
check controller_has_a_material_with_maps test -n "$MAT"

expect_exit 0 rendered_search_on_the_controller_runs \
  "$JND" pca --model "$F" --material "$MAT" -o "$T/ctrl" --p 0.2 --views 8 --size 256x256 --timings
J="$T/ctrl/pca.json"
check chosen_encoding_is_smaller_than_the_original_maps \
  jq -e '.result.storage_bytes < .result.original_bytes' "$J"
check report_lists_rendered_p_for_each_of_8_views \
  jq -e '(.result.rendered.p_per_view | length) == 8 and all(.result.rendered.p_per_view[]; . >= 0 and . <= 1)' "$J"
check chosen_encoding_meets_the_criterion \
  jq -e '.result.rendered.pass and .result.rendered.views_above <= .result.rendered.criterion.allowed' "$J"
check block_compressed_variants_are_rendered_too \
  jq -e '[.result.rendered.block_compressed[] | .p_per_view | length] == [8, 8, 8]' "$J"
check summary_lists_p_per_view grep -q "chosen .*P per view:" "$T/err.txt"
jq -r '"   K=\(.result.components_kept), \(.result.storage_bytes) of \(.result.original_bytes) bytes, P per view \(.result.rendered.p_per_view | map(. * 1000 | round / 1000)), \(.result.timings_s.total | . * 10 | round / 10) s"' "$J"
finish
