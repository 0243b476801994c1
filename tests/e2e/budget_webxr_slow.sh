#!/usr/bin/env bash
# jnd budget on a real asset (oculus-touch-v3 of the npm package
# @webxr-input-profiles/assets, MIT, pinned and cached by
# scripts/install-deps.sh), docs/budget.md step 7: texres + pca + lod chosen
# separately (510 437 B, level 2) reads 0.1004 on the judge's views, over
# texres's margin (0.1) that every joint candidate is held to, and is
# unnoticed at p on held-out views at every switch distance; the joint
# search's own choice costs 641 509 B. Budget takes the separate one: the
# choice is never dearer than the three commands' combination where that
# is unnoticed. About 80 s of CPU. Skips (exit 77) when the cache is missing.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
need_renderer
need_webxr_assets
command -v python3 >/dev/null || skip "needs python3"
M="$ASSETS/dist/profiles/oculus-touch-v3/left.glb"
[ -f "$M" ] || { bad "the asset is in the package"; finish; }
"$JND" budget "$M" -o "$T/a" --screens standard-fhd >"$T/out.txt" 2>"$T/err.txt"
rc=$?
check "budget on oculus-touch-v3 passes (exit 0; rc $rc)" test "$rc" -eq 0
check "the stage log says the separate choice was taken" grep -q "the separate choice .* taken" "$T/err.txt"
check "the summary names the choice as the separate one" grep -q "chosen: the separate one" "$T/err.txt"
check "budget.json: the separate candidate chosen, cheaper than the joint search's own, unnoticed at p, its chain written and verified" \
  env PYTHONPATH="$(dirname "$0")" python3 - "$T/a/budget.json" "$T/a/model/left.glb" <<'PY'
import json, struct, sys
r = json.load(open(sys.argv[1]))
res, p = r["result"], r["parameters"]["criterion"]["p"]
ch, se, cmp_ = res["chosen"], res["separate"], res["comparison"]
assert cmp_["separate_taken"] is True, cmp_
assert ch["index"] == se["index"] and ch["kind"] == "separate", (ch["index"], se["index"], ch["kind"])
joint = res["candidates"][cmp_["joint_index"]]
assert joint["kind"] != "separate" and joint["cost_bytes"] == cmp_["joint_cost_bytes"] > ch["cost_bytes"], joint
assert joint["passes_with_margin"] and not ch["passes_with_margin"], (joint, ch)
margin = r["parameters"]["margin"]
assert p * (1 - margin) < ch["statistic"] <= p and ch["pass"], (ch["statistic"], p, margin)
assert cmp_["chosen_cost_bytes"] == cmp_["separate_cost_bytes"] and cmp_["saving_bytes"] == 0, cmp_
assert res["passes"] is True
# the written chain is the separate one's, each level as its verification says
sv = se["verification"]
assert [L["level"] for L in res["levels"]] == [v["level"] for v in sv], (res["levels"], sv)
for L, v in zip(res["levels"], sv):
    assert L["verification"] == {k: v[k] for k in ("views", "statistic", "pass")}, (L, v)
    assert L["verification"]["pass"], L
assert res["levels"][0]["level"] == ch["level"]
# the GLB's finest level has the chosen level's triangles
data = open(sys.argv[2], "rb").read()
n = struct.unpack_from("<I", data, 12)[0]
g = json.loads(data[20:20 + n])
tri = sum(g["accessors"][pr["indices"]]["count"] // 3 for m in g["meshes"][:1] for pr in m["primitives"])
assert tri == ch["triangles"], (tri, ch["triangles"])
print("taken: %.0f B at level %d (statistic %.4f); the joint search's own %.0f B at level %d"
      % (ch["cost_bytes"], ch["level"], ch["statistic"], joint["cost_bytes"], joint["level"]))
PY
finish
