#!/usr/bin/env bash
# jnd batch: 8 small assets (texres on the built-in asset, 2 views at 96x96,
# 128^2 maps, 8 view seeds) at 1 and at 2 concurrent workers (--jobs). With 1
# worker each asset's command gets
# every CPU as threads; with 2, the CPUs are shared out (OMP_NUM_THREADS =
# CPUs / 2, passive waits). Wall time of the whole batch, median of
# BENCH_RUNS (3), and the throughput per asset; each run starts from an empty
# output folder, so every asset is computed.
set -uo pipefail
: "${JND:?}"
here=$(cd "$(dirname "$0")" && pwd)
out=${BENCH_OUT:-$here/out}/batch
RUNS=${BENCH_RUNS:-3}
rm -rf "$out" && mkdir -p "$out"
{
  echo "id,asset,command,options"
  for s in 1 2 3 4 5 6 7 8; do
    echo "seed$s,builtin,texres,--views 2 --size 96x96 --map-size 128 --samples 1 --anisotropy 4 --no-matrix --seed $s"
  done
} >"$out/assets.csv"

run() { # run JOBS: the median wall time of RUNS batches
  local times=()
  for r in $(seq "$RUNS"); do
    rm -rf "$out/j$1"
    local t0=$EPOCHREALTIME
    "$JND" batch "$out/assets.csv" -o "$out/j$1" --jobs "$1" --quiet || return 1
    local t1=$EPOCHREALTIME
    times+=("$(awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.3f", b - a}')")
  done
  "$JND" batch merge "$out/j$1" --no-timings --quiet || return 1
  printf '%s\n' "${times[@]}" | sort -g | awk '{a[NR]=$1} END{print a[int((NR+1)/2)]}'
}
t1=$(run 1) || { echo "   batch failed"; exit 1; }
t2=$(run 2) || { echo "   batch failed"; exit 1; }
cmp -s "$out/j1/summary.json" "$out/j2/summary.json" && same=identical || same=DIFFERENT
awk -v a="$t1" -v b="$t2" -v n="$RUNS" -v c="$(nproc)" -v same="$same" 'BEGIN{
  printf "   jnd batch, 8 assets (texres builtin, 2 views at 96x96, 128^2 maps), %d CPUs, median of %d:\n", c, n
  printf "     1 worker : %6.2f s, %.2f s per asset, %.3f assets/s\n", a, a / 8, 8 / a
  printf "     2 workers: %6.2f s, %.2f s per asset, %.3f assets/s (x%.2f); summaries %s\n", b, b / 8, 8 / b, a / b, same }'
