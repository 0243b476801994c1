"""OBJ meshes for the end-to-end tests, with the standard library only.

sphere_obj(path, n=12, m=24): a unit UV sphere of n × m quads (two
triangles each, those at the poles degenerate), positions only: no texture
coordinates, no normals, no material. Import with PYTHONPATH set to this
folder, or run as `python3 meshwrite.py PATH [N M]`.
"""
import math
import sys


def sphere_obj(path, n=12, m=24):
    with open(path, "w") as f:
        for i in range(n + 1):
            t = math.pi * i / n
            for j in range(m):
                p = 2 * math.pi * j / m
                f.write("v %.6f %.6f %.6f\n" % (math.sin(t) * math.cos(p), math.cos(t), math.sin(t) * math.sin(p)))
        for i in range(n):
            for j in range(m):
                a, b = i * m + j + 1, i * m + (j + 1) % m + 1
                f.write("f %d %d %d\nf %d %d %d\n" % (a, a + m, b + m, a, b + m, b))


if __name__ == "__main__":
    sphere_obj(sys.argv[1], *(int(x) for x in sys.argv[2:4]))
