#!/usr/bin/env python3
"""Write a UV sphere as a Wavefront OBJ with per-vertex normals (`v`, `vn`, `f v//vn`).

Used for scenes/bench/meshes/glass_sphere_r0.1.obj (the mesh variant of the glass-sphere
caustic, scenes/bench/glass_sphere_mesh.ron):

    python3 scripts/uv_sphere_obj.py --radius 0.1 --center 0 0.1 0 --rings 48 --segments 96 \
        > scenes/bench/meshes/glass_sphere_r0.1.obj

Standard library only. Vertices lie on the sphere; each vertex normal is the exact sphere
normal there (so interpolated shading normals differ from the flat facets' geometric normals).
Faces are wound counter-clockwise seen from outside (geometric normals point outwards).
"""
import argparse
import math


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--radius", type=float, default=0.1, help="radius (m)")
    ap.add_argument("--center", type=float, nargs=3, default=(0.0, 0.1, 0.0), help="centre (m)")
    ap.add_argument("--rings", type=int, default=48, help="latitude bands")
    ap.add_argument("--segments", type=int, default=96, help="longitude segments")
    a = ap.parse_args()
    cx, cy, cz = a.center
    r, nr, ns = a.radius, a.rings, a.segments
    print(f"# UV sphere r = {r} m at ({cx}, {cy}, {cz}), {nr} rings x {ns} segments")
    print("# written by scripts/uv_sphere_obj.py; normals = exact sphere normals")
    # Poles are single vertices (index 1 and the last); rings 1..nr-1 have ns vertices each.
    verts = [(0.0, 1.0, 0.0)]
    for i in range(1, nr):
        th = math.pi * i / nr
        for j in range(ns):
            ph = 2.0 * math.pi * j / ns
            verts.append((math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph)))
    verts.append((0.0, -1.0, 0.0))
    for x, y, z in verts:
        print(f"v {cx + r * x:.7f} {cy + r * y:.7f} {cz + r * z:.7f}")
    for x, y, z in verts:
        print(f"vn {x:.7f} {y:.7f} {z:.7f}")

    def ring(i, j):
        return 2 + (i - 1) * ns + (j % ns)

    last = len(verts)
    for j in range(ns):
        # Top cap: pole, then the first ring (counter-clockwise seen from +y outside).
        print(f"f 1//1 {ring(1, j + 1)}//{ring(1, j + 1)} {ring(1, j)}//{ring(1, j)}")
    for i in range(1, nr - 1):
        for j in range(ns):
            a_, b_ = ring(i, j), ring(i, j + 1)
            c_, d_ = ring(i + 1, j), ring(i + 1, j + 1)
            print(f"f {a_}//{a_} {b_}//{b_} {d_}//{d_}")
            print(f"f {a_}//{a_} {d_}//{d_} {c_}//{c_}")
    for j in range(ns):
        a_, b_ = ring(nr - 1, j), ring(nr - 1, j + 1)
        print(f"f {a_}//{a_} {b_}//{b_} {last}//{last}")


if __name__ == "__main__":
    main()
