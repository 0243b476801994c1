#!/usr/bin/env bash
# jnd pca on the DamagedHelmet set (5 JPEG maps, 2048²): 13 informative
# channels, energies summing to the total variance, ≥ 60 dB with every
# component in float, 001's 5-component table, and albedo weighting.
. "$(dirname "$0")/lib.bash"
shared_data && [ -d "$JND_SHARED/data/texsets/damagedhelmet" ] || skip "no shared data"
H="$JND_SHARED/data/texsets/damagedhelmet"
MAPS="$H/Default_AO.jpg $H/Default_albedo.jpg $H/Default_emissive.jpg $H/Default_metalRoughness.jpg $H/Default_normal.jpg"

expect_exit 0 all_components_run "$JND" pca $MAPS -o "$T/all" --components all --no-bc --quiet
check helmet_has_13_informative_channels jq -e '.result.channel_count == 13 and .result.channels[0].name == "AO"' "$T/all/pca.json"
check energies_sum_to_total_variance \
  jq -e '((.result.energy | add) - .result.total_variance | fabs) <= 1e-9 * .result.total_variance' "$T/all/pca.json"
check all_components_reconstruct_at_60_db_in_float jq -e 'all(.result.channels[]; .psnr_float_db >= 60)' "$T/all/pca.json"

expect_exit 0 five_components_run "$JND" pca $MAPS -o "$T/k5" --components 5 --quiet
check five_components_give_a_c_by_6_matrix \
  jq -e '.result.components_kept == 5 and (.result.reconstruction | length) == 13 and (.result.reconstruction[0] | length) == 6' "$T/k5/pca.json"
jq -r '"5 components: " + ([.result.channels[] | "\(.name)=\(.psnr_db * 10 | round / 10)"] | join(" "))' "$T/k5/pca.json"
check block_compression_is_compared jq -e '.result.block_compression.pca_bc4_bytes > 0 and .result.block_compression.plain_bc_bytes > 0' "$T/k5/pca.json"

expect_exit 0 weighted_run "$JND" pca $MAPS -o "$T/k5w" --components 5 --weight albedo=2 --no-bc --quiet
albedo='[.result.channels[] | select(.name | startswith("albedo")) | .psnr_float_db] | add'
check weighting_albedo_raises_its_psnr \
  jq -e --slurpfile u "$T/k5/pca.json" "($albedo) > (\$u[0] | $albedo)" "$T/k5w/pca.json"
check weighting_albedo_lowers_another_channel \
  jq -e --slurpfile u "$T/k5/pca.json" '[range(0; 13) as $i | select((.result.channels[$i].name | startswith("albedo") | not)
         and .result.channels[$i].psnr_float_db < $u[0].result.channels[$i].psnr_float_db)] | length > 0' "$T/k5w/pca.json"
finish
