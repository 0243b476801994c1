"""glTF test assets for the end-to-end tests, with the standard library only.

png_bytes(w, h, k): a w x h RGB PNG (bytes) of a smooth pattern that k varies.
write_glb(path, g, geo, images): writes the glTF dict g as one .glb whose
binary chunk holds geo (the bytes g's first bufferViews already point into)
and then each of images (PNG bytes), each image given its own bufferView;
g gets its images and buffers.
mip_chain_bytes(w, h, block): bytes of a w x h texture of block bytes per 4x4 block
with its mip chain (000 Table 2).
write_ball(path, images): a unit UV sphere of one material "ball" whose
images are its baseColor, metallicRoughness and occlusion (PNG bytes each).
uv_sphere(S, R): a unit UV sphere of S segments and R rings: (positions,
texcoords, indices) as flat lists (its normals are its positions); the
triangles of ring j come before those of ring j + 1 (2·S per ring).
Import with PYTHONPATH set to this folder.
"""
import json
import math
import struct
import zlib


def png_bytes(w, h, k):
    raw = bytearray()
    for y in range(h):
        raw.append(0)
        for x in range(w):
            raw.extend(max(0, min(255, int(round(v * 255)))) for v in
                       (0.5 + 0.45 * math.sin(x * (1.3 + 0.2 * k)), 0.5 + 0.45 * math.cos(y * (1.1 + 0.1 * k)),
                        0.2 + 0.15 * k))

    def chunk(t, b):
        return struct.pack('>I', len(b)) + t + b + struct.pack('>I', zlib.crc32(t + b) & 0xffffffff)

    return (b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 2, 0, 0, 0))
            + chunk(b'IDAT', zlib.compress(bytes(raw))) + chunk(b'IEND', b''))


def write_glb(path, g, geo, images):
    binary = bytearray(geo)
    g["images"] = []
    for b in images:
        while len(binary) % 4:
            binary.append(0)
        g["bufferViews"].append({"buffer": 0, "byteOffset": len(binary), "byteLength": len(b)})
        g["images"].append({"bufferView": len(g["bufferViews"]) - 1, "mimeType": "image/png"})
        binary += b
    while len(binary) % 4:
        binary.append(0)
    g["buffers"] = [{"byteLength": len(binary)}]
    js = json.dumps(g).encode()
    js += b" " * ((4 - len(js) % 4) % 4)
    open(path, "wb").write(b"glTF" + struct.pack("<II", 2, 12 + 8 + len(js) + 8 + len(binary))
                           + struct.pack("<I", len(js)) + b"JSON" + js
                           + struct.pack("<I", len(binary)) + b"BIN\x00" + bytes(binary))


def mip_chain_bytes(w, h, block):
    t = 0
    while True:
        t += ((w + 3) // 4) * ((h + 3) // 4) * block
        if w == 1 and h == 1:
            return t
        w, h = max(1, w // 2), max(1, h // 2)


def uv_sphere(S=32, R=16):
    pos, uv, idx = [], [], []
    for j in range(R + 1):
        for i in range(S + 1):
            t, p = math.pi * j / R, 2 * math.pi * i / S
            pos += [math.sin(t) * math.cos(p), math.cos(t), math.sin(t) * math.sin(p)]
            uv += [i / S, j / R]
    for j in range(R):
        for i in range(S):
            a, b = j * (S + 1) + i, (j + 1) * (S + 1) + i
            idx += [a, a + 1, b, a + 1, b + 1, b]
    return pos, uv, idx


def write_ball(path, images):
    pos, uv, idx = uv_sphere(32, 16)
    nv = len(pos) // 3
    geo = (struct.pack('<%df' % len(pos), *pos) * 2 + struct.pack('<%df' % len(uv), *uv)
           + struct.pack('<%dI' % len(idx), *idx))
    view = lambda off, n: {"buffer": 0, "byteOffset": off, "byteLength": n}
    g = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
         "bufferViews": [view(0, 12 * nv), view(12 * nv, 12 * nv), view(24 * nv, 8 * nv), view(32 * nv, 4 * len(idx))],
         "accessors": [{"bufferView": 0, "componentType": 5126, "count": nv, "type": "VEC3", "min": [-1, -1, -1],
                        "max": [1, 1, 1]},
                       {"bufferView": 1, "componentType": 5126, "count": nv, "type": "VEC3"},
                       {"bufferView": 2, "componentType": 5126, "count": nv, "type": "VEC2"},
                       {"bufferView": 3, "componentType": 5125, "count": len(idx), "type": "SCALAR"}],
         "textures": [{"source": 0}, {"source": 1}, {"source": 2}],
         "materials": [{"name": "ball", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                                                 "metallicRoughnessTexture": {"index": 1}},
                        "occlusionTexture": {"index": 2}}],
         "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3,
                                     "material": 0}]}]}
    write_glb(path, g, geo, images)
