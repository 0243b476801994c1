#!/usr/bin/env bash
# jnd gaze: 002's table L(d, ecc) on a shared mesh with a chain from
# `jnd lod` (the teapot, 4 levels: error targets 1/1024, 1/256, 1/64):
# 8 distances × 8 eccentricities × 8 orientations × 4 levels — the target is
# 120 s on 2 cores. Prints the wall and CPU times and the load average.
set -uo pipefail
: "${JND:?}"
here=$(cd "$(dirname "$0")" && pwd)
out=${BENCH_OUT:-$here/out}/gaze
data=${JND_SHARED:-$here/../../shared}/data/meshes
mkdir -p "$out"
if [ ! -f "$data/teapot.obj" ]; then
  echo "   skipped: the shared meshes are not at $data"
  exit 0
fi
"$JND" lod "$data/teapot.obj" -o "$out/lod" --errors 0.0009765625,0.00390625,0.015625 --chain-only --quiet || exit 1
load=$(cut -d' ' -f1-3 /proc/loadavg)
t=$( { /usr/bin/time -f "%e %U %S" "$JND" gaze "$out/lod/model/teapot.glb" -o "$out/table" --orientations 8 \
       --timings --quiet; } 2>&1 | tail -1) || exit 1
python3 - "$out/table/gaze.json" "$t" "$load" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))["result"]
wall, user, sys_ = sys.argv[2].split()
print("   teapot.obj, %d levels (%s triangles), %d distances x %d eccentricities x 8 orientations, %d renderings on %s"
      % (len(r["triangles"]), " ".join(str(int(t)) for t in r["triangles"]), len(r["distances_m"]),
         len(r["eccentricities_deg"]), r["renderings"], r["renderer"]))
print("     table: wall %s s (target 120 s on 2 cores), user %s s, sys %s s; load average before: %s"
      % (wall, user, sys_, sys.argv[3]))
PY
