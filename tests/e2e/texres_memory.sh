#!/usr/bin/env bash
# jnd texres counts memory as a GPU holds it (issue 25): each unique image
# once, with its mip chain, at one size. On glTF and GLB assets built here —
# two materials sharing one image, a packed occlusion-roughness-metal image,
# a material no mesh uses, and a material only KHR_materials_variants
# reaches — the reported before/after bytes equal the sum over the unique
# images the default scene's materials sample, read back from the input and
# from the written model (RGBA8: w·h·4 a level; block formats by 4×4
# blocks), computed here without jnd; a packed or shared image stays one
# image, and no image grows.
. "$(dirname "$0")/lib.bash"
command -v python3 >/dev/null || skip "needs python3"
need_renderer

PYTHONPATH="$(dirname "$0")" python3 - "$T" <<'PY'
import json, struct, sys
from gltfwrite import png_bytes, write_glb
d = sys.argv[1]
# 0: the shells' shared colour; 1: metal's packed occlusion-roughness-metal;
# 2: metal's colour and emission (BC7 and BC1 slots: the image needs BC7);
# 3: the unused material's; 4: the variant's own
sizes = [(64, 64), (64, 64), (64, 32), (48, 48), (40, 40)]
imgs = [png_bytes(w, h, k) for k, (w, h) in enumerate(sizes)]
def quad(x0):
    return struct.pack('<12f', x0, 0, 0, x0 + 1, 0, 0, x0 + 1, 1, 0, x0, 1, 0)
uv = struct.pack('<8f', 0, 1, 1, 1, 1, 0, 0, 0)
idx = struct.pack('<6I', 0, 1, 2, 0, 2, 3)
geo = quad(0) + quad(1.1) + quad(2.2) + uv + idx
tex = lambda i: {"index": i}
g = {
  "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
  "nodes": [{"mesh": 0}, {"mesh": 1}, {"mesh": 2}],
  "extensionsUsed": ["KHR_materials_variants"],
  "extensions": {"KHR_materials_variants": {"variants": [{"name": "plain"}, {"name": "gold"}]}},
  "bufferViews": [{"buffer": 0, "byteOffset": 48 * k, "byteLength": 48} for k in range(3)]
                 + [{"buffer": 0, "byteOffset": 144, "byteLength": 32}, {"buffer": 0, "byteOffset": 176, "byteLength": 24}],
  "accessors": [{"bufferView": k, "componentType": 5126, "count": 4, "type": "VEC3",
                 "min": [1.1 * k, 0, 0], "max": [1.1 * k + 1, 1, 0]} for k in range(3)]
               + [{"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC2"},
                  {"bufferView": 4, "componentType": 5125, "count": 6, "type": "SCALAR"}],
  "textures": [{"source": i} for i in range(5)],
  "materials": [
    {"name": "unused", "pbrMetallicRoughness": {"baseColorTexture": tex(3)}, "occlusionTexture": tex(1)},
    {"name": "shellA", "pbrMetallicRoughness": {"baseColorTexture": tex(0)}},
    {"name": "shellB", "pbrMetallicRoughness": {"baseColorTexture": tex(0)}},
    {"name": "metal", "pbrMetallicRoughness": {"baseColorTexture": tex(2), "metallicRoughnessTexture": tex(1)},
     "occlusionTexture": tex(1), "emissiveTexture": tex(2), "emissiveFactor": [0.2, 0.2, 0.2]},
    {"name": "gold", "pbrMetallicRoughness": {"baseColorTexture": tex(4), "metallicRoughnessTexture": tex(1)}}],
  "meshes": [
    {"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 3}, "indices": 4, "material": 1,
                     "extensions": {"KHR_materials_variants": {"mappings": [{"material": 4, "variants": [1]}]}}}]},
    {"primitives": [{"attributes": {"POSITION": 1, "TEXCOORD_0": 3}, "indices": 4, "material": 2}]},
    {"primitives": [{"attributes": {"POSITION": 2, "TEXCOORD_0": 3}, "indices": 4, "material": 3}]}]}
t = json.loads(json.dumps(g))
t["buffers"] = [{"uri": "mem.bin", "byteLength": len(geo)}]
t["images"] = [{"uri": "mem_img%d.png" % i} for i in range(5)]
open(f"{d}/mem.bin", "wb").write(geo)
for i, b in enumerate(imgs):
    open(f"{d}/mem_img{i}.png", "wb").write(b)
json.dump(t, open(f"{d}/mem.gltf", "w"))
write_glb(f"{d}/mem.glb", g, geo, imgs)
PY


