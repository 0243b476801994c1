#!/usr/bin/env bash
# jnd pop on a 1920x1080 pair with motion: whole-process wall seconds (median
# of BENCH_RUNS), user+sys CPU seconds, peak memory, and the steps' share
# (--timings of the last run). The pair is `jnd example`'s (four distortions,
# one per quadrant); the displacement is the renderer's motion output for the
# built-in asset orbiting 5 degrees a frame (float EXR, ZIP), or, without a
# renderer, a rotation field written by python3. Budget (issue 12): <= 0.5 s
# on 2 cores.
set -uo pipefail
: "${JND:?}"
here=$(cd "$(dirname "$0")" && pwd)
. "$here/targets.sh"
out=${BENCH_OUT:-$here/out}/pop
mkdir -p "$out"
RUNS=${BENCH_RUNS:-5}
W=1920 H=1080
"$JND" example -o "$out" --size ${W}x${H} 2>/dev/null || exit 1
disp=$out/motion.exr
if "$JND" render builtin -o "$out/r" --views 1 --size ${W}x${H} --outputs motion,exr --motion-orbit 5 --quiet 2>/dev/null; then
  cp "$out/r/view_000_motion.exr" "$disp"
  source="renderer motion, builtin asset orbiting 5 deg/frame"
elif command -v python3 >/dev/null; then
  PYTHONPATH="$here/../tests/e2e" python3 -B - "$disp" $W $H <<'PY' || exit 1
import sys
from exrwrite import exr
w, h, k = int(sys.argv[2]), int(sys.argv[3]), 0.02  # a rotation of 0.02 rad a frame about the centre
exr(sys.argv[1], w, h, {'X': lambda x, y: -(y - h / 2) * k, 'Y': lambda x, y: (x - w / 2) * k})
PY
  source="rotation field (python3), uncompressed EXR"
else
  echo "   no renderer and no python3: no displacement map to measure with"; exit 1
fi
px=$((W * H))
# timed N DIR COMMAND...: runs COMMAND N times, each into a fresh DIR (may be
# ""); fills times (wall s), cpu (user+sys s) and rss (peak KB)
timed() {
  local n=$1 dir=$2 t0 t1 u s m
  shift 2
  times=() cpu=() rss=0
  for _ in $(seq "$n"); do
    [ -n "$dir" ] && rm -rf "$dir"
    t0=$EPOCHREALTIME
    /usr/bin/time -f "%U %S %M" -o "$out/time.txt" "$@" >/dev/null 2>"$out/stderr.txt" || { cat "$out/stderr.txt"; exit 1; }
    t1=$EPOCHREALTIME
    read -r u s m <"$out/time.txt"
    times+=("$(awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.4f", b - a}')")
    cpu+=("$(awk -v u="$u" -v s="$s" 'BEGIN{printf "%.2f", u + s}')")
    [ "$m" -gt "$rss" ] && rss=$m
  done
}
timed "$RUNS" "$out/o" "$JND" pop "$out/test.png" "$out/reference.png" -o "$out/o" --displacement "$disp" --timings --quiet
med() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END{print a[int((NR+1)/2)]}'; }
wt=$(med "${times[@]}") ct=$(med "${cpu[@]}")
awk -v t="$wt" -v c="$ct" -v m="$rss" -v px="$px" -v n="$RUNS" -v src="$source" 'BEGIN{
  printf "   jnd pop 1920x1080 with motion (%s):\n", src
  printf "     %.3f s wall (median of %d), %.2f s user+sys, peak %.1f MiB = %.1f bytes/pixel; budget 0.5 s: %s\n",
         t, n, c, m / 1024, m * 1024 / px, t <= 0.5 ? "within" : "OVER" }'
