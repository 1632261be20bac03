"""Write the triangle meshes of the bench suite's own scenes (scenes/bench/suite_meshes/):

    python3 scripts/anchors/make_bench_meshes.py

sphere_r0.15.ply: a UV sphere of radius 0.15 m centred at the origin, 40 rings x 80 segments,
exact sphere normals at the vertices (the scene file places it). Binary little-endian PLY
with x, y, z, nx, ny, nz and triangles; outward winding. Standard library only.
"""
import math, os, struct

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scenes", "bench",
                   "suite_meshes")


def uv_sphere(radius, rings, segments):
    verts, faces = [], []
    for i in range(rings + 1):
        th = math.pi * i / rings
        for j in range(segments):
            ph = 2 * math.pi * j / segments
            n = (math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph))
            verts.append((tuple(radius * c for c in n), n))
    idx = lambda i, j: i * segments + (j % segments)
    for i in range(rings):
        for j in range(segments):
            a, b, c, d = idx(i, j), idx(i, j + 1), idx(i + 1, j + 1), idx(i + 1, j)
            if i != 0:
                faces.append((a, b, c))
            if i != rings - 1:
                faces.append((a, c, d))
    return verts, faces


def write_ply(path, verts, faces):
    with open(path, "wb") as f:
        f.write(("ply\nformat binary_little_endian 1.0\nelement vertex %d\n"
                 "property float x\nproperty float y\nproperty float z\n"
                 "property float nx\nproperty float ny\nproperty float nz\n"
                 "element face %d\nproperty list uchar int vertex_indices\nend_header\n"
                 % (len(verts), len(faces))).encode())
        for p, n in verts:
            f.write(struct.pack("<6f", *p, *n))
        for t in faces:
            f.write(struct.pack("<B3i", 3, *t))


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    v, f = uv_sphere(0.15, 40, 80)
    write_ply(os.path.join(OUT, "sphere_r0.15.ply"), v, f)
    print(f"wrote sphere_r0.15.ply: {len(v)} vertices, {len(f)} triangles")
