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
status=0
for b in "$here"/bench_*.sh; do
  [ -e "$b" ] || continue
  echo "== $(basename "$b" .sh)"
  bash "$b" || { echo "   (failed: $b)"; status=1; }
done
exit $status
