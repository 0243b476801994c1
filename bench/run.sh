#!/usr/bin/env bash
# make bench: runs every bench/bench_*.sh in name order with the build folder
# as $1. Each prints its own figures; peers (butteraugli_main, ...) are timed in
# the same run so that ratios compare like with like.
set -uo pipefail
BUILD=${1:-build}
here=$(cd "$(dirname "$0")" && pwd)
export JND="$(cd "$BUILD" && pwd)/jnd"
export BENCH_OUT="${BENCH_OUT:-$here/out}"
mkdir -p "$BENCH_OUT"
: >"$BENCH_OUT/targets.tsv"   # bench/targets.sh: each script's targets, printed at the end
status=0
for b in "$here"/bench_*.sh; do
  [ -e "$b" ] || continue
  echo "== $(basename "$b" .sh)"
  bash "$b" || { echo "   (failed: $b)"; status=1; }
done
# the issues' targets from this run, in one table (bench/targets.sh)
if [ -s "$BENCH_OUT/targets.tsv" ]; then
  echo "== targets (this run; the load average when each was measured: wall times are idle cores' only near 0)"
  awk -F'\t' '{ printf "   %-62s %10s %-2s %6s %-8s %-7s load %s\n", $1, $2, $3, $4, $5, $6, $7;
                 if ($6 != "met") miss++ }
               END { printf "   %d of %d met\n", NR - miss, NR }' "$BENCH_OUT/targets.tsv"
fi
exit $status
