#!/usr/bin/env bash
# jnd texres's model copy matches its report: on glTF and GLB assets with a
# material no mesh uses, a material only KHR_materials_variants reaches, two
# materials sharing one image, and nodes whose children hold meshes (assimp
# loads materials in the order the scene's meshes first use them, so the
# scene's material index is not the file's). For every written model, the
# map sizes read back with `jnd render --list-maps` equal the report's, and
# the images the other materials use are untouched. Memory as the GPU holds
# it (one size per shared image): tests/e2e/texres_memory.sh.
. "$(dirname "$0")/lib.bash"
command -v python3 >/dev/null || skip "needs python3"
need_renderer

PYTHONPATH="$(dirname "$0")" python3 - "$T" <<'PY'
import json, struct, sys
from gltfwrite import png_bytes, write_glb
d = sys.argv[1]
# image sizes differ, so a size read back says which image a slot uses
sizes = [(64, 32), (48, 48), (32, 64), (40, 40)]
imgs = [png_bytes(w, h, k) for k, (w, h) in enumerate(sizes)]
quad = struct.pack('<12f', 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0)
uv = struct.pack('<8f', 0, 1, 1, 1, 1, 0, 0, 0)
idx = struct.pack('<6I', 0, 1, 2, 0, 2, 3)
quad2 = struct.pack('<12f', 1.2, 0, 0, 2.2, 0, 0, 2.2, 1, 0, 1.2, 1, 0)
geo = quad + uv + idx + quad2
def doc(nodes, scene_nodes):
    return {
     "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": scene_nodes}], "nodes": nodes,
     "extensionsUsed": ["KHR_materials_variants"],
     "extensions": {"KHR_materials_variants": {"variants": [{"name": "plain"}, {"name": "label"}]}},
     "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                     {"buffer": 0, "byteOffset": 80, "byteLength": 24}, {"buffer": 0, "byteOffset": 104, "byteLength": 48}],
     "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                   {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                   {"bufferView": 2, "componentType": 5125, "count": 6, "type": "SCALAR"},
                   {"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC3", "min": [1.2, 0, 0], "max": [2.2, 1, 0]}],
     "textures": [{"source": i} for i in range(4)],
     "materials": [
       {"name": "unused", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}},
       {"name": "body", "pbrMetallicRoughness": {"baseColorTexture": {"index": 1}}},
       {"name": "label", "pbrMetallicRoughness": {"baseColorTexture": {"index": 2}}},
       {"name": "trim", "pbrMetallicRoughness": {"baseColorTexture": {"index": 1}}},
       {"name": "lid", "pbrMetallicRoughness": {"baseColorTexture": {"index": 3}}}],
     "meshes": [
       {"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 1,
                        "extensions": {"KHR_materials_variants": {"mappings": [{"material": 2, "variants": [1]}]}}}]},
       {"primitives": [{"attributes": {"POSITION": 3, "TEXCOORD_0": 1}, "indices": 2, "material": 4},
                       {"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 3}]}]}
# .gltf with files beside it; the second mesh under a child of the first node
for name, nodes, roots in (("flat", [{"mesh": 0}, {"mesh": 1}], [0, 1]),
                           ("nested", [{"mesh": 0, "children": [1]}, {"mesh": 1}], [0])):
    g = doc(nodes, roots)
    g["buffers"] = [{"uri": name + ".bin", "byteLength": len(geo)}]
    g["images"] = [{"uri": "%s_img%d.png" % (name, i)} for i in range(4)]
    open(f"{d}/{name}.bin", "wb").write(geo)
    for i, b in enumerate(imgs):
        open(f"{d}/{name}_img{i}.png", "wb").write(b)
    json.dump(g, open(f"{d}/{name}.gltf", "w"))
# .glb with the images in the binary chunk
g = doc([{"mesh": 0}, {"mesh": 1}], [0, 1])
write_glb(f"{d}/packed.glb", g, geo, imgs)
PY

L="--views 2 --size 64x64 --anisotropy 1 --samples 1 --p 0.999 --q 0.5 --margin 0 --quiet"
for m in flat.gltf nested.gltf packed.glb; do
  "$JND" texres "$T/$m" -o "$T/out_$m" --maps trim/baseColor,lid/baseColor --sizes 24 $L
  rc=$?
  check "$m: texres runs (exit 0 or 1)" [ $rc -le 1 ]
  "$JND" render "$T/out_$m/model/$m" --list-maps >"$T/list_$m.txt" 2>"$T/err.txt"
  check "$m: the copy loads" [ $? -eq 0 ]
  check "$m: every map read back has the size the report gives, and something changed" python3 - "$T/out_$m/texres.json" "$T/list_$m.txt" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))["result"]
back = {}
for line in open(sys.argv[2]):
    f = line.split()
    back[f[0]] = [int(f[1]), int(f[3])]
maps = {m["name"]: m["chosen"] for m in r["maps"]}
assert back == maps, (back, maps)
assert any(m["chosen"] != m["original"] for m in r["maps"]), "nothing was resized: the test says nothing"
PY
done
check "the unused and the variant-only materials keep their images; trim and body still share one image, at the size body (kept) needs" python3 - "$T/out_flat.gltf/model/flat.gltf" "$T/out_flat.gltf/texres.json" <<'PY'
import json, sys
g = json.load(open(sys.argv[1]))
img = lambda mat: g["images"][g["textures"][g["materials"][mat]["pbrMetallicRoughness"]["baseColorTexture"]["index"]]["source"]]["uri"]
assert img(0) == "flat_img0.png" and img(2) == "flat_img2.png" and img(1) == "flat_img1.png", [img(i) for i in range(5)]
assert img(3) == "flat_img1.png", "trim's image was split from body's: one GPU image became two"
maps = {m["name"]: m for m in json.load(open(sys.argv[2]))["result"]["maps"]}
assert maps["trim/baseColor"]["chosen"] == maps["trim/baseColor"]["original"] and maps["trim/baseColor"]["image"] == maps["body/baseColor"]["image"]
assert maps["lid/baseColor"]["chosen"] != maps["lid/baseColor"]["original"]
PY
finish
