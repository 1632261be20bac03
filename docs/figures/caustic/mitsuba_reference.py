"""An independent reference for scenes/caustic.ron: the same scene rendered by Mitsuba 3's spectral
path tracer (mitsuba from PyPI), so spectrace's caustic is judged against a renderer it shares no
code with. Everything is written out from scenes/caustic.ron by hand and must be kept in step with
it: geometry, the constant-IOR glass, the floor's 0.7, ColorChecker patch 13 ("blue", BabelColor
average, host/data/reflectance/), the lamp's D65 radiance normalised to ∫ = 1 over its table times
480 000, the camera (x field of view 45°, 160×120, box pixel filter), 16 bounces (Mitsuba counts
vertices: max_depth 17). Mitsuba's film convention (XYZ = ∫ L x̄ȳz̄ dλ / ∫ ȳ dλ, then linear sRGB)
is spectrace's.

    pip install mitsuba numpy           # seen with mitsuba 3.9.1
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1   # for llvm_* variants
    python docs/figures/caustic/mitsuba_reference.py --minutes 20 -o caustic_reference_mitsuba.exr

It renders chunks of --chunk-spp with distinct seeds and averages them, writing the running mean
after every chunk, until --minutes have passed.
"""
import argparse, csv, os, tempfile, time
import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
DATA = os.path.join(ROOT, "host", "data")


def read_table(path, column):
    rows = [r for r in csv.reader(l for l in open(path) if not l.startswith("#"))]
    header, body = rows[0], rows[1:]
    return [(float(r[0]), float(r[column])) for r in body]


def irregular(pairs, scale=1.0):
    return {"type": "irregular",
            "wavelengths": ", ".join(repr(w) for w, _ in pairs),
            "values": ", ".join(repr(v * scale) for _, v in pairs)}


def quad_obj(path, corner, e0, e1):
    c, e0, e1 = (np.asarray(x, dtype=float) for x in (corner, e0, e1))
    v = [c, c + e0, c + e0 + e1, c + e1]   # winding gives the normal e0 × e1, as in spectrace
    with open(path, "w") as f:
        for p in v:
            f.write("v %.9g %.9g %.9g\n" % tuple(p))
        f.write("f 1 2 3\nf 1 3 4\n")
    return path


def scene_dict(tmp):
    d65 = read_table(os.path.join(DATA, "illuminants", "d65.csv"), 1)
    w = np.array([p[0] for p in d65]); v = np.array([p[1] for p in d65])
    d65_integral = float(np.sum(0.5 * (v[1:] + v[:-1]) * np.diff(w)))   # linear interpolant
    blue = read_table(os.path.join(DATA, "reflectance", "colorchecker_babelcolor_average.csv"), 13)
    diffuse = lambda r: {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": r}}
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 17},
        "sensor": {
            "type": "perspective", "fov": 45.0, "fov_axis": "x",
            "to_world": mi.ScalarTransform4f().look_at(origin=[0, 1.6, 4.5], target=[0, 0.5, 0], up=[0, 1, 0]),
            "sampler": {"type": "independent"},
            "film": {"type": "hdrfilm", "width": 160, "height": 120, "rfilter": {"type": "box"},
                     "pixel_format": "rgb"},
        },
        "floor": {"type": "obj", "filename": quad_obj(os.path.join(tmp, "floor.obj"), (-2, 0, 2), (4, 0, 0), (0, 0, -4)),
                  "face_normals": True, "bsdf": diffuse({"type": "spectrum", "value": 0.7})},
        "back": {"type": "obj", "filename": quad_obj(os.path.join(tmp, "back.obj"), (-2, 0, -2), (4, 0, 0), (0, 3, 0)),
                 "face_normals": True, "bsdf": diffuse(irregular(blue))},
        "glass_ball": {"type": "sphere", "center": [0, 0.8, 0], "radius": 0.5,
                       "bsdf": {"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0}},
        "lamp": {"type": "obj",
                 "filename": quad_obj(os.path.join(tmp, "lamp.obj"), (-0.025, 2.6, -0.025), (0.05, 0, 0), (0, 0, 0.05)),
                 "face_normals": True,
                 "bsdf": {"type": "diffuse", "reflectance": {"type": "spectrum", "value": 0.0}},
                 "emitter": {"type": "area", "radiance": irregular(d65, 480000.0 / d65_integral)}},
    }


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--variant", default="llvm_ad_spectral")
    ap.add_argument("--minutes", type=float, default=20.0)
    ap.add_argument("--chunk-spp", type=int, default=1024)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("-o", "--output", default="caustic_reference_mitsuba.exr")
    a = ap.parse_args()
    import mitsuba as mi, drjit as dr
    mi.set_variant(a.variant)
    dr.set_thread_count(a.threads)
    with tempfile.TemporaryDirectory() as tmp:
        scene = mi.load_dict(scene_dict(tmp))
    acc, n, t0 = None, 0, time.perf_counter()
    while n == 0 or time.perf_counter() - t0 < a.minutes * 60:
        img = np.array(mi.render(scene, spp=a.chunk_spp, seed=1000 + n), dtype=np.float64)
        acc = img if acc is None else acc + img
        n += 1
        mi.util.write_bitmap(a.output, (acc / n).astype(np.float32))
        print(f"{n * a.chunk_spp} spp, {time.perf_counter() - t0:.0f} s, mean {(acc / n).reshape(-1, 3).mean(0)}", flush=True)
