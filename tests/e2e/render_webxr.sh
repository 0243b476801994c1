#!/usr/bin/env bash
# jnd render on real assets: the MIT-licensed controller models of the npm
# package @webxr-input-profiles/assets, pinned and cached once by
# scripts/install-deps.sh (bench/webxr_assets.sh); the test only reads the
# cache and skips (exit 77) when it is missing.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
need_renderer
need_webxr_assets
command -v python3 >/dev/null || skip "needs python3"
for m in oculus-touch/left.glb generic-trigger/none.glb; do
  f="$ASSETS/dist/profiles/$m"
  [ -f "$f" ] || { bad "$m is in the package"; continue; }
  out="$T/$(echo "$m" | tr / _)"
  expect_exit 0 "$m renders" "$JND" render "$f" -o "$out" --views 2 --size 128x128 --outputs color,mask,mip --quiet
  check "$m fills a plausible part of the frame and lists its maps" python3 - "$out" <<'PY'
import json, sys
m = json.load(open(sys.argv[1] + "/views.json"))
cov = [v["coverage"] for v in m["views"]]
assert all(0.03 < c < 0.8 for c in cov), cov
assert len(m["maps"]) >= 1 and all(x["orig_width"] > 0 for x in m["maps"])
PY
done
finish