jq -r '.result.timings | "     steps (last run): read \(.read_s*1000|floor) ms, weights+dE94 \(.weights_s*1000|floor) ms, model \(.model_s*1000|floor) ms, regions \(.regions_s*1000|floor) ms, picture \(.picture_s*1000|floor) ms, writing \(.write_s*1000|floor) ms"' "$out/o/pop.json"
jq -r '.result | "     \(.region_count) regions, max R \(.max_rating), detection score \(.detection_score)"' "$out/o/pop.json"

# the floor under the predictor: the vision model alone on the same pair with
# the same motion map (jnd diff --motion: reading, display, model, no regions,
# no picture); the budget cannot be met while this is over it
timed "$RUNS" "" "$JND" diff "$out/reference.png" "$out/test.png" --motion "$disp" --quiet
wt=$(med "${times[@]}") ct=$(med "${cpu[@]}")
awk -v t="$wt" -v c="$ct" -v n="$RUNS" 'BEGIN{
  printf "   the model alone (jnd diff --motion, same pair): %.3f s wall (median of %d), %.2f s user+sys\n", t, n, c }'

# the asset form: jnd renders the pair itself (four 1920x1080 renderings: both
# levels at the switch frame, both levels' depth one frame earlier) and runs
# the same predictor; the builtin asset, a chain of one level, orbiting 120 deg/s
timed "$(( RUNS < 3 ? RUNS : 3 ))" "$out/a" "$JND" pop builtin -o "$out/a" --size ${W}x${H} --views 1 \
  --map-size 512 --errors 0.02 --orbit 120 --timings --quiet
wt=$(med "${times[@]}") ct=$(med "${cpu[@]}")
renderer=$(jq -r .result.renderer "$out/a/pop.json")
awk -v t="$wt" -v c="$ct" -v n="${#times[@]}" -v r="$renderer" 'BEGIN{
  printf "   jnd pop MODEL 1920x1080, orbit 120 deg/s (renders the pair; %s):\n", r
  printf "     %.3f s wall (median of %d), %.2f s user+sys\n", t, n, c }'
jq -r '.result.timings | "     steps (last run): load \(.load_s*1000|floor) ms, render+predict \(.render_s*1000|floor) ms (model \(.model_s*1000|floor) ms), writing \(.write_s*1000|floor) ms"' "$out/a/pop.json"

# the switch table (issue 29 item 3): `jnd pop MODEL --decide` with the
# defaults (8 views at 512 x 512, the chain of nine error targets, speeds
# 0, 30 and 120 deg/s: 27 searches) on a 100 K-triangle mesh, the teapot of
# the shared data with every triangle split in 4 twice (101 K triangles).
# Target: 120 s on 2 cores. user+sys beside the wall time: on a shared
# machine the CPU time is the steadier (threads wait passively here, as
# bench_lod.sh's note says why).
data=${JND_SHARED:-$here/../../shared}/data/meshes
if [ -f "$data/teapot.obj" ]; then
  [ -s "$out/teapot_100k.obj" ] || python3 "$here/subdivide_obj.py" "$data/teapot.obj" "$out/teapot_100k.obj" 2
  OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive} timed 1 "$out/d" "$JND" pop "$out/teapot_100k.obj" -o "$out/d" --decide --timings --quiet
  awk -v t="${times[0]}" -v c="${cpu[0]}" 'BEGIN{
    printf "   jnd pop teapot_100k.obj --decide (defaults: 27 searches): %.1f s wall, %.1f s user+sys; target 120 s: %s\n",
           t, c, (t <= 120 ? "within" : "OVER") " (wall), " (c <= 120 ? "within" : "OVER") " (CPU)" }'
  target "pop --decide, 100 K-triangle teapot, defaults: wall (issue 29)" "${times[0]}" "<=" 120 "s"
  jq -r '"     \(.result.switch | map(.evaluations) | add) evaluations over \(.result.switch | length) searches; decide \(.result.timings.decide_s | floor) s"' "$out/d/pop.json"
else
  echo "   pop --decide on 100 K triangles: skipped, the shared meshes are not at $data"
fi
