"""The memory a GPU holds for a glTF/GLB model, computed without jnd (issue
25): the unique images the default scene's materials sample (sizes read
from the PNG headers), each once with its mip chain, as RGBA8 and in each
image's block format. Used by tests/e2e/texres_memory.sh and
report_memory.sh."""
import json, os, struct

SLOTS = (("baseColor", ("pbrMetallicRoughness", "baseColorTexture")),
         ("metallicRoughness", ("pbrMetallicRoughness", "metallicRoughnessTexture")),
         ("normal", ("normalTexture",)), ("occlusion", ("occlusionTexture",)), ("emissive", ("emissiveTexture",)))
# bytes a 4×4 block of each slot's usual format (docs/texres.md): baseColor
# BC7 and normal BC5 16, the others (BC4, BC1) 8; RGBA8 4 a texel
BLOCK = {"baseColor": 16, "normal": 16, "metallicRoughness": 8, "occlusion": 8, "emissive": 8}

def load(path):
    data = open(path, "rb").read()
    if data[:4] == b"glTF":
        jl = struct.unpack("<I", data[12:16])[0]
        return json.loads(data[20:20 + jl]), data[20 + jl + 8:]
    return json.loads(data), None

def image_size(path, g, binary, i):
    im = g["images"][i]
    if "bufferView" in im:
        bv = g["bufferViews"][im["bufferView"]]
        head = binary[bv.get("byteOffset", 0):bv.get("byteOffset", 0) + 24]
    else:
        head = open(os.path.join(os.path.dirname(path), im["uri"]), "rb").read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n", head
    return struct.unpack(">II", head[16:24])

def chain(w, h, block):
    total = 0
    while True:
        total += 4 * w * h if block == 0 else ((w + 3) // 4) * ((h + 3) // 4) * block
        if w == 1 and h == 1: return total
        w, h = max(1, w // 2), max(1, h // 2)

def used(g):
    """image index -> (size, the slots "MATERIAL/SLOT" that sample it) over the default scene's materials"""
    mats = []
    def walk(n):
        node = g["nodes"][n]
        for c in node.get("children", []): walk(c)
        if "mesh" in node:
            for p in g["meshes"][node["mesh"]]["primitives"]:
                if "material" in p and p["material"] not in mats: mats.append(p["material"])
    for n in g["scenes"][g.get("scene", 0)]["nodes"]: walk(n)
    out = {}
    for m in mats:
        mat = g["materials"][m]
        for slot, keys in SLOTS:
            o = mat
            for k in keys: o = o.get(k, {}) if isinstance(o, dict) else {}
            if "index" in o:
                out.setdefault(g["textures"][o["index"]]["source"], []).append(mat["name"] + "/" + slot)
    return out

def memory(path):
    """RGBA8 and block-format bytes of the unique images, and {image: (size, slots)}"""
    g, binary = load(path)
    imgs = {i: (image_size(path, g, binary, i), slots) for i, slots in used(g).items()}
    rgba = sum(chain(*wh, 0) for wh, _ in imgs.values())
    block = sum(chain(*wh, max(BLOCK[s.split("/")[1]] for s in slots)) for wh, slots in imgs.values())
    return rgba, block, imgs, g
