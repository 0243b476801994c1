#!/usr/bin/env bash
# The memory figures batch's summary, jnd report and make bench show are the
# per-unique-image accounting (issue 25): on a model built here whose two
# materials share one colour image and whose second material samples a
# packed occlusion-roughness-metal image in two slots (2 images, 4 slots),
# texres and pca run through jnd batch; summary.json and summary.csv, the
# report's index (each row's cells and the totals, exact value and MiB text)
# and the asset's page, and bench's memory line (bench/figures.py, what
# bench_texres.sh and bench_pca.sh print) all equal the unique images' mip
# chains computed here without jnd (tests/e2e/gpu_bytes.py) — not the
# once-per-slot sum.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
command -v python3 >/dev/null || skip "needs python3"
need_renderer
here=$(cd "$(dirname "$0")" && pwd)
cd "$T" || exit 1

PYTHONPATH="$here" python3 - "$T" <<'PY'
import json, struct, sys
from gltfwrite import png_bytes
d = sys.argv[1]
# 0: both shells' colour (128²); 1: shellB's packed occlusion-roughness-metal (64²)
for i, (w, h) in enumerate([(128, 128), (64, 64)]):
    open(f"{d}/img{i}.png", "wb").write(png_bytes(w, h, i))
def quad(x0):
    return struct.pack('<12f', x0, 0, 0, x0 + 1, 0, 0, x0 + 1, 1, 0, x0, 1, 0)
uv = struct.pack('<8f', 0, 1, 1, 1, 1, 0, 0, 0)
idx = struct.pack('<6I', 0, 1, 2, 0, 2, 3)
geo = quad(0) + quad(1.1) + uv + idx
open(f"{d}/m.bin", "wb").write(geo)
tex = lambda i: {"index": i}
g = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}], "nodes": [{"mesh": 0}, {"mesh": 1}],
     "buffers": [{"uri": "m.bin", "byteLength": len(geo)}],
     "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 48},
                     {"buffer": 0, "byteOffset": 96, "byteLength": 32}, {"buffer": 0, "byteOffset": 128, "byteLength": 24}],
     "accessors": [{"bufferView": k, "componentType": 5126, "count": 4, "type": "VEC3",
                    "min": [1.1 * k, 0, 0], "max": [1.1 * k + 1, 1, 0]} for k in range(2)]
                  + [{"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
                     {"bufferView": 3, "componentType": 5125, "count": 6, "type": "SCALAR"}],
     "images": [{"uri": "img0.png"}, {"uri": "img1.png"}], "textures": [{"source": 0}, {"source": 1}],
     "materials": [{"name": "shellA", "pbrMetallicRoughness": {"baseColorTexture": tex(0)}},
                   {"name": "shellB", "pbrMetallicRoughness": {"baseColorTexture": tex(0), "metallicRoughnessTexture": tex(1)},
                    "occlusionTexture": tex(1)}],
     "meshes": [{"primitives": [{"attributes": {"POSITION": k, "TEXCOORD_0": 2}, "indices": 3, "material": k}]}
                for k in range(2)]}
json.dump(g, open(f"{d}/m.gltf", "w"))
PY

SMALL="--views 2 --size 64x64 --samples 1 --anisotropy 1"
cat >assets.csv <<EOF
id,asset,command,options
tex,m.gltf,texres,$SMALL --p 0.999 --q 0.5 --margin 0 --confirm 0 --min-size 8 --no-matrix
set,m.gltf,pca,--material shellB --components 2 --no-bc $SMALL
EOF
expect_exit 0 "jnd batch runs texres and pca on the model" "$JND" batch assets.csv -o out --quiet
expect_exit 0 "jnd batch merge" "$JND" batch merge out --no-timings --quiet
expect_exit 0 "jnd report" "$JND" report out --quiet

check "summary.json and summary.csv: each unique image once with its mips, before and after, and their totals" \
  env PYTHONPATH="$here" python3 - <<'PY'
