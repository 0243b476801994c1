#!/usr/bin/env python3
"""A multi-material glTF 2.0 asset for benchmarks and tests, made with the
standard library only: N parts (rounded-ish boxes and spheres on a grid),
each with its own material and four maps (baseColor, metallicRoughness,
normal, occlusion) of SIZE x SIZE pixels as PNG files beside the .gltf.

The parts differ in what their maps can lose: part k's finest detail has a
period of 2 << (k % 4) pixels, from 2-pixel speckle (visible at any lower
resolution) to 16-pixel (can shrink a lot); panel grooves and a low-frequency
paint mix are common to all. Deterministic in its arguments.

--shape real makes it look like a shipped asset instead (issue 29 item 2):
each material's occlusion, roughness and metal are packed into one
occlusion-roughness-metal image that both slots sample, materials k and
k + parts/2 share one normal map (a tiling detail normal), one material in
three is emissive with an image of its own, and every third part is thin: a
plate 1/20 as thick as it is wide, or a rod. With 6 parts: 6 materials, 26 map
slots, 17 unique images.

usage: make_asset.py OUT.gltf [--parts 6] [--size 512] [--seed 1] [--shape grid|real]
"""
import argparse
import json
import math
import os
import random
import struct
import zlib


def png(path, w, h, channels, rows):
    """rows: an iterable of h bytes objects of w * channels samples"""
    colour = {1: 0, 3: 2, 4: 6}[channels]
    raw = b"".join(b"\x00" + r for r in rows)

    def chunk(t, b):
        return struct.pack(">I", len(b)) + t + b + struct.pack(">I", zlib.crc32(t + b) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, colour, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def clamp8(v):
    return 0 if v < 0 else 255 if v > 1 else int(v * 255 + 0.5)


def periodic(rng, n, waves, lo, hi):
    """a tileable 1-D signal of n samples: a sum of sines of integer periods in [lo, hi] cycles"""
    parts = [(rng.randint(lo, hi), rng.random() * 2 * math.pi, rng.random()) for _ in range(waves)]
    total = sum(a for _, _, a in parts) or 1
    return [sum(a * math.sin(2 * math.pi * c * x / n + ph) for c, ph, a in parts) / total for x in range(n)]


def make_maps(folder, k, S, seed, packed=()):
    """packed: the slots of --shape real that part k writes (empty: --shape grid)"""
    rng = random.Random(seed * 1000 + k)
    period = 2 << (k % 4)                     # finest detail: 2, 4, 8, 16 pixels
    tiles = 4 + k % 3                         # panels per side
    lowx, lowy = periodic(rng, S, 3, 1, 3), periodic(rng, S, 3, 1, 3)
    # detail: random values on a lattice of `period` pixels, held (blocky speckle)
    cells = max(1, S // period)
    lat = [rng.random() for _ in range(cells * cells)]
    cx = [min(cells - 1, x // period) for x in range(S)]
    groove_x = [1 if (x * tiles) % S < max(2, S // 128) else 0 for x in range(S)]
    c1 = [0.55 + 0.3 * rng.random(), 0.25 + 0.3 * rng.random(), 0.15 + 0.2 * rng.random()]
    c2 = [0.15 + 0.2 * rng.random(), 0.3 + 0.3 * rng.random(), 0.45 + 0.3 * rng.random()]
    height = []
    base_rows, mr_rows, occ_rows = [], [], []
    for y in range(S):
        ly, gy, cy = lowy[y], (y * tiles) % S < max(2, S // 128), min(cells - 1, y // period) * cells
        hrow = [0.25 * lowx[x] * ly + 0.04 * lat[cy + cx[x]] - 0.5 * (gy or groove_x[x]) for x in range(S)]
        height.append(hrow)
        b = bytearray(3 * S)
        m = bytearray(3 * S)
        o = bytearray(S)
        for x in range(S):
            t = 0.5 + 0.5 * lowx[x] * ly
            d = lat[cy + cx[x]]
            g = gy or groove_x[x]
            sp = (0.7 + 0.6 * d) * (0.45 if g else 1.0)
            b[3 * x] = clamp8((c1[0] + (c2[0] - c1[0]) * t) * sp)
            b[3 * x + 1] = clamp8((c1[1] + (c2[1] - c1[1]) * t) * sp)
            b[3 * x + 2] = clamp8((c1[2] + (c2[2] - c1[2]) * t) * sp)
            m[3 * x] = 255
            m[3 * x + 1] = clamp8(0.35 + 0.4 * t + 0.2 * d)
            m[3 * x + 2] = 255 if (t > 0.8 and not g) else 0
            o[x] = clamp8(0.45 if g else 0.85 + 0.15 * d)
        base_rows.append(bytes(b))
        mr_rows.append(bytes(m))
        occ_rows.append(bytes(o))
    nrm_rows = []
    s = S / 48.0
    for y in range(S):
        hm, h0, hp = height[(y - 1) % S], height[y], height[(y + 1) % S]
        r = bytearray(3 * S)
        for x in range(S):
            dx = (h0[(x + 1) % S] - h0[(x - 1) % S]) * s
            dy = (hp[x] - hm[x]) * s
            l = math.sqrt(dx * dx + dy * dy + 1)
            r[3 * x] = clamp8(0.5 - 0.5 * dx / l)
            r[3 * x + 1] = clamp8(0.5 + 0.5 * dy / l)
            r[3 * x + 2] = clamp8(0.5 + 0.5 / l)
        nrm_rows.append(bytes(r))
    names = {}
    if packed:
        # occlusion in R, roughness in G, metal in B: one image for two slots
        orm_rows = [bytes(v for x in range(S) for v in (o[x], m[3 * x + 1], m[3 * x + 2]))
                    for o, m in zip(occ_rows, mr_rows)]
        emissive_rows = [bytes(v for x in range(S) for v in (b[3 * x] if b[3 * x + 2] > 150 else 0, 0, 0))
                         for b in base_rows]
        for slot, ch, rows in (("baseColor", 3, base_rows), ("orm", 3, orm_rows), ("normal", 3, nrm_rows),
                               ("emissive", 3, emissive_rows)):
            names[slot] = "part%d_%s.png" % (k, slot)
            if slot not in packed:
                continue
            png(os.path.join(folder, names[slot]), S, S, ch, rows)
        return names
    for slot, ch, rows in (("baseColor", 3, base_rows), ("metallicRoughness", 3, mr_rows), ("normal", 3, nrm_rows),
                           ("occlusion", 1, occ_rows)):
        names[slot] = "part%d_%s.png" % (k, slot)
        png(os.path.join(folder, names[slot]), S, S, ch, rows)
    return names


def box():
    pos, nrm, uv, idx = [], [], [], []
    faces = [((1, 0, 0), (0, 0, -1), (0, -1, 0)), ((-1, 0, 0), (0, 0, 1), (0, -1, 0)), ((0, 1, 0), (1, 0, 0), (0, 0, 1)),
             ((0, -1, 0), (1, 0, 0), (0, 0, -1)), ((0, 0, 1), (1, 0, 0), (0, -1, 0)), ((0, 0, -1), (-1, 0, 0), (0, -1, 0))]
    N = 8
    for n, u, v in faces:
        first = len(pos)
        for j in range(N + 1):
            for i in range(N + 1):
                a, b = 2 * i / N - 1, 2 * j / N - 1
                pos.append([n[q] + a * u[q] + b * v[q] for q in range(3)])
                nrm.append(list(n))
                uv.append([i / N, j / N])
        for j in range(N):
            for i in range(N):
                a = first + j * (N + 1) + i
                idx += [a, a + N + 1, a + 1, a + 1, a + N + 1, a + N + 2]
    return pos, nrm, uv, idx


def sphere():
    pos, nrm, uv, idx = [], [], [], []
    NU, NV = 48, 24
    for j in range(NV + 1):
        for i in range(NU + 1):
            th, ph = math.pi * j / NV, 2 * math.pi * i / NU
            n = [math.sin(th) * math.sin(ph), math.cos(th), math.sin(th) * math.cos(ph)]
            pos.append(n)
            nrm.append(n)
            uv.append([2.0 * i / NU, j / NV])
    for j in range(NV):
        for i in range(NU):
            a = j * (NU + 1) + i
            idx += [a, a + NU + 1, a + 1, a + 1, a + NU + 1, a + NU + 2]
    return pos, nrm, uv, idx


def real_material(k, parts, names, images, textures):
    """material k of --shape real: images are added once, by file name"""
    def texture(uri):
        for i, im in enumerate(images):
            if im["uri"] == uri:
                return next(t for t, tx in enumerate(textures) if tx["source"] == i)
        images.append({"uri": uri})
        textures.append({"source": len(images) - 1})
        return len(textures) - 1
    half = max(1, parts // 2)
    normal = "part%d_normal.png" % (k % half)   # materials k and k + parts/2 share it
    orm = texture(names["orm"])
    mat = {"name": "part%d" % k,
           "pbrMetallicRoughness": {"baseColorTexture": {"index": texture(names["baseColor"])},
                                    "metallicRoughnessTexture": {"index": orm}},
           "normalTexture": {"index": texture(normal)}, "occlusionTexture": {"index": orm}}
    if k % 3 == 0:
        mat["emissiveTexture"] = {"index": texture(names["emissive"])}
        mat["emissiveFactor"] = [1.0, 1.0, 1.0]
    return mat


def thin(k):
    """a plate 1/20 as thick as wide (k // 3 even) or a rod along x (odd)"""
    pos, nrm, uv, idx = box()
    sy, sz = (0.05, 1.0) if (k // 3) % 2 == 0 else (0.08, 0.08)
    pos = [[p[0], p[1] * sy, p[2] * sz] for p in pos]
    return pos, nrm, uv, idx


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--parts", type=int, default=6)
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--shape", choices=("grid", "real"), default="grid")
    a = ap.parse_args()
    real = a.shape == "real"
    folder = os.path.dirname(os.path.abspath(a.out))
    os.makedirs(folder, exist_ok=True)
    stem = os.path.splitext(os.path.basename(a.out))[0]
    cols = math.ceil(math.sqrt(a.parts))
    rows = (a.parts + cols - 1) // cols
    binary = bytearray()
    views, accessors, meshes, nodes, materials, images, textures = [], [], [], [], [], [], []

    def add(data, fmt, count, target, comp, typ, minmax=None):
        while len(binary) % 4:
            binary.append(0)
        off = len(binary)
        binary.extend(struct.pack("<%d%s" % (len(data), fmt), *data))
        views.append({"buffer": 0, "byteOffset": off, "byteLength": len(binary) - off, "target": target})
        acc = {"bufferView": len(views) - 1, "componentType": comp, "count": count, "type": typ}
        if minmax:
            acc["min"], acc["max"] = minmax
        accessors.append(acc)
        return len(accessors) - 1

    for k in range(a.parts):
        if real and k % 3 == 2:
            pos, nrm, uv, idx = thin(k)
        else:
            pos, nrm, uv, idx = box() if k % 2 == 0 else sphere()
        ox, oz = (k % cols - 0.5 * (cols - 1)) * 2.6, (k // cols - 0.5 * (rows - 1)) * 2.6
        pos = [[p[0] + ox, p[1], p[2] + oz] for p in pos]
        flat = [c for p in pos for c in p]
        mn = [min(p[q] for p in pos) for q in range(3)]
        mx = [max(p[q] for p in pos) for q in range(3)]
        ap_ = add(flat, "f", len(pos), 34962, 5126, "VEC3", (mn, mx))
        an = add([c for n in nrm for c in n], "f", len(nrm), 34962, 5126, "VEC3")
        at = add([c for t in uv for c in t], "f", len(uv), 34962, 5126, "VEC2")
        ai = add(idx, "I", len(idx), 34963, 5125, "SCALAR")
        written = ("baseColor", "orm") + (("normal",) if k < max(1, a.parts // 2) else ()) + \
            (("emissive",) if k % 3 == 0 else ())
        names = make_maps(folder, k, a.size, a.seed, packed=written if real else ())
        if real:
            materials.append(real_material(k, a.parts, names, images, textures))
            meshes.append({"primitives": [{"attributes": {"POSITION": ap_, "NORMAL": an, "TEXCOORD_0": at},
                                           "indices": ai, "material": k}]})
            nodes.append({"mesh": k})
            continue
        tex = {}
        for slot in ("baseColor", "metallicRoughness", "normal", "occlusion"):
            images.append({"uri": names[slot]})
            textures.append({"source": len(images) - 1})
            tex[slot] = len(textures) - 1
        materials.append({"name": "part%d" % k,
                          "pbrMetallicRoughness": {"baseColorTexture": {"index": tex["baseColor"]},
                                                   "metallicRoughnessTexture": {"index": tex["metallicRoughness"]}},
                          "normalTexture": {"index": tex["normal"]}, "occlusionTexture": {"index": tex["occlusion"]}})
        meshes.append({"primitives": [{"attributes": {"POSITION": ap_, "NORMAL": an, "TEXCOORD_0": at},
                                       "indices": ai, "material": k}]})
        nodes.append({"mesh": k})
    bin_name = stem + ".bin"
    with open(os.path.join(folder, bin_name), "wb") as f:
        f.write(binary)
    gltf = {"asset": {"version": "2.0", "generator": "jnd bench/make_asset.py"}, "scene": 0,
            "scenes": [{"nodes": list(range(a.parts))}], "nodes": nodes, "meshes": meshes, "materials": materials,
            "textures": textures, "images": images, "accessors": accessors, "bufferViews": views,
            "buffers": [{"uri": bin_name, "byteLength": len(binary)}]}
    with open(a.out, "w") as f:
        json.dump(gltf, f, indent=1)


if __name__ == "__main__":
    main()
