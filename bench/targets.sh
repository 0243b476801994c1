# Sourced by the bench scripts: `target NAME VALUE OP LIMIT UNIT` records one
# of the issues' targets measured in this run (OP: <= or >=) in
# $BENCH_OUT/targets.tsv, which bench/run.sh prints as one table at the end,
# so that `make bench` says from one run where each target stands. The load
# average is recorded beside it: a wall time on a loaded machine is not the
# time on idle cores.
target() {
  local name=$1 value=$2 op=$3 limit=$4 unit=$5 verdict
  verdict=$(awk -v v="$value" -v o="$op" -v l="$limit" 'BEGIN{
    ok = (o == "<=") ? (v <= l) : (v >= l); print ok ? "met" : "NOT met" }')
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$value" "$op" "$limit" "$unit" "$verdict" \
    "$(cut -d' ' -f1 /proc/loadavg)" >>"${BENCH_OUT:-$(dirname "${BASH_SOURCE[0]}")/out}/targets.tsv"
}