import csv, json
from gpu_bytes import chain, memory
s = json.load(open("out/summary.json"))["result"]
a = {e["id"]: e for e in s["assets"]}
assert a["tex"]["status"] == "ok" and a["set"]["status"] == "ok", a
before, _, imgs, _ = memory("m.gltf")
assert len(imgs) == 2 and sorted(len(sl) for _, sl in imgs.values()) == [2, 2], imgs
per_slot = sum(chain(*wh, 0) * len(sl) for wh, sl in imgs.values())
assert before == chain(128, 128, 0) + chain(64, 64, 0) and per_slot > before
# texres: before from the input, after from the model it wrote
after, _, out_imgs, _ = memory("out/tex/model/m.gltf")
assert len(out_imgs) == 2, out_imgs
assert a["tex"]["memory_before_bytes"] == before, (a["tex"], before, per_slot)
assert a["tex"]["memory_after_bytes"] == after, (a["tex"], after)
# pca of shellB: both images once (its colour, and the packed image of two slots)
assert a["set"]["memory_before_bytes"] == before, (a["set"], before, per_slot)
pca = json.load(open("out/set/pca.json"))["result"]["memory"]
assert a["set"]["memory_after_bytes"] == pca["after_bytes"] == sum(t["bytes"] for t in pca["textures"]), pca
t = s["totals"]
assert t["memory_before_bytes"] == 2 * before, t
assert t["memory_after_bytes"] == after + pca["after_bytes"], t
rows = {r["id"]: r for r in csv.DictReader(open("out/summary.csv"))}
for k in ("tex", "set"):
    assert int(rows[k]["memory_before_bytes"]) == a[k]["memory_before_bytes"], rows[k]
    assert int(rows[k]["memory_after_bytes"]) == a[k]["memory_after_bytes"], rows[k]
PY

check "the report's index: each row's memory cells and the totals are those bytes, in MiB" \
  env PYTHONPATH="$here" python3 - <<'PY'
import json, re
from gpu_bytes import chain
s = json.load(open("out/summary.json"))["result"]
html = open("out/report/index.html").read()
def text(v):
    x = v / 2 ** 20
    return "%.2f MiB" % x if abs(x) >= 0.01 or x == 0 else "%.4f MiB" % x
for e in s["assets"]:
    row = re.search(r'<tr data-status="ok" data-id="%s">(.*?)</tr>' % e["id"], html).group(1)
    cells = re.findall(r'<td class="num" data-value="([^"]*)"[^>]*>([^<]*)</td>', row)
    # P(detect), memory before, memory after, smaller
    (_, _), (b, bt), (a, at), _ = cells
    assert float(b) == e["memory_before_bytes"] and bt == text(e["memory_before_bytes"]), (e["id"], b, bt)
    assert float(a) == e["memory_after_bytes"] and at == text(e["memory_after_bytes"]), (e["id"], a, at)
before = chain(128, 128, 0) + chain(64, 64, 0)
for key, v in (("memory_before_bytes", 2 * before), ("memory_after_bytes", s["totals"]["memory_after_bytes"])):
    m = re.search(r'<div id="total-%s" data-value="([^"]*)"><b>([^<]*)</b>' % key, html)
    assert m and float(m.group(1)) == v and m.group(2) == text(v), (key, m and m.groups(), v)
# the asset's page: the field, and the images table with a row per image
page = open("out/report/tex.html").read()
m = re.search(r"<tr><th>memory before \(unique images, RGBA8 \+ mips\)</th><td>([^<]*)</td></tr>", page)
assert m and m.group(1) == text(before), (m and m.group(1), text(before))
table = page.split("<h2>Images (each once, as a GPU holds it)</h2>")[1].split("</table>")[0]
rows = re.findall(r"<tr><td>([^<]*)</td><td>(\d+)×(\d+)</td>.*?<td class=\"num\">([^<]*)</td>", table)
assert sorted((r[0], r[3]) for r in rows) == [("shellA/baseColor, shellB/baseColor", text(chain(128, 128, 0))),
                                              ("shellB/metallicRoughness, shellB/occlusion", text(chain(64, 64, 0)))], rows
PY

# bench's memory line (bench_texres.sh and bench_pca.sh print it) on the
# same reports
for r in tex/texres.json set/pca.json; do
  check "bench's memory line of $r: the unique images' MiB" \
    env PYTHONPATH="$here" python3 - "out/$r" "${JND_SRC:-$here/../..}/bench/figures.py" <<'PY'
import json, re, subprocess, sys
from gpu_bytes import chain
rep, figures = sys.argv[1:]
line = subprocess.run([sys.executable, figures, "memory", rep], check=True, capture_output=True, text=True).stdout
m = re.match(r"memory \((\d+) unique images, RGBA8 \+ mips\): ([0-9.]+) MiB -> ([0-9.]+) MiB \(([-+]\d+)%\)", line)
assert m, line
mem = json.load(open(rep))["result"]["memory"]
before = chain(128, 128, 0) + chain(64, 64, 0)
assert int(m.group(1)) == 2, line
assert m.group(2) == "%.3f" % (before / 2 ** 20), (line, before)
assert m.group(3) == "%.3f" % (mem["after_bytes"] / 2 ** 20), (line, mem["after_bytes"])
assert "MB" not in line.replace("MiB", ""), line
PY
done
finish
