#!/usr/bin/env bash
# jnd diff on a 1920x1080 pair: whole-process seconds, megapixels per second and
# peak memory in bytes per pixel, and the same for Debian's butteraugli_main
# (libjxl-devtools) on the same pair in the same run, with the ratio.
set -uo pipefail
: "${JND:?}"
here=$(cd "$(dirname "$0")" && pwd)
out=${BENCH_OUT:-$here/out}/diff
mkdir -p "$out"
RUNS=${BENCH_RUNS:-5}
W=1920 H=1080
"$JND" example -o "$out" --size ${W}x${H} 2>/dev/null || exit 1
px=$((W * H))

# median of RUNS wall times and the largest peak RSS, for a command
measure() {
  local times=() rss=0
  for _ in $(seq "$RUNS"); do
    # wall time in microseconds from bash's clock (time(1) rounds to 10 ms),
    # peak resident memory from time(1)
    local t0=$EPOCHREALTIME
    /usr/bin/time -f "%M" -o "$out/time.txt" "$@" >/dev/null 2>"$out/stderr.txt" || { cat "$out/stderr.txt"; return 1; }
    local t1=$EPOCHREALTIME
    t=$(awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.4f", b - a}')
    read -r m <"$out/time.txt"
    times+=("$t")
    [ "$m" -gt "$rss" ] && rss=$m
  done
  local med
  med=$(printf '%s\n' "${times[@]}" | sort -g | awk '{a[NR]=$1} END{print a[int((NR+1)/2)]}')
  echo "$med $rss"
}

read -r jt jm < <(measure "$JND" diff "$out/reference.png" "$out/test.png" --json "$out/diff.json" --quiet) || exit 1
awk -v t="$jt" -v m="$jm" -v px="$px" -v n="$RUNS" 'BEGIN{
  printf "   jnd diff         1920x1080: %.3f s (median of %d), %.2f Mpixel/s, peak %.1f MB = %.1f bytes/pixel\n",
         t, n, px / 1e6 / t, m / 1024, m * 1024 / px }'
if command -v butteraugli_main >/dev/null 2>&1; then
  read -r bt bm < <(measure butteraugli_main "$out/reference.png" "$out/test.png") || exit 1
  awk -v t="$bt" -v m="$bm" -v px="$px" -v n="$RUNS" 'BEGIN{
    printf "   butteraugli_main 1920x1080: %.3f s (median of %d), %.2f Mpixel/s, peak %.1f MB = %.1f bytes/pixel\n",
           t, n, px / 1e6 / t, m / 1024, m * 1024 / px }'
  awk -v a="$jt" -v b="$bt" -v ma="$jm" -v mb="$bm" 'BEGIN{
    printf "   ratio: jnd is %.1fx faster than butteraugli_main and uses %.2fx its peak memory\n", b / a, ma / mb }'
else
  echo "   butteraugli_main not installed (apt-get install libjxl-devtools) — no peer figures"
fi
