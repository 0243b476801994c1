#!/usr/bin/env bash
# jnd lod's memory is the bytes its GLB stores and a GPU holds (issue 25):
# an OBJ without uvs gets neither TEXCOORD_0 nor TANGENT (the validator's
# UNUSED_OBJECT) and is not charged for them; a textured, normal-mapped
# asset keeps both. The reported before/after bytes are recomputed here from
# the written GLB's accessors (count × components × 4 bytes, 32-bit
# indices), without jnd.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
command -v python3 >/dev/null || skip "needs python3"
need_renderer
SMALL=(--screens 320x240 --views 1 --map-size 64 --surface-samples 4096 --quiet
       --judge-views 1 --max-px 96 --tolerance 0.5 --far-coverage 0.05 --no-pop)

# a UV sphere without texture coordinates, as plain OBJ
python3 "$(dirname "$0")/meshwrite.py" "$T/ball.obj" 24 48

# the GLB's bytes, without jnd: every primitive of a level's mesh, its
# attributes and indices (count × components × component size); `mapped`
# says whether the asset's materials have a normal map
cat >"$T/check_glb.py" <<'PY'
import json, os, struct, sys
NCOMP = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}
SIZE = {5126: 4, 5125: 4, 5123: 2, 5121: 1}
rep, mapped = sys.argv[1], sys.argv[2] == "mapped"
r = json.load(open(rep))["result"]
data = open(os.path.join(os.path.dirname(rep), r["model"]["path"]), "rb").read()
g = json.loads(data[20:20 + struct.unpack("<I", data[12:16])[0]])
def accessor_bytes(i):
    a = g["accessors"][i]
    return a["count"] * NCOMP[a["type"]] * SIZE[a["componentType"]]
def level_bytes(level):
    mesh = g["meshes"][g["nodes"][level]["mesh"]]
    return sum(sum(accessor_bytes(a) for a in p["attributes"].values()) + accessor_bytes(p["indices"])
               for p in mesh["primitives"])
for m in g["meshes"]:
    for p in m["primitives"]:
        at = set(p["attributes"])
        if mapped:
            assert {"POSITION", "NORMAL", "TEXCOORD_0", "TANGENT"} <= at and "normalTexture" in g["materials"][p["material"]], at
        else:
            assert at == {"POSITION", "NORMAL"}, at
mem, lv = r["memory"], r["levels"]
assert mem["before_bytes"] == level_bytes(0), (mem["before_bytes"], level_bytes(0))
assert mem["after_bytes"] == level_bytes(mem["level"]), (mem["after_bytes"], level_bytes(mem["level"]))
assert 0 < mem["after_bytes"] <= mem["before_bytes"], mem
if not mapped:   # 24 bytes a vertex and 12 a triangle
    for k in (0, mem["level"]):
        assert 12 * lv[k]["triangles"] < level_bytes(k) <= 36 * lv[k]["triangles"] + 72, k
PY

expect_exit 0 "an OBJ without uvs runs" "$JND" lod "$T/ball.obj" -o "$T/ball" "${SMALL[@]}" --no-textures
check "its GLB has no TEXCOORD_0 or TANGENT, and the reported bytes are its levels' accessors" \
  python3 "$T/check_glb.py" "$T/ball/lod.json" plain
expect_exit 0 "a textured, normal-mapped asset runs" "$JND" lod builtin:sphere -o "$T/tex" "${SMALL[@]}"
check "its GLB keeps TEXCOORD_0 and TANGENT, and the reported bytes are its levels' accessors" \
  python3 "$T/check_glb.py" "$T/tex/lod.json" mapped
finish
