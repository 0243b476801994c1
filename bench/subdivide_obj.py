#!/usr/bin/env python3
"""Writes an OBJ with every triangle of IN split into 4 (edge midpoints), N
times: a dense mesh of the same shape for timing (bench_lod.sh). Reads
positions and triangle faces only (polygons are fanned); shared edges share
their midpoint, so the result is as connected as the input."""
import sys


def main():
    src, dst, times = sys.argv[1], sys.argv[2], int(sys.argv[3])
    verts, faces = [], []
    with open(src) as f:
        for line in f:
            p = line.split()
            if not p:
                continue
            if p[0] == "v":
                verts.append(tuple(float(x) for x in p[1:4]))
            elif p[0] == "f":
                idx = [int(q.split("/")[0]) for q in p[1:]]
                idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
                for k in range(1, len(idx) - 1):
                    faces.append((idx[0], idx[k], idx[k + 1]))
    for _ in range(times):
        mid, out = {}, []

        def m(a, b):
            key = (a, b) if a < b else (b, a)
            if key not in mid:
                va, vb = verts[a], verts[b]
                mid[key] = len(verts)
                verts.append(((va[0] + vb[0]) / 2, (va[1] + vb[1]) / 2, (va[2] + vb[2]) / 2))
            return mid[key]

        for a, b, c in faces:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            out += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
        faces = out
    with open(dst, "w") as f:
        f.write("".join("v %.7g %.7g %.7g\n" % v for v in verts))
        f.write("".join("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in faces))


if __name__ == "__main__":
    main()
