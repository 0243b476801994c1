#!/usr/bin/env bash
# jnd budget, budget mode's encodings (src/tasks/budget.c budget_encodings,
# by_saving): a candidate over the memory budget gets a variant whose images
# take BC1 (4 bits a texel where their slots ask for 8), the image that saves
# most first, until it fits. A ball of two materials whose baseColors differ
# in size (128² and 32², both BC7: BC1 halves each), under a budget that
# encoding the larger one alone meets and the smaller one alone does not:
# the larger takes BC1 and the smaller keeps BC7 (taking the smaller first,
# both would be encoded). The choice's memory is recomputed from its sizes and
# formats (000 Table 2), and it is the least visible within the budget.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
need_renderer
command -v python3 >/dev/null || skip "needs python3"

# the maps: a texel checker of two colours per 4×4 block, each an RGB565
# endpoint exactly (channels 0 or 255), so BC1 holds every block without
# error while any halving blends the two (seen on every view)
PYTHONPATH="$(dirname "$0")" python3 - "$T" <<'PY'
import struct, sys
from gltfwrite import uv_sphere, write_glb
from pngwrite import png
d = sys.argv[1]
corners = [(a, b, c) for a in (0, 1) for b in (0, 1) for c in (0, 1)]
def checker(x, y, k):
    bx, by = x // 4, y // 4
    a, b = corners[(3 * bx + 5 * by + k) % 8], corners[(bx + 7 * by + 3 + k) % 8]
    if a == b:
        b = corners[(corners.index(a) + 1) % 8]
    return a if (x + y) % 2 else b
images = []
for n, (side, k) in enumerate(((128, 0), (32, 1))):
    png(d + "/m%d.png" % n, side, side, 3, lambda x, y: checker(x, y, k))
    images.append(open(d + "/m%d.png" % n, "rb").read())
S, R = 32, 16
pos, uv, idx = uv_sphere(S, R)
half = len(idx) // 2   # the upper rings' triangles, then the lower ones'
nv = len(pos) // 3
geo = (struct.pack('<%df' % len(pos), *pos) * 2 + struct.pack('<%df' % len(uv), *uv)
       + struct.pack('<%dI' % len(idx), *idx))
