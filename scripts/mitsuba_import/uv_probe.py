"""Print Mitsuba 3's texture coordinates (si.uv) where rays hit its analytic shapes.

The values `host/src/scene/mitsuba/tests.rs` (analytic_shapes_show_textures_as_mitsuba_does)
and `cube_mesh` in `host/src/scene/mitsuba/convert.rs` compare against. Mitsuba's bitmap reads
its image with v = 0 on the top row. Run with the anchors venv:

    /tmp/anchors-venv/bin/python scripts/mitsuba_import/uv_probe.py
"""
import mitsuba as mi

mi.set_variant("scalar_rgb")


def probe(shape, rays):
    scene = mi.load_dict({"type": "scene", "s": shape})
    for o, d in rays:
        si = scene.ray_intersect(mi.Ray3f(mi.Point3f(*o), mi.Vector3f(*d)))
        p = [round(x, 4) for x in si.p]
        print(f"  {shape['type']:9s} hit {p} uv ({si.uv[0]:.4f}, {si.uv[1]:.4f})")


down = (0, 0, -1)
print(f"Mitsuba {mi.__version__}")
probe({"type": "rectangle"}, [((x, y, 5), down) for x, y in
                              [(-0.9, -0.9), (0.9, -0.9), (-0.9, 0.9), (0.9, 0.9)]])
probe({"type": "rectangle", "flip_normals": True},
      [((x, y, 5), down) for x, y in [(-0.9, -0.9), (0.9, -0.9), (-0.9, 0.9)]])
probe({"type": "disk"}, [((x, y, 5), down) for x, y in
                         [(0.5, 0), (0, 0.5), (-0.5, 0), (0, -0.5), (0.9, 0.1), (0.1, 0.01)]])
probe({"type": "sphere"}, [((5, 0, 0), (-1, 0, 0)), ((0, 5, 0), (0, -1, 0)),
                           ((-5, 0, 0), (1, 0, 0)), ((0, -5, 0), (0, 1, 0)),
                           ((5, 0.01, 0.5), (-1, 0, 0)), ((5, -0.01, 0.5), (-1, 0, 0)),
                           ((0.3, 0.4, 5), down)])
rays = []
for axis in range(3):
    for s in (-1, 1):
        for a, b in [(-0.8, -0.8), (0.8, -0.8), (-0.8, 0.8)]:
            o, d = [0.0] * 3, [0.0] * 3
            o[axis], d[axis] = 5 * s, -s
            o[(axis + 1) % 3], o[(axis + 2) % 3] = a, b
            rays.append((tuple(o), tuple(d)))
probe({"type": "cube"}, rays)
