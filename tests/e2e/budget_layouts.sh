#!/usr/bin/env bash
# jnd budget, pca's layouts in the joint search (src/tasks/budget.c
# search_layouts): after the fewest full-size components that pass, the
# layouts of `jnd pca`'s family by PSNR floor (K, each component's scale)
# that take fewer bytes are searched by bisection, the cheapest that passes
# with texres's margin taken. A ball whose three images (six channels the
# shader reads) are affine in two patterns with orthogonal loadings: a fine
# one of large variance (the first component, which no halving keeps) and a
# smooth one of 4 periods (the second). One component is seen; two at full
# size pass; `jnd pca`'s own choice, the second at a quarter of the side,
# passes at p on its views but not texres's margin on budget's (oculus-touch-v3's
# situation, docs/budget.md), so the separate choice fails the margin; the
# layout with the second component at half the side passes and is the joint
# search's own choice: 3 440 B against two full-size components' 5 488 B.
# pca's own layout is unnoticed at p on the judge's views (0.139) and on its
# held-out views, and cheaper: step 7 (docs/budget.md) takes it instead, so
# the written choice is the separate one, the joint search's own beside it.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
need_renderer
command -v python3 >/dev/null || skip "needs python3"

PYTHONPATH="$(dirname "$0")" python3 - "$T" 4 0.3 <<'PY'
import math, struct, sys
from gltfwrite import write_ball
from pngwrite import png
d, F, amp = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
N = 64
def A(x, y): return 0.45 * math.sin(1.9 * x + 0.7 * y) * math.cos(1.3 * y - 0.4 * x)
def B(x, y): return amp * math.sin(2 * math.pi * F * x / N) * math.cos(2 * math.pi * F * y / N)
# loadings over the six channels the shader reads (baseColor RGB, metallicRoughness G B, occlusion R), orthogonal
a = [0.5, 0.3, -0.3, 0.4, -0.4, 0.3]
b = [0.3, 0.4, 0.5, -0.3, 0.2, -0.3]
b0 = sum(x*y for x, y in zip(a, b)) / sum(x*x for x in a)
b = [y - b0 * x for x, y in zip(a, b)]
m = [0.5, 0.5, 0.5, 0.5, 0.5, 0.5]
def ch(x, y):
    va, vb = A(x, y), B(x, y)
    return [max(0.0, min(1.0, m[i] + a[i] * va + b[i] * vb)) for i in range(6)]
def img(name, sel):
    png(d + "/" + name + ".png", N, N, 3, lambda x, y: sel(ch(x, y)))
    return open(d + "/" + name + ".png", "rb").read()
images = [img("base", lambda c: (c[0], c[1], c[2])), img("mr", lambda c: (0, c[3], c[4])), img("occ", lambda c: (c[5],) * 3)]
write_ball(d + "/ball2.glb", images)
PY

SMALL=(--map-size 128 --size 96x96 --samples 1 --views 4 --confirm 0 --screens 640x480 --errors 0.03
       --judge-views 2 --max-px 128 --tolerance 0.5 --far-coverage 0.05 --verify-views 2)
"$JND" budget "$T/ball2.glb" -o "$T/b" "${SMALL[@]}" >"$T/out.txt" 2>"$T/err.txt"
rc=$?
check "cheapest unnoticed: the ball of two patterns passes (exit 0; rc $rc)" test "$rc" -eq 0
check "the joint search's own choice packs the ball in pca's layout with its second component at half the side, under two full-size components" \
  env PYTHONPATH="$(dirname "$0")" python3 - "$T/b/budget.json" <<'PY'
import json, sys
from gltfwrite import mip_chain_bytes as chain
r = json.load(open(sys.argv[1]))["result"]
j, se = r["comparison"]["joint"], r["separate"]
assert j["index"] == r["comparison"]["joint_index"] and j["cost_bytes"] == r["comparison"]["joint_cost_bytes"], j
assert j["kind"] == "encoded" and j["passes_with_margin"], j
assert all(wh == [64, 64] for wh in j["sizes"].values()), j["sizes"]
assert j["pca_layouts"] == {"ball": {"components": 2, "scale": [0, 1], "bits": [8, 8]}}, j["pca_layouts"]
assert j["memory_bytes"] == chain(64, 64, 8) + chain(32, 32, 8) < 2 * chain(64, 64, 8), j["memory_bytes"]
# pca's own, cheaper layout fails texres's margin: the joint search had to find its own
assert se["pca_layouts"]["ball"]["scale"] == [0, 2] and not se["passes_with_margin"], se
PY
# step 7: pca's own layout, unnoticed at p on the judge's and the held-out views, is taken
check "the stage log says the separate choice is taken" grep -q "the separate choice .* taken" "$T/err.txt"
check "the summary names the choice as the separate one" grep -q "chosen: the separate one" "$T/err.txt"
check "step 7: the separate candidate written, cheaper than the joint search's own, unnoticed at p, its chain verified" \
  python3 - "$T/b/budget.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
res, p, margin = r["result"], r["parameters"]["criterion"]["p"], r["parameters"]["margin"]
ch, se, cmp_ = res["chosen"], res["separate"], res["comparison"]
assert cmp_["separate_taken"] is True and ch["index"] == se["index"] and ch["kind"] == "separate", cmp_
assert ch["cost_bytes"] < cmp_["joint_cost_bytes"] and cmp_["saving_bytes"] == 0, cmp_
assert p * (1 - margin) < ch["statistic"] <= p and ch["pass"] and not ch["passes_with_margin"], ch
assert res["passes"] is True
sv = se["verification"]
assert [L["level"] for L in res["levels"]] == [v["level"] for v in sv] and res["levels"][0]["level"] == ch["level"]
for L, v in zip(res["levels"], sv):
    assert L["verification"] == {k: v[k] for k in ("views", "statistic", "pass")} and v["pass"], (L, v)
assert any(v["views"] > 0 for v in sv), sv
PY
finish
