#!/usr/bin/env bash
# jnd pca counts memory as a GPU holds it (issue 25): before, each unique
# source image once as RGBA8 with its mip chain, with the maps that sample
# it — a packed occlusion-roughness-metal image bound to two slots, or one
# image as colour and emission, is one image; after, each packed component
# texture with its mip chain at its texels' bytes (1, 2 or 4 channels; RGB
# is stored RGBA). The figures are recomputed here from the input model and
# the written PNG files, without jnd.
. "$(dirname "$0")/lib.bash"
command -v python3 >/dev/null || skip "needs python3"
need_renderer

PYTHONPATH="$(dirname "$0")" python3 - "$T" <<'PY'
import json, struct, sys
from gltfwrite import png_bytes
d = sys.argv[1]
# 0: colour and emission of one material (one image); 1: packed occlusion-roughness-metal
sizes = [(64, 64), (32, 32)]
for i, (w, h) in enumerate(sizes):
    open(f"{d}/img{i}.png", "wb").write(png_bytes(w, h, i))
def quad(x0):
    return struct.pack('<12f', x0, 0, 0, x0 + 1, 0, 0, x0 + 1, 1, 0, x0, 1, 0)
uv = struct.pack('<8f', 0, 1, 1, 1, 1, 0, 0, 0)
idx = struct.pack('<6I', 0, 1, 2, 0, 2, 3)
geo = quad(0) + uv + idx
open(f"{d}/m.bin", "wb").write(geo)
tex = lambda i: {"index": i}
g = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
     "buffers": [{"uri": "m.bin", "byteLength": len(geo)}],
     "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                     {"buffer": 0, "byteOffset": 80, "byteLength": 24}],
     "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                   {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                   {"bufferView": 2, "componentType": 5125, "count": 6, "type": "SCALAR"}],
     "images": [{"uri": "img0.png"}, {"uri": "img1.png"}], "textures": [{"source": 0}, {"source": 1}],
     "materials": [{"name": "metal", "pbrMetallicRoughness": {"baseColorTexture": tex(0), "metallicRoughnessTexture": tex(1)},
                    "occlusionTexture": tex(1), "emissiveTexture": tex(0), "emissiveFactor": [0.2, 0.2, 0.2]}],
     "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}]}
json.dump(g, open(f"{d}/m.gltf", "w"))
PY
expect_exit 0 "pca of a material with a packed and a shared image runs" "$JND" pca --model "$T/m.gltf" \
  --material metal -o "$T/out" --components 3 --no-bc --views 2 --size 96x96 --samples 1
cp "$T/err.txt" "$T/printed.txt"
check "before: each unique image once (RGBA8 + mips); after: the packed textures (+ mips), from the files" \
  python3 - "$T" <<'PY'
import json, struct, sys
d = sys.argv[1]
r = json.load(open(d + "/out/pca.json"))["result"]
mem = r["memory"]
def chain(w, h, texel):
    b = 0
    while True:
        b += w * h * texel
        if w == 1 and h == 1: return b
        w, h = max(1, w // 2), max(1, h // 2)
def png(path):
    b = open(path, "rb").read(26)
    w, h = struct.unpack(">II", b[16:24])
    depth, colour = b[24], b[25]
    ch = {0: 1, 4: 2, 2: 3, 6: 4}[colour]
    return w, h, ch, depth
imgs = sorted((sorted(i["maps"]), i["width"], i["height"]) for i in mem["images"])
assert imgs == [(["metal/baseColor", "metal/emissive"], 64, 64),
                (["metal/metallicRoughness", "metal/occlusion"], 32, 32)], imgs
before = chain(64, 64, 4) + chain(32, 32, 4)
assert mem["before_bytes"] == before == sum(i["bytes"] for i in mem["images"]), (mem["before_bytes"], before)
after = 0
for t in mem["textures"]:
    w, h, ch, depth = png(d + "/out/" + t["file"])
    assert (w, h, ch, depth) == (t["width"], t["height"], t["channels"], t["bits"]), (t, (w, h, ch, depth))
    after += chain(w, h, (4 if ch == 3 else ch) * depth // 8)
assert mem["after_bytes"] == after == sum(t["bytes"] for t in mem["textures"]), (mem["after_bytes"], after)
assert len(mem["textures"]) == len(r["textures"])
# per image before and after, with the maps that sample it (texres's shape): the
# packed textures replace every source image, and every map samples some texture
for i in mem["images"]:
    assert i["bytes_before"] == chain(i["width"], i["height"], 4) and i["bytes_after"] == 0, i
maps = set(m for i in mem["images"] for m in i["maps"])
assert set(m for t in mem["textures"] for m in t["maps"]) == maps, [t["maps"] for t in mem["textures"]]
assert all(t["maps"] and set(t["maps"]) <= maps for t in mem["textures"])
PY
check "the printout: per image and texture before and after in MiB, the totals, the energy kept" \
  python3 - "$T" <<'PY'
import json, re, sys
d = sys.argv[1]
r = json.load(open(d + "/out/pca.json"))["result"]
mem = r["memory"]
text = open(d + "/printed.txt").read()
mib = lambda b: "%.3f" % (b / 1048576)
for i in mem["images"]:
    row = [l for l in text.splitlines() if "%dx%d" % (i["width"], i["height"]) in l and "components_" not in l]
    assert len(row) == 1 and row[0].split()[-2:] == [mib(i["bytes_before"]), mib(0)], (i, row)
    assert all(m.split("/")[-1] in row[0] for m in i["maps"]), (i["maps"], row)
for t in mem["textures"]:
    row = [l for l in text.splitlines() if t["file"] in l]
    assert len(row) == 1 and row[0].split()[-2:] == [mib(0), mib(t["bytes"])], (t, row)
assert "memory as a GPU holds it: %s MiB -> %s MiB" % (mib(mem["before_bytes"]), mib(mem["after_bytes"])) in text, text
# the energy printed is the kept components' share of the variance, recomputed from the report
K = len(r["components"])
kept = 100 * sum(r["energy"][:K]) / r["total_variance"]
m = re.search(r"the (\d+) components? kept holds? ([0-9.]+)% of the energy", text)
assert m and int(m.group(1)) == K and m.group(2) == "%.1f" % kept, (m and m.groups(), K, kept)
PY
finish
