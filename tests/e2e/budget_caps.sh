#!/usr/bin/env bash
# jnd budget, a level's texture cap at its switch distance (src/tasks/budget.c
# levels): a level seen only from distance d on samples no mip finer than the
# one 000 §4's bound gives there, and an image sampled by several slots is
# capped at the finest mip any of them samples. A ball whose upper half
# (material "fine") maps one 128² image once and whose lower half (material
# "coarse") repeats it 16 times: the lower half samples mips 4 coarser. With
# the image shared, its cap at each switch distance is the upper half's; with
# the lower half given its own copy of the image, the copy is capped
# smaller, and the upper half's image exactly as when shared.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
need_renderer
command -v python3 >/dev/null || skip "needs python3"

PYTHONPATH="$(dirname "$0")" python3 - "$T" <<'PY'
import struct, sys
from gltfwrite import uv_sphere, write_glb
from pngwrite import png
d, N = sys.argv[1], 128
corners = [(a, b, c) for a in (0, 1) for b in (0, 1) for c in (0, 1)]
def checker(x, y):   # two colours a texel apart in every 4×4 block: any halving blends them
    bx, by = x // 4, y // 4
    a, b = corners[(3 * bx + 5 * by) % 8], corners[(bx + 7 * by + 3) % 8]
    if a == b:
        b = corners[(corners.index(a) + 1) % 8]
    return a if (x + y) % 2 else b
png(d + "/i.png", N, N, 3, checker)
img = open(d + "/i.png", "rb").read()
pos, uv, idx = uv_sphere(32, 16)
half = len(idx) // 2   # the upper rings' triangles, then the lower ones'
nv = len(pos) // 3
uv16 = [16 * t for t in uv]
geo = (struct.pack('<%df' % len(pos), *pos) * 2 + struct.pack('<%df' % len(uv), *uv)
       + struct.pack('<%df' % len(uv16), *uv16) + struct.pack('<%dI' % len(idx), *idx))
view = lambda off, n: {"buffer": 0, "byteOffset": off, "byteLength": n}
ib = 40 * nv
for name, sources in (("shared", [0, 0]), ("apart", [0, 1])):
    g = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
         "bufferViews": [view(0, 12 * nv), view(12 * nv, 12 * nv), view(24 * nv, 8 * nv), view(32 * nv, 8 * nv),
                         view(ib, 4 * half), view(ib + 4 * half, 4 * (len(idx) - half))],
         "accessors": [{"bufferView": 0, "componentType": 5126, "count": nv, "type": "VEC3", "min": [-1, -1, -1], "max": [1, 1, 1]},
                       {"bufferView": 1, "componentType": 5126, "count": nv, "type": "VEC3"},
                       {"bufferView": 2, "componentType": 5126, "count": nv, "type": "VEC2"},
                       {"bufferView": 3, "componentType": 5126, "count": nv, "type": "VEC2"},
                       {"bufferView": 4, "componentType": 5125, "count": half, "type": "SCALAR"},
                       {"bufferView": 5, "componentType": 5125, "count": len(idx) - half, "type": "SCALAR"}],
         "samplers": [{"wrapS": 10497, "wrapT": 10497}],
         "textures": [{"source": s, "sampler": 0} for s in sorted(set(sources))],
         "materials": [{"name": "fine", "pbrMetallicRoughness": {"baseColorTexture": {"index": sources[0]}, "metallicFactor": 0}},
                       {"name": "coarse", "pbrMetallicRoughness": {"baseColorTexture": {"index": sources[1]}, "metallicFactor": 0}}],
         "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 4, "material": 0},
                                    {"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 3}, "indices": 5, "material": 1}]}]}
    write_glb(d + "/%s.glb" % name, g, geo, [img] * len(set(sources)))
PY

SMALL=(--map-size 128 --size 96x96 --samples 1 --views 2 --confirm 0 --screens 640x480 --errors 0.002,0.01
       --judge-views 2 --max-px 128 --tolerance 0.5 --far-coverage 0.05 --verify-views 2 --min-size 4 --quiet)
for m in shared apart; do
  "$JND" budget "$T/$m.glb" -o "$T/$m" "${SMALL[@]}" >"$T/$m.txt" 2>&1
  rc=$?
  check "$m: budget runs (exit 0 or 1; rc $rc: $(head -c 200 "$T/$m.txt"))" test "$rc" -le 1 -a -s "$T/$m/budget.json"
done
check "an image two slots share is capped at the finest mip either samples: the fine half's, as when it is its own" \
  python3 - "$T/shared/budget.json" "$T/apart/budget.json" <<'PY'
import json, sys
sh, ap = (json.load(open(f))["result"] for f in sys.argv[1:3])
lv = lambda r: {L["level"]: L for L in r["levels"] if L["switch_distance"] and L["verification"]["views"]}
ls, la = lv(sh), lv(ap)
assert ls and set(ls) == set(la), (ls, la)
assert sh["chosen"]["sizes"]["fine/baseColor"] == ap["chosen"]["sizes"]["fine/baseColor"], (sh["chosen"], ap["chosen"])
seen = 0
for k in ls:
    s, a = ls[k]["sizes"], la[k]["sizes"]
    # apart, the repeated copy samples coarser mips: capped smaller than the fine half's image
    seen += max(a["coarse/baseColor"]) < max(a["fine/baseColor"])
    # shared, both slots hold the fine half's cap
    assert s["fine/baseColor"] == s["coarse/baseColor"] == a["fine/baseColor"], (k, s, a)
assert seen, ("the two halves' caps never differ: the test shows nothing", ls, la)
PY
finish
