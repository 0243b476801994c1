#!/usr/bin/env bash
# jnd csf end to end on a small hand-made castleCSF-format data set (no shared data needed).
. "$(dirname "$0")/lib.bash"

cat >"$T/color_directions.csv" <<'CSV'
col_dir_id,L_delta,M_delta,S_delta,dataset
1,0.918203011274591,0.395254682570263,0.0260185701481506,mine
3,0.762860488743917,-0.646494144848117,-0.00944433112997181,mine
CSV
cat >"$T/backgrounds.csv" <<'CSV'
bkg_id,L,M,S,bkg_label,dataset
1,36.7372648518233,15.8141236515338,1.04100192534928,D65,mine
CSV
cat >"$T/data.csv" <<'CSV'
luminance,s_frequency,col_dir_id,bkg_id,ge_sigma,area,N,log_cone_contrast,dataset,t_frequency,orientation,eccentricity,vis_field,stimulus,sensitivity
50,2,1,1,0.5,0.785,1,-2.3,achromatic,0,0,0,180,gabor,200
50,8,1,1,0.5,0.785,1,-2.0,achromatic,0,0,0,180,gabor,100
50,1,3,1,0.5,0.785,1,-2.5,chromatic,0,0,0,180,gabor,300
20,4,1,1,1,4,1,-1.8,moving,8,0,0,180,grating,60
20,4,1,1,1,4,1,-1.5,peripheral,0,0,10,180,grating,30
50,16,1,1,0.5,0.785,1,-1.5,achromatic,0,0,0,180,gabor,30
20,4,1,1,1,4,1,-1.9,foveal,0,0,0,180,grating,80
CSV
expect_exit 0 help_exits_zero "$JND" csf --help
expect_exit 0 csf_runs_on_a_small_set "$JND" csf "$T/data.csv" -o "$T/pred.csv" --json "$T/csf.json" --quiet
check output_has_every_input_column_plus_the_prediction bash -c "head -1 '$T/pred.csv' | grep -q '^luminance,s_frequency,.*,sensitivity,predicted_sensitivity'"
check output_has_a_row_per_input test "$(wc -l <"$T/pred.csv")" -eq 8
check every_row_is_predicted bash -c "! grep -q NaN,NaN '$T/pred.csv'"
check report_has_pooled_rmse jq -e '.result.rmse_db_static > 0 and .result.rows == 7' "$T/csf.json"
check a_16_cpd_gabor_is_less_visible_than_a_2_cpd_one bash -c "awk -F, 'NR==2{a=\$16} NR==7{b=\$16} END{exit !(a>b)}' '$T/pred.csv'"
check the_periphery_is_less_visible_than_the_fovea bash -c "awk -F, 'NR==8{f=\$16} NR==6{p=\$16} END{exit !(p>0 && p<f)}' '$T/pred.csv'"
# the report's errors recomputed from the predictions file: a row's error is 20·log10(predicted /
# measured) dB; rmse_db is their RMS (pooled and per data set), rmse_db_static over rows with
# t_frequency 0 only, bias_db their mean (the file holds 6 digits: 1e-3 dB)
rms_db() { awk -F, -v ds="$2" -v only_static="$3" -v what="${4:-}" 'NR==1{for(i=1;i<=NF;i++) c[$i]=i; next}
  (ds=="" || $c["dataset"]==ds) && (!only_static || $c["t_frequency"]<=0) {
    e=20*log(($c["predicted_sensitivity"])/($c["sensitivity"]))/log(10); s+=e*e; m+=e; n++ }
  END{ if (what=="bias") printf "%.9f", m/n; else printf "%.9f", sqrt(s/n) }' "$1"; }
check the_reported_rmse_is_the_rms_of_the_rows_errors_in_db jq -e \
  --argjson a "$(rms_db "$T/pred.csv" "" 0)" --argjson s "$(rms_db "$T/pred.csv" "" 1)" \
  --argjson d "$(rms_db "$T/pred.csv" achromatic 0)" --argjson b "$(rms_db "$T/pred.csv" achromatic 0 bias)" \
  '((.result.rmse_db - $a) | fabs) < 1e-3 and ((.result.rmse_db_static - $s) | fabs) < 1e-3 and ($s != $a)
   and ((.result.datasets.achromatic.rmse_db - $d) | fabs) < 1e-3 and ((.result.datasets.achromatic.bias_db - $b) | fabs) < 1e-3
   and .result.static_rows == 6' "$T/csf.json"

# constants: listed, set, fitted, cross-validated
expect_exit 0 constants_are_listed "$JND" csf --list-constants
check the_list_names_the_priors grep -q "^sensitivity .*004" "$T/out.txt"
check the_list_says_which_constants_are_held grep -q "^chroma_sat_td .* held  " "$T/out.txt"
"$JND" csf "$T/data.csv" --set sensitivity=0.1 --json "$T/low.json" --quiet
check set_changes_a_constant jq -e --slurpfile a "$T/csf.json" '.parameters.constants.sensitivity.value == 0.1 and .result.datasets.achromatic.rmse_db != $a[0].result.datasets.achromatic.rmse_db' "$T/low.json"
expect_exit 0 a_fit_runs "$JND" csf "$T/data.csv" --set sensitivity=0.1 --fit --fit-only sensitivity --json "$T/fit.json" --quiet
check the_fit_moves_the_constant_back_and_lowers_the_error jq -e --slurpfile l "$T/low.json" '.parameters.constants.sensitivity.value > 0.2 and .parameters.constants.sensitivity.fitted and .parameters.constants.sensitivity.sd_ln > 0 and .result.rmse_db < $l[0].result.rmse_db' "$T/fit.json"
# a constant held at its prior is fitted only when --fit-only names it
expect_exit 0 a_fit_of_every_constant_runs "$JND" csf "$T/data.csv" --fit --iterations 0 --json "$T/all.json" --quiet
check held_constants_are_not_fitted jq -e '.parameters.constants.chroma_sat_td.fitted == false and .parameters.constants.chroma_sat_td.value == 100 and .parameters.constants.sensitivity.fitted and .parameters.constants.ecc_freq.fitted' "$T/all.json"
"$JND" csf "$T/data.csv" --fit --iterations 0 --fit-only chroma_sat_td --json "$T/held.json" --quiet
check a_held_constant_is_fitted_when_named jq -e '.parameters.constants.chroma_sat_td.fitted and (.parameters.constants.sensitivity.fitted | not)' "$T/held.json"
expect_exit 0 cross_validation_runs "$JND" csf "$T/data.csv" --cross-validate --fit-only sensitivity,sens_rg -o "$T/cv.csv" --json "$T/cv.json" --quiet
check every_data_set_is_predicted_by_the_others jq -e '[.result.datasets[] | select(.cv_rmse_db > 0)] | length == 5' "$T/cv.json"
check cv_columns_are_written bash -c "head -1 '$T/cv.csv' | grep -q 'predicted_cv,error_cv_db,note'"
# each data set's bias is the mean of its rows' errors (training and cross-validated), not their RMS
mean_err() { awk -F, -v ds="$2" -v col="$3" 'NR==1{for(i=1;i<=NF;i++) if($i==col) c=i; next} $9==ds{s+=$c; n++} END{printf "%.6f", s/n}' "$1"; }
check the_bias_is_the_mean_error_of_each_data_set jq -e \
  --argjson t "$(mean_err "$T/cv.csv" achromatic error_db)" --argjson v "$(mean_err "$T/cv.csv" achromatic error_cv_db)" \
  '.result.datasets.achromatic | ((.bias_db - $t) | fabs) < 1e-3 and ((.cv_bias_db - $v) | fabs) < 1e-3 and (.cv_bias_db | fabs) <= .cv_rmse_db' "$T/cv.json"
check each_fold_reports_its_constants jq -e '.parameters.constants.sensitivity.without | length == 5' "$T/cv.json"
"$JND" csf "$T/data.csv" --cross-validate --fit-only sensitivity,sens_rg --threads 1 --json "$T/cv1.json" --quiet
check cross_validation_does_not_depend_on_the_thread_count cmp -s "$T/cv.json" "$T/cv1.json"
# the folds are honest: a held-out set's own thresholds never reach its
# prediction (the achromatic set's measured sensitivities ×4: its cross-
# validated predictions stay to the last digit, its training fit moves) ...
awk -F, 'BEGIN{OFS=","} NR>1 && $9=="achromatic"{$15*=4} 1' "$T/data.csv" >"$T/data4.csv"
"$JND" csf "$T/data4.csv" --colors "$T/color_directions.csv" --backgrounds "$T/backgrounds.csv" \
  --cross-validate --fit-only sensitivity,sens_rg -o "$T/cv4.csv" --quiet
pred_of() { awk -F, -v ds="$2" -v col="$3" 'NR==1{for(i=1;i<=NF;i++) if($i==col) c=i; next} ds=="" || $9==ds{print $c}' "$1"; }
check a_held_out_sets_thresholds_do_not_reach_its_prediction \
  test "$(pred_of "$T/cv.csv" achromatic predicted_cv)" = "$(pred_of "$T/cv4.csv" achromatic predicted_cv)"
"$JND" csf "$T/data4.csv" --colors "$T/color_directions.csv" --backgrounds "$T/backgrounds.csv" \
  --fit --fit-only sensitivity,sens_rg -o "$T/fit4.csv" --quiet
"$JND" csf "$T/data.csv" --fit --fit-only sensitivity,sens_rg -o "$T/fit1.csv" --quiet
check while_the_training_fit_follows_them \
  test "$(pred_of "$T/fit1.csv" achromatic predicted_sensitivity)" != "$(pred_of "$T/fit4.csv" achromatic predicted_sensitivity)"
# ... and every fold starts from the priors, not from the constants given
# (the defaults were fitted on all the data): --set of a fitted constant
# leaves every fold as it was
"$JND" csf "$T/data.csv" --cross-validate --fit-only sensitivity,sens_rg --set sensitivity=0.05 --set sens_rg=5000 -o "$T/cvset.csv" --quiet
check the_folds_start_from_the_priors_not_the_defaults \
  test "$(pred_of "$T/cv.csv" "" predicted_cv)" = "$(pred_of "$T/cvset.csv" "" predicted_cv)"
# --fold: only the named folds, each the same fold as in the full run; the
# pooled figure says which sets it covers
"$JND" csf "$T/data.csv" --cross-validate --fit-only sensitivity,sens_rg --fold achromatic --fold moving \
  -o "$T/cvfold.csv" --json "$T/cvfold.json" --quiet
check a_fold_named_is_the_fold_of_the_full_run \
  test "$(pred_of "$T/cv.csv" achromatic predicted_cv; pred_of "$T/cv.csv" moving predicted_cv)" = \
  "$(pred_of "$T/cvfold.csv" achromatic predicted_cv; pred_of "$T/cvfold.csv" moving predicted_cv)"
check the_other_folds_are_not_computed test "$(pred_of "$T/cvfold.csv" chromatic predicted_cv)" = NaN
check the_report_says_which_sets_the_cross_validation_pools jq -e \
  '.result.cv_pooled_over == ["achromatic", "moving"] and .result.cv_every_fold == false and (.result.datasets.chromatic | has("cv_rmse_db") | not) and (.parameters.constants.sensitivity.without | keys) == ["achromatic", "moving"]' "$T/cvfold.json"
check a_full_run_pools_every_set jq -e '(.result.cv_pooled_over | length) == 5 and .result.cv_every_fold' "$T/cv.json"
# each search row stands for the search_every rows it was picked from: with
# every row given twice, a fit on every 2nd row is the fit on every row, and
# --prior-weight weighs the priors against every row (the single rows with
# weight 4 are the doubled rows' objective with the default 4·√2, halved)
awk 'NR == 1 {print; next} {print; print}' "$T/data.csv" >"$T/data2.csv"
fit_on() { "$JND" csf "$1" --colors "$T/color_directions.csv" --backgrounds "$T/backgrounds.csv" \
  --fit --fit-only sensitivity,sens_rg --set sensitivity=0.3 --json "$2" --quiet "${@:3}"; }
fit_on "$T/data2.csv" "$T/dup1.json" --search-every 1
fit_on "$T/data2.csv" "$T/dup2.json" --search-every 2
fit_on "$T/data.csv" "$T/one.json" --search-every 1
fit_on "$T/data.csv" "$T/one4.json" --search-every 1 --prior-weight 4
# the same objective, fitted to about 1e-4 (LM's stopping rule), while the
# priors' weight ×√2 moves sens_rg by 4%
same_fit() { jq -e -n --slurpfile a "$1" --slurpfile b "$2" \
  '[$a[0], $b[0]] | map(.parameters.constants) | (.[0].sensitivity.value / .[1].sensitivity.value - 1 | fabs) < 5e-3
   and (.[0].sens_rg.value / .[1].sens_rg.value - 1 | fabs) < 5e-3'; }
check a_search_row_stands_for_the_rows_it_was_picked_from same_fit "$T/dup1.json" "$T/dup2.json"
check the_prior_weight_is_against_every_row same_fit "$T/one4.json" "$T/dup1.json"
check the_prior_weight_matters bash -c "$(declare -f same_fit); ! same_fit '$T/one.json' '$T/one4.json'"
expect_exit 2 a_fold_of_no_data_set_exits_two "$JND" csf "$T/data.csv" --cross-validate --fold nonsense
check a_fold_of_no_data_set_is_named grep -q "fold 'nonsense'" "$T/err.txt"
check a_fold_of_no_data_set_error_is_one_line one_line_error
expect_exit 2 a_fold_without_cross_validation_exits_two "$JND" csf "$T/data.csv" --fold achromatic
expect_exit 2 unknown_constant_exits_two "$JND" csf "$T/data.csv" --set nonsense=1
check unknown_constant_error_is_one_line one_line_error
expect_exit 2 constant_out_of_bounds_exits_two "$JND" csf "$T/data.csv" --set sensitivity=-1
expect_exit 2 unknown_constant_to_fit_exits_two "$JND" csf "$T/data.csv" --fit --fit-only chroma_sat_td,nonsense
check unknown_constant_to_fit_is_named grep -q "no constant 'nonsense'" "$T/err.txt"
check unknown_constant_to_fit_error_is_one_line one_line_error

# bad input
printf 'luminance,s_frequency\n1,2\n' >"$T/bad.csv"
expect_exit 2 missing_columns_exit_two "$JND" csf "$T/bad.csv" --colors "$T/color_directions.csv" --backgrounds "$T/backgrounds.csv"
check missing_column_is_named grep -q "missing column" "$T/err.txt"
check missing_column_error_is_one_line one_line_error
expect_exit 2 missing_file_exits_two "$JND" csf "$T/none.csv"
sed 's/^50,2,1,1/50,2,9,1/' "$T/data.csv" >"$T/badcol.csv"
expect_exit 2 unknown_colour_direction_exits_two "$JND" csf "$T/badcol.csv" --colors "$T/color_directions.csv" --backgrounds "$T/backgrounds.csv"
sed 's/^50,2,1,1,0.5/50,x,1,1,0.5/' "$T/data.csv" >"$T/badnum.csv"
expect_exit 2 non_numeric_cell_exits_two "$JND" csf "$T/badnum.csv" --colors "$T/color_directions.csv" --backgrounds "$T/backgrounds.csv"
check non_numeric_cell_error_names_the_line grep -q "line 2" "$T/err.txt"
finish
