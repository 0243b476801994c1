#!/usr/bin/env bash
# jnd render: frames per second at 1024x1024 and the time to load a real
# asset (a controller of @webxr-input-profiles/assets, MIT), on whatever
# OpenGL the machine has (llvmpipe on the CPU when there is no GPU).
set -uo pipefail
: "${JND:?}"
here=$(cd "$(dirname "$0")" && pwd)
. "$here/webxr_assets.sh"
out=${BENCH_OUT:-$here/out}/render
mkdir -p "$out"
ASSETS=$(webxr_assets_fetch && webxr_assets) || { echo "   skipped: @webxr-input-profiles/assets not available (npm/network)"; exit 0; }
MODEL=${BENCH_RENDER_MODEL:-$ASSETS/dist/profiles/oculus-touch/left.glb}
VIEWS=${BENCH_RENDER_VIEWS:-8}
for aniso in 8 1; do
  "$JND" render "$MODEL" -o "$out/a$aniso" --views "$VIEWS" --size 1024x1024 --anisotropy "$aniso" \
      --timings --quiet --json "$out/report_a$aniso.json" || exit 1
  python3 - "$out/report_a$aniso.json" "$MODEL" "$aniso" <<'PY'
import json, os, sys
r = json.load(open(sys.argv[1]))
t = r["result"]["timings"]
print("   %s (%d triangles, %d maps) on %s" % (os.path.relpath(sys.argv[2], os.path.dirname(sys.argv[2]) + "/../.."),
      r["result"]["triangles"], len(r["maps"]), r["result"]["renderer"]))
print("   1024x1024, 4x MSAA, anisotropy %s: %.2f frames/s over %d views; load %.2f s, renderer setup %.2f s"
      % (sys.argv[3], t["fps"], r["parameters"]["views"], t["load_s"], t["renderer_s"]))
PY
done
