#!/usr/bin/env bash
# jnd pca with rendered visibility on the builtin asset (its material has
# baseColor, metallicRoughness, normal and occlusion maps, generated at 128²):
# the material's own maps as the set, the rendered choice (--p) searching the cheapest encoding
# whose renderings pass, P per view listed for it and for its block-compressed
# variants; map files bound to slots by name or --slot; one-line errors.
# P values are not asserted (the model's constants are being refitted), only
# the properties every calibration must keep.
. "$(dirname "$0")/lib.bash"
need_renderer
R="--model builtin --map-size 128 --material builtin --views 4 --size 128x128 --anisotropy 1"

# with a model and no criterion, the rendered choice at p = 0.2, q = 0.1 (000 §9) is the default
expect_exit 0 rendered_search_runs "$JND" pca $R -o "$T/mp"
J="$T/mp/pca.json"
check human_summary_lists_p_per_view grep -q "chosen .*P per view:" "$T/err.txt"
check the_set_is_the_materials_own_maps \
  jq -e '[.inputs.maps[].name] == ["baseColor","metallicRoughness","normal","occlusion"]
         and .result.rendered.slots.normal == "normal"' "$J"
check shader_channels_only_for_packed_maps \
  jq -e '[.result.channels[].name] | index("metallicRoughness.g") != null and index("metallicRoughness.r") == null' "$J"
check lists_pooled_p_for_every_view \
  jq -e '.result.rendered.views == 4 and (.result.rendered.p_per_view | length) == 4
         and all(.result.rendered.p_per_view[]; . >= 0 and . <= 1)' "$J"
check chosen_encoding_meets_the_criterion \
  jq -e '.parameters.criterion == "rendered" and .result.rendered.pass
         and ([.result.rendered.p_per_view[] | select(. > 0.2)] | length) <= .result.rendered.criterion.allowed' "$J"
check default_criterion_is_000s_p_0_2_q_0_1_with_p93_pooling \
  jq -e '.result.rendered.criterion.p == 0.2 and .result.rendered.criterion.q == 0.1
         and .result.rendered.pooling == "p93"' "$J"
# 000 §9 recomputed from the reported P per view: floor(0.1 n) views may be
# above 0.2, the statistic is the (floor(0.1 n) + 1)-th largest P
criterion_as_used='(.p_per_view | length) as $n | ((0.1 * $n + 1e-9) | floor) as $k
  | ([.p_per_view[] | select(. > 0.2)] | length) as $above
  | .views_above == $above and .pass == ($above <= $k) and .p_criterion == (.p_per_view | sort | reverse)[$k]'
check criterion_is_applied_as_000_s9_says jq -e ".result.rendered | ($criterion_as_used)
  and .criterion.allowed == (((0.1 * (.p_per_view | length)) + 1e-9) | floor)" "$J"
check block_compressed_variants_are_judged_the_same_way \
  jq -e "[.result.rendered.block_compressed[] | ($criterion_as_used)] | all" "$J"
check chosen_encoding_stores_less_than_the_original_maps \
  jq -e '.result.storage_bytes < .result.original_bytes' "$J"
check cheaper_candidates_tried_all_fail \
  jq -e '.result.storage_bytes as $s | .result.rendered.search.rendered >= 1
         and all(.result.rendered.search.tried[] | select(.storage_bytes < $s); .pass | not)' "$J"
check block_compressed_variants_list_p_per_view \
  jq -e '.result.rendered.block_compressed | [.pca_bc4, .pca_bc1, .plain_bc]
         | all(.[]; (.p_per_view | length) == 4 and .bytes > 0 and (.pass | type) == "boolean")' "$J"

# with a model and no rule, the rendered choice is the default
expect_exit 0 model_alone_runs "$JND" pca $R -o "$T/dm" --no-bc --quiet
check the_default_with_a_model_is_the_rendered_choice jq -e '.parameters.criterion == "rendered" and .result.rendered.pass' "$T/dm/pca.json"

# a fixed encoding is measured as it is
expect_exit 0 components_with_a_model_are_measured "$JND" pca $R -o "$T/k0" --components 0 --no-bc --quiet
check means_alone_are_visible jq -e '.result.rendered.pass == false and .result.rendered.views_above >= 1' "$T/k0/pca.json"

# deterministic on any thread count
D="--model builtin --map-size 64 --material builtin --views 2 --size 64x64 --anisotropy 1 --components 2 --no-bc --quiet"
OMP_NUM_THREADS=1 "$JND" pca $D -o "$T/d1"
OMP_NUM_THREADS=3 "$JND" pca $D -o "$T/d3"
check rendered_report_is_identical_across_thread_counts cmp -s "$T/d1/pca.json" "$T/d3/pca.json"

# map files replace the slots their names (or --slot) say
command -v python3 >/dev/null || skip "the rest needs python3"
PYTHONPATH="$(dirname "$0")" python3 - "$T" <<'PY'
import math, sys
from pngwrite import png
d = sys.argv[1]
def a(x, y): return 0.5 + 0.3 * math.sin(x * 0.3) * math.cos(y * 0.2)
png(f'{d}/mat_albedo.png', 64, 64, 3, lambda x, y: (a(x, y), 0.8 * a(x, y), 0.3))
png(f'{d}/mat_normal.png', 64, 64, 3, lambda x, y: (0.5 + 0.2 * math.sin(x * 0.3), 0.5, 1.0))
png(f'{d}/mat_height.png', 64, 64, 3, lambda x, y: (0.6 * a(x, y) + 0.2,) * 3)
PY
expect_exit 0 map_files_bound_by_name_and_slot "$JND" pca "$T/mat_albedo.png" "$T/mat_normal.png" "$T/mat_height.png" \
  $R --slot mat_height.png=occlusion -o "$T/files" --components 2 --no-bc --quiet
check slots_from_names_and_option \
  jq -e '.result.rendered.slots == {"albedo":"baseColor","normal":"normal","height":"occlusion"}
         and (.result.rendered.p_per_view | length) == 4' "$T/files/pca.json"

bad_input() { # bad_input NAME PATTERN ARGS...
  local name=$1 pat=$2; shift 2
  expect_exit 2 "$name" "$JND" pca "$@"
  check "${name}_says_so_in_one_line" bash -c "[ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -q '^jnd: .*$pat' '$T/err.txt'"
}
bad_input unknown_material_is_refused "no material .nope" --model builtin --map-size 16 --material nope -o "$T/x"
bad_input unguessable_map_name_is_refused "mat_height.png: no material slot" "$T/mat_height.png" $R -o "$T/x"
bad_input unknown_slot_is_refused ".roughness. is not a slot" "$T/mat_height.png" $R --slot mat_height.png=roughness -o "$T/x"
bad_input slot_without_a_model_is_refused "slot needs" "$T/mat_height.png" --slot mat_height.png=occlusion -o "$T/x"
finish
