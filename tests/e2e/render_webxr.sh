#!/usr/bin/env bash
# jnd render on real assets: the MIT-licensed controller models of the npm
# package @webxr-input-profiles/assets, fetched once into the build folder's
# cache (never committed). Skips cleanly when npm or the network is missing.
set -uo pipefail
: "${JND:?}" "${JND_TMP:?}"
T=$JND_TMP
rm -rf "$T" && mkdir -p "$T"
. "$(dirname "$0")/../../bench/webxr_assets.sh"
ASSETS=$(webxr_assets "$(dirname "$JND")/webxr-cache") || skip "@webxr-input-profiles/assets not available (no npm or no network)"
fail=0
check() { if ! eval "$1"; then echo "FAIL: $2"; fail=1; else echo "ok   $2"; fi; }
for m in oculus-touch/left.glb generic-trigger/none.glb; do
  f="$ASSETS/dist/profiles/$m"
  [ -f "$f" ] || { echo "FAIL: $m is not in the package"; fail=1; continue; }
  out="$T/$(echo "$m" | tr / _)"
  "$JND" render "$f" -o "$out" --views 2 --size 128x128 --outputs color,mask,mip --quiet
  check '[ $? -eq 0 ]' "$m renders"
  check 'python3 - "$out" <<"PY"
import json, sys
m = json.load(open(sys.argv[1] + "/views.json"))
cov = [v["coverage"] for v in m["views"]]
assert all(0.03 < c < 0.8 for c in cov), cov
assert len(m["maps"]) >= 1 and all(x["orig_width"] > 0 for x in m["maps"])
PY' "$m fills a plausible part of the frame and lists its maps"
done
exit $fail