view = lambda off, n: {"buffer": 0, "byteOffset": off, "byteLength": n}
ib = 32 * nv
g = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
     "bufferViews": [view(0, 12 * nv), view(12 * nv, 12 * nv), view(24 * nv, 8 * nv), view(ib, 4 * half),
                     view(ib + 4 * half, 4 * (len(idx) - half))],
     "accessors": [{"bufferView": 0, "componentType": 5126, "count": nv, "type": "VEC3", "min": [-1, -1, -1], "max": [1, 1, 1]},
                   {"bufferView": 1, "componentType": 5126, "count": nv, "type": "VEC3"},
                   {"bufferView": 2, "componentType": 5126, "count": nv, "type": "VEC2"},
                   {"bufferView": 3, "componentType": 5125, "count": half, "type": "SCALAR"},
                   {"bufferView": 4, "componentType": 5125, "count": len(idx) - half, "type": "SCALAR"}],
     "textures": [{"source": 0}, {"source": 1}],
     "materials": [{"name": "large", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0}},
                   {"name": "small", "pbrMetallicRoughness": {"baseColorTexture": {"index": 1}, "metallicFactor": 0}}],
     "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0},
                                {"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 4, "material": 1}]}]}
write_glb(d + "/two.glb", g, geo, images)
PY

# the budget: both at BC7 less half the larger's bytes (000 Table 2, mip chains):
# the larger in BC1 fits exactly; the smaller in BC1 saves about a sixteenth of that
budget=$(PYTHONPATH="$(dirname "$0")" python3 -c '
from gltfwrite import mip_chain_bytes as chain
print(chain(128, 128, 16) + chain(32, 32, 16) - (chain(128, 128, 16) - chain(128, 128, 8)))')
SMALL=(--map-size 128 --size 96x96 --samples 1 --views 4 --confirm 0 --screens 640x480 --errors 0.01
       --judge-views 2 --max-px 128 --tolerance 0.5 --far-coverage 0.05 --verify-views 2 --min-size 16 --quiet)
"$JND" budget "$T/two.glb" -o "$T/b" --memory "${budget}B" "${SMALL[@]}" >"$T/out.txt" 2>"$T/err.txt"
rc=$?
check "budget mode runs (exit 0 or 1; rc $rc: $(head -c 200 "$T/err.txt"))" test "$rc" -le 1 -a -s "$T/b/budget.json"
check "the larger image takes BC1 and the smaller keeps BC7, at their full sizes: the least visible candidate within the budget" \
  env PYTHONPATH="$(dirname "$0")" python3 - "$T/b/budget.json" "$budget" <<'PY'
import json, sys
from gltfwrite import mip_chain_bytes as chain
r = json.load(open(sys.argv[1])); M = int(sys.argv[2])
res = r["result"]; ch = res["chosen"]
assert r["parameters"]["mode"] == "budget"
assert ch["kind"] == "encoded", ch
f, sz = ch["formats"], ch["sizes"]
assert sz == {"large/baseColor": [128, 128], "small/baseColor": [32, 32]}, sz
assert f == {"large/baseColor": "bc1", "small/baseColor": "bc7"}, f
# its memory from its sizes and formats (000 Table 2), within the budget
block = {"bc7": 16, "bc1": 8}
mem = sum(chain(*sz[n], block[f[n]]) for n in f)
assert mem == ch["memory_bytes"] <= M, (mem, ch["memory_bytes"], M)
# seen on no view (BC1 holds the checker exactly); every halving is seen on every view
assert ch["statistic"] == 0, ch
inb = [c for c in res["candidates"] if c["memory_bytes"] <= M and c["kind"] != "encoded"]
assert inb and all(c["statistic"] > ch["statistic"] for c in inb), inb
PY

# every written level renders with jnd render --lod K, and it is that level:
# its triangles as budget.json says
nl=$(python3 -c 'import json,sys; print(len(json.load(open(sys.argv[1]))["result"]["levels"]))' "$T/b/budget.json")
check "the written model has a coarser level (nl $nl)" test "$nl" -ge 2
for k in $(seq 0 $((nl - 1))); do
  expect_exit 0 "jnd render --lod $k renders written level $k" "$JND" render "$T/b/model/two.glb" --lod "$k" \
    -o "$T/r$k" --views 1 --size 48x48 --quiet --json "$T/r$k.json"
  check "... with level $k's triangles" python3 - "$T/b/budget.json" "$T/r$k.json" "$k" <<'PY'
import json, sys
lv = json.load(open(sys.argv[1]))["result"]["levels"][int(sys.argv[3])]
got = json.load(open(sys.argv[2]))["result"]["triangles"]
assert got == lv["triangles"], (got, lv)
PY
done

# the smallest budget possible (every map at --min-size, 16², at the slots'
# formats): met, not refused; one byte less is refused before any rendering.
# Every candidate that fits is seen on every view (statistic 1), so the tie
# goes to the cheapest: the coarser level's triangles
least=$(PYTHONPATH="$(dirname "$0")" python3 -c 'from gltfwrite import mip_chain_bytes as chain; print(2 * chain(16, 16, 16))')
"$JND" budget "$T/two.glb" -o "$T/m" --memory "${least}B" "${SMALL[@]}" >"$T/out.txt" 2>"$T/err.txt"
rc=$?
check "a budget of the smallest possible memory is met (rc $rc: $(head -c 200 "$T/err.txt"))" test "$rc" -le 1 -a -s "$T/m/budget.json"
check "... of the candidates within it, equally seen, the cheapest" python3 - "$T/m/budget.json" "$least" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); M = int(sys.argv[2])
res = r["result"]; ch = res["chosen"]
inb = [c for c in res["candidates"] if c["memory_bytes"] <= M]
assert ch["memory_bytes"] == M and ch["statistic"] == min(c["statistic"] for c in inb), (ch, inb)
tied = [c for c in inb if c["statistic"] == ch["statistic"]]
assert len({c["cost_bytes"] for c in tied}) >= 2, ("no tie to break", tied)
assert ch["cost_bytes"] == min(c["cost_bytes"] for c in tied), (ch["cost_bytes"], tied)
PY
expect_exit 2 "a byte under the smallest possible: exit 2" "$JND" budget "$T/two.glb" -o "$T/n" --memory "$((least - 1))B" \
  "${SMALL[@]}"
check "... one line naming the smallest possible, nothing written" \
  sh -c "[ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -q 'smallest possible is' '$T/err.txt' && [ ! -e '$T/n' ]"
finish
