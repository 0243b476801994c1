#!/usr/bin/env bash
# jnd diff on a 1920x1080 pair: whole-process seconds, megapixels per second and
# peak memory in bytes per pixel, and the same for Debian's butteraugli_main
# (libjxl-devtools) and NVIDIA FLIP's C++ tool on the same pair in the same
# run, with the ratios. FLIP is built from ../shared/anchors/flip (its README's
# build line) into the build folder's bench/ when that folder is there; it is
# never copied into the repository.
set -uo pipefail
: "${JND:?}"
here=$(cd "$(dirname "$0")" && pwd)
. "$here/targets.sh"
out=${BENCH_OUT:-$here/out}/diff
mkdir -p "$out" && out=$(cd "$out" && pwd)
RUNS=${BENCH_RUNS:-5}
W=1920 H=1080
"$JND" example -o "$out" --size ${W}x${H} 2>/dev/null || exit 1
px=$((W * H))

# median of RUNS wall times and the largest peak RSS, for a command. Each
# tool's runs follow one another, each on cores the previous run of the same
# tool has just left: run in turn with the peers instead (jnd, FLIP,
# butteraugli, jnd, …), jnd's runs right after butteraugli's took 10–25 %
# longer and its ratios fell by about a tenth (docs/speed.md "Ninth pass")
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
  printf "   jnd diff         1920x1080: %.3f s (median of %d), %.2f Mpixel/s, peak %.1f MiB = %.1f bytes/pixel\n",
         t, n, px / 1e6 / t, m / 1024, m * 1024 / px }'
target "diff 1080p: jnd's peak memory (issue 29)" "$(awk -v m="$jm" -v px="$px" 'BEGIN{printf "%.1f", m * 1024 / px}')" "<=" 64 "B/pixel"
peer() { # peer NAME SECONDS PEAK_KIB
  awk -v name="$1" -v t="$2" -v m="$3" -v px="$px" -v n="$RUNS" 'BEGIN{
    printf "   %-16s 1920x1080: %.3f s (median of %d), %.2f Mpixel/s, peak %.1f MiB = %.1f bytes/pixel\n",
           name, t, n, px / 1e6 / t, m / 1024, m * 1024 / px }'
  awk -v name="$1" -v a="$jt" -v b="$2" -v ma="$jm" -v mb="$3" 'BEGIN{
    printf "   ratio: jnd is %.1fx faster than %s (target 10x) and uses %.2fx its peak memory\n", b / a, name, ma / mb }'
  target "diff 1080p: jnd's speed over $1's (issue 29)" "$(awk -v a="$jt" -v b="$2" 'BEGIN{printf "%.2f", b / a}')" ">=" 10 "x"
}
flip_src=${JND_SHARED:-$here/../../shared}/anchors/flip
flip_bin=$(cd "$(dirname "$JND")" && pwd)/bench/flip
if [ -f "$flip_src/tool/FLIP-tool.cpp" ]; then
  if [ ! -x "$flip_bin" ] || [ "$flip_src/tool/FLIP-tool.cpp" -nt "$flip_bin" ]; then
    mkdir -p "$(dirname "$flip_bin")"
    echo "   building FLIP's C++ tool from $flip_src (about a minute)"
    command -v g++ >/dev/null || { echo "   g++ missing (apt-get install g++)"; exit 1; }
    g++ -O3 -march=native -fopenmp -std=c++17 -I"$flip_src" "$flip_src/tool/FLIP-tool.cpp" -o "$flip_bin" ||
      { echo "   FLIP did not build"; exit 1; }
  fi
  # FLIP writes its outputs into the working folder; -nexm -nerm: no error maps
  read -r ft fm < <(cd "$out" && measure "$flip_bin" --reference reference.png --test test.png -nexm -nerm -v 1) || exit 1
  peer "FLIP (C++ tool)" "$ft" "$fm"
else
  echo "   FLIP's source not found at $flip_src (../shared/anchors/flip) — no FLIP figures"
fi
if command -v butteraugli_main >/dev/null 2>&1; then
  read -r bt bm < <(measure butteraugli_main "$out/reference.png" "$out/test.png") || exit 1
  peer butteraugli_main "$bt" "$bm"
else
  echo "   butteraugli_main not installed (apt-get install libjxl-devtools) — no peer figures"
fi