L="--views 2 --size 64x64 --anisotropy 1 --samples 1 --p 0.999 --q 0.5 --margin 0 --confirm 0 --min-size 8 --quiet"
# every map searched; then one slot of the packed image and one of the
# shared image searched, the others kept: their images must stay whole
# (the size the most demanding slot needs), not split into a smaller copy
# beside the original
for run in "mem.gltf all" "mem.glb all" "mem.gltf some" "mem.glb some"; do
  set -- $run
  m=$1 O=$T/out_$1_$2
  case $2 in
    all) "$JND" texres "$T/$m" -o "$O" $L ;;
    some) "$JND" texres "$T/$m" -o "$O" --maps metal/occlusion,shellA/baseColor,metal/baseColor,metal/emissive $L ;;
  esac
  rc=$?
  check "$m ($2): texres runs (exit 0 or 1)" [ $rc -le 1 ]
  check "$m ($2): the reported bytes are the unique images' mip chains, before (input) and after (the written model)" \
    env PYTHONPATH="$(dirname "$0")" python3 - "$T/$m" "$O/model/$m" "$O/texres.json" <<'PY'
import json, sys
from gpu_bytes import memory
src, out, rep = sys.argv[1:]
r = json.load(open(rep))["result"]
mem = r["memory"]
b_rgba, b_block, b_imgs, _ = memory(src)
a_rgba, a_block, a_imgs, _ = memory(out)
# shellA and shellB share one image, metal's occlusion and metallicRoughness
# another, its baseColor and emissive a third: 3 images, 6 slots
assert len(b_imgs) == 3 and len(a_imgs) == 3, (b_imgs, a_imgs)
assert sorted(len(s) for _, s in a_imgs.values()) == [2, 2, 2], a_imgs
assert mem["before_bytes"] == b_rgba, (mem["before_bytes"], b_rgba)
assert mem["after_bytes"] == a_rgba, (mem["after_bytes"], a_rgba)
assert mem["block_before_bytes"] == b_block, (mem["block_before_bytes"], b_block)
assert mem["block_after_bytes"] == a_block, (mem["block_after_bytes"], a_block)
assert mem["formats_before"]["rgba8"] == b_rgba and mem["formats_after"]["rgba8"] == a_rgba
assert abs(mem["reduction"] - (1 - a_rgba / b_rgba)) < 1e-9
assert a_rgba < b_rgba, "nothing was resized: the test says nothing"
# per image: the slots that sample it, its sizes, its bytes
assert len(mem["images"]) == 3, mem["images"]
back = {tuple(sorted(s)): wh for wh, s in a_imgs.values()}
for im in mem["images"]:
    key = tuple(sorted(im["maps"]))
    assert key in back, (key, back)
    assert list(back[key]) == im["chosen"], (key, back[key], im["chosen"])
    w, h = im["chosen"]
    assert im["bytes_after"]["rgba8"] == sum(4 * max(1, w >> l) * max(1, h >> l) for l in range(max(w, h).bit_length()))
assert sum(im["bytes_after"]["rgba8"] for im in mem["images"]) == a_rgba
# every map reports the size of its image
for m in r["maps"]:
    assert m["chosen"] == mem["images"][m["image"]]["chosen"], m
PY
  check "$m ($2): a packed or shared image stays one image, no image grows, the other materials keep theirs" \
    env PYTHONPATH="$(dirname "$0")" python3 - "$T/$m" "$O/model/$m" <<'PY'
import sys
from gpu_bytes import load, image_size
src, out = sys.argv[1:]
g0, b0 = load(src)
g1, b1 = load(out)
def img(g, mat, *keys):
    o = g["materials"][mat]
    for k in keys: o = o[k]
    return g["textures"][o["index"]]["source"]
# metal: occlusion and metallicRoughness one image; shellA and shellB one image
assert img(g1, 3, "occlusionTexture") == img(g1, 3, "pbrMetallicRoughness", "metallicRoughnessTexture")
assert img(g1, 1, "pbrMetallicRoughness", "baseColorTexture") == img(g1, 2, "pbrMetallicRoughness", "baseColorTexture")
# no slot of any material samples a larger image than it did
for mi, mat in enumerate(g0["materials"]):
    for keys in (("pbrMetallicRoughness", "baseColorTexture"), ("pbrMetallicRoughness", "metallicRoughnessTexture"),
                 ("occlusionTexture",)):
        try: i0 = img(g0, mi, *keys)
        except KeyError: continue
        w0, h0 = image_size(src, g0, b0, i0)
        w1, h1 = image_size(out, g1, b1, img(g1, mi, *keys))
        assert w1 <= w0 and h1 <= h0, (mat["name"], keys, (w0, h0), (w1, h1))
