#!/usr/bin/env python3
"""A stand-in for DamagedHelmet in `jnd budget`'s benchmark: the shared
data holds the helmet's texture set (five 2048 x 2048 maps: albedo,
metal-roughness, normal, occlusion, emissive) but not its mesh, so the set
is mapped on Spot (the shared data's textured cow, 5 856 triangles, its own
UVs) in one material. The textures do not fit Spot's UV layout, so what
the picture shows is not the helmet; what it measures is budget on an asset
of the helmet's shape: one material, five 2048-pixel maps, a chain made by
jnd. The images are copied beside the .gltf.

usage: helmet_standin.py OUT.gltf MESH.obj TEXSET_DIR
"""
import json
import os
import shutil
import struct
import sys

MAPS = ["Default_albedo.jpg", "Default_metalRoughness.jpg", "Default_normal.jpg", "Default_AO.jpg",
        "Default_emissive.jpg"]


def read_obj(path):
    """positions, uvs and triangle corners (position, uv indices) of a Wavefront OBJ"""
    v, vt, corners = [], [], []
    for line in open(path):
        a = line.split()
        if not a:
            continue
        if a[0] == "v":
            v.append(tuple(map(float, a[1:4])))
        elif a[0] == "vt":
            vt.append(tuple(map(float, a[1:3])))
        elif a[0] == "f":
            f = [tuple(int(x) if x else 0 for x in (c.split("/") + ["", ""])[:2]) for c in a[1:]]
            for i in range(1, len(f) - 1):   # a fan of triangles
                corners += [f[0], f[i], f[i + 1]]
    return v, vt, corners


def main():
    if len(sys.argv) != 4:
        print("usage: helmet_standin.py OUT.gltf MESH.obj TEXSET_DIR", file=sys.stderr)
        sys.exit(2)
    out, mesh, texset = sys.argv[1:4]
    for m in [mesh] + [os.path.join(texset, n) for n in MAPS]:
        if not os.path.isfile(m):
            print("helmet_standin.py: %s: no such file" % m, file=sys.stderr)
            sys.exit(2)
    if os.path.realpath(os.path.dirname(os.path.abspath(out))) == os.path.realpath(texset):
        print("helmet_standin.py: %s: the output would sit beside the texture set it copies" % out, file=sys.stderr)
        sys.exit(2)
    v, vt, corners = read_obj(mesh)
    key, pos, uv, idx = {}, [], [], []
    for c in corners:   # one vertex per distinct (position, uv) pair
        if c not in key:
            key[c] = len(pos)
            pos.append(v[c[0] - 1])
            uv.append(vt[c[1] - 1] if c[1] else (0.0, 0.0))
        idx.append(key[c])
    nv = len(pos)
    binary = bytearray()
    for p in pos:
        binary += struct.pack("<3f", *p)
    for t in uv:   # OBJ's v runs up, glTF's down
        binary += struct.pack("<2f", t[0], 1 - t[1])
    for i in idx:
        binary += struct.pack("<I", i)
    d = os.path.dirname(os.path.abspath(out))
    os.makedirs(d, exist_ok=True)
    stem = os.path.splitext(os.path.basename(out))[0]
    open(os.path.join(d, stem + ".bin"), "wb").write(binary)
    for m in MAPS:
        shutil.copyfile(os.path.join(texset, m), os.path.join(d, m))
    view = lambda off, n: {"buffer": 0, "byteOffset": off, "byteLength": n}
    g = {"asset": {"version": "2.0", "generator": "jnd bench/helmet_standin.py"}, "scene": 0,
         "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
         "buffers": [{"uri": stem + ".bin", "byteLength": len(binary)}],
         "bufferViews": [view(0, 12 * nv), view(12 * nv, 8 * nv), view(20 * nv, 4 * len(idx))],
         "accessors": [{"bufferView": 0, "componentType": 5126, "count": nv, "type": "VEC3",
                        "min": [min(p[k] for p in pos) for k in range(3)],
                        "max": [max(p[k] for p in pos) for k in range(3)]},
                       {"bufferView": 1, "componentType": 5126, "count": nv, "type": "VEC2"},
                       {"bufferView": 2, "componentType": 5125, "count": len(idx), "type": "SCALAR"}],
         "images": [{"uri": m} for m in MAPS],
         "textures": [{"source": i} for i in range(len(MAPS))],
         "materials": [{"name": "helmet",
                        "pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                                 "metallicRoughnessTexture": {"index": 1}},
                        "normalTexture": {"index": 2}, "occlusionTexture": {"index": 3},
                        "emissiveTexture": {"index": 4}, "emissiveFactor": [1, 1, 1]}],
         "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2,
                                     "material": 0}]}]}
    json.dump(g, open(out, "w"), indent=1)
    print("%s: %d vertices, %d triangles, %d maps" % (out, nv, len(idx) // 3, len(MAPS)))


if __name__ == "__main__":
    main()
