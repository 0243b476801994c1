#!/usr/bin/env bash
# jnd texres on a real asset (a controller of the npm package
# @webxr-input-profiles/assets, MIT, pinned and cached by
# scripts/install-deps.sh): sizes within the mip bound, the base colour x
# normal matrix, memory, the held-out check, and the model copy. Skips (exit 77)
# when the cache is missing.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
need_renderer
need_webxr_assets
M="$ASSETS/dist/profiles/generic-trigger-squeeze-thumbstick/left.glb"
command -v python3 >/dev/null || skip "needs python3"
[ -f "$M" ] || { bad "the asset is in the package"; finish; }
"$JND" texres "$M" -o "$T/a" --views 4 --size 256x256 --verify-views 8 --matrix --quiet
rc=$?
check "texres runs on a webxr controller (exit 0, or 1 with the failure reported)" [ $rc -le 1 ]
check "the report: sizes within the mip bound, the matrix, memory, the held-out check" python3 - "$T/a/texres.json" "$rc" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))["result"]
slots = {m["slot"] for m in r["maps"]}
assert {"baseColor", "normal"} <= slots, slots
for m in r["maps"]:
    assert max(m["chosen"]) <= max(m["mip_bound"]), m
mx = r["matrices"][0]
assert len(mx["stat"]) == len(mx["row_sizes"]) >= 2 and len(mx["stat"][0]) == len(mx["column_sizes"]) >= 2
assert 0 < r["memory"]["after_bytes"] <= r["memory"]["before_bytes"]
v = r["verify"]
assert v["views"] == 8 and 0 <= v["fraction_above"] <= 1
assert (int(sys.argv[2]) == 0) == (r["views"]["passes"] and v["passes"])
PY
check "the copy of the model loads with the chosen sizes" python3 - "$T/a" "$JND" <<'PY'
import json, subprocess, sys
out, jnd = sys.argv[1:3]
r = json.load(open(out + "/texres.json"))["result"]
lst = subprocess.run([jnd, "render", r["model"], "--list-maps"], capture_output=True, text=True, check=True).stdout
for m in r["maps"]:
    line = [l for l in lst.splitlines() if l.startswith(m["name"] + " ")][0]
    assert ("%d x %d" % tuple(m["chosen"])) in " ".join(line.split()).replace(" x ", " x "), (line, m["chosen"])
PY
finish