# the unused and the variant-only materials were not judged: their images keep their size, the packed
# image they share with metal's judged slots (the unused one's occlusion, gold's metallicRoughness) too
for mi, slots in ((0, ("occlusionTexture",)), (4, ("pbrMetallicRoughness", "metallicRoughnessTexture"))):
    for keys in (("pbrMetallicRoughness", "baseColorTexture"), slots):
        assert image_size(out, g1, b1, img(g1, mi, *keys)) == image_size(src, g0, b0, img(g0, mi, *keys))
PY
done

# an OBJ whose two materials sample one file: the chosen image is written
# once, and both maps name it
PYTHONPATH="$(dirname "$0")" python3 - "$T" <<'PY'
import sys
from gltfwrite import png_bytes
d = sys.argv[1]
open(f"{d}/shared.png", "wb").write(png_bytes(256, 256, 0))
open(f"{d}/two.mtl", "w").write("newmtl A\nKd 1 1 1\nmap_Kd shared.png\nnewmtl B\nKd 1 1 1\nmap_Kd shared.png\n")
open(f"{d}/two.obj", "w").write(
    "mtllib two.mtl\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1.1 0 0\nv 2.1 0 0\nv 2.1 1 0\nv 1.1 1 0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
    "usemtl A\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n"
    "usemtl B\nf 5/1/1 6/2/1 7/3/1\nf 5/1/1 7/3/1 8/4/1\n")
PY
expect_exit 0 "an OBJ with one file under two materials runs" "$JND" texres "$T/two.obj" -o "$T/two" \
  --views 2 --size 96x96 --samples 1 --confirm 0 --min-size 16 --quiet
check "the shared file is one image, written once (maps/), and both maps name it" python3 - "$T/two" <<'PY'
import json, os, struct, sys
d = sys.argv[1]
r = json.load(open(d + "/texres.json"))["result"]
base = [m for m in r["maps"] if m["slot"] == "baseColor"]
assert len(base) == 2 and base[0]["image"] == base[1]["image"], base
im = r["memory"]["images"][base[0]["image"]]
assert sorted(im["maps"]) == sorted(m["name"] for m in base), im
changed = [i for i in r["memory"]["images"] if i["chosen"] != i["original"]]
assert im in changed, ("the 256-pixel image on a 96-pixel view must shrink", im)
assert len(r["map_files"]) == len(changed), (r["map_files"], changed)
assert sorted(os.listdir(d + "/maps")) == sorted(os.path.basename(f) for f in r["map_files"])
for f, i in zip(r["map_files"], changed):
    b = open(os.path.join(d, f), "rb").read(24)
    assert list(struct.unpack(">II", b[16:24])) == i["chosen"], (f, i)
PY

# one file spelt three ways (shared.png as colour, ./shared.png as emission, a
# link to it in another material): one image, counted once, written once
PYTHONPATH="$(dirname "$0")" python3 - "$T" <<'PY'
import os, sys
d = sys.argv[1]
os.symlink("shared.png", f"{d}/link.png")
open(f"{d}/spelt.mtl", "w").write("newmtl A\nKd 1 1 1\nKe 1 1 1\nmap_Kd shared.png\nmap_Ke ./shared.png\n"
                                  "newmtl B\nKd 1 1 1\nmap_Kd link.png\n")
open(f"{d}/spelt.obj", "w").write(open(f"{d}/two.obj").read().replace("two.mtl", "spelt.mtl"))
PY
expect_exit 0 "an OBJ naming one file three ways runs" "$JND" texres "$T/spelt.obj" -o "$T/spelt" \
  --views 2 --size 96x96 --samples 1 --confirm 0 --min-size 16 --quiet
check "one file however it is spelt: one image, its bytes once, one file written" python3 - "$T/spelt" <<'PY'
import json, os, sys
d = sys.argv[1]
r = json.load(open(d + "/texres.json"))["result"]
assert sorted(m["name"] for m in r["maps"]) == ["A/baseColor", "A/emissive", "B/baseColor"], r["maps"]
assert len({m["image"] for m in r["maps"]}) == 1 and len(r["memory"]["images"]) == 1, r["maps"]
def chain(w, h):
    b = 0
    while True:
        b += w * h * 4
        if w == 1 and h == 1: return b
        w, h = max(1, w // 2), max(1, h // 2)
im = r["memory"]["images"][0]
assert r["memory"]["before_bytes"] == chain(256, 256) and r["memory"]["after_bytes"] == chain(*im["chosen"]), r["memory"]
assert len(r["map_files"]) == 1 and os.listdir(d + "/maps") == [os.path.basename(r["map_files"][0])], r["map_files"]
PY
finish
