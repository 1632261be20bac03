"""Render one of spectrace's benchmark scenes in an anchor renderer for a fixed wall-clock budget.

Used by `spectrace bench speed`; runs on its own too:

    python scripts/anchors/anchor_render.py --renderer mitsuba --scene cornell --seconds 10 \
        --threads 2 --out /tmp/mitsuba_cornell.exr
    python scripts/anchors/anchor_render.py --renderer luxcore --engine BIDIRCPU --scene caustic ...

Prints one JSON line: renderer, integrator, spp, seconds (sampling time, scene loading and
Mitsuba's JIT warm-up excluded, as for spectrace), file. Exits with status 3 and a message on
stderr when the renderer's Python module is not installed.

Setup: `python3 -m venv VENV && VENV/bin/pip install mitsuba pyluxcore numpy openexr`
(seen with mitsuba 3.9.1, drjit 1.5.0, pyluxcore 2.11.2, openexr 3.5.3); Mitsuba's llvm_*
variants need LLVM >= 16 (Debian: `apt-get install libllvm19`, then
`export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1`).

The scenes are written out by hand from the project's own data and must be kept in step with
it: the Cornell box from host/data/scenes/cornell_box.json (as the Mitsuba and LuxCore Cornell
scripts in the project's shared anchors directory do; LuxCore's screen-window shift and the
"first-bounce exact" RGB projection are taken from there), the caustic from scenes/caustic.ron
(as docs/figures/caustic/mitsuba_reference.py does for Mitsuba). Film convention as spectrace's:
XYZ = integral of L x y z over integral of y, then linear sRGB. LuxCore is an RGB renderer:
spectra are projected to linear sRGB under the scene's light; its Russian roulette is switched
off (with it, BIDIRCPU comes out 2-6% too bright on the Cornell box).
"""
import argparse, csv, json, math, os, struct, sys, tempfile, time

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
DATA = os.path.join(ROOT, "host", "data")

# Linear sRGB (D65) from CIE 1931 XYZ (the matrix Mitsuba 3 uses).
XYZ_TO_SRGB = [[3.240479, -1.537150, -0.498535],
               [-0.969256, 1.875991, 0.041556],
               [0.055648, -0.204043, 1.057311]]


def read_table(path, column):
    rows = [r for r in csv.reader(l for l in open(path) if not l.startswith("#"))]
    return [(float(r[0]), float(r[column])) for r in rows[1:]]


def interp(pairs, x):
    """Linear interpolation, 0 outside the table (as Mitsuba's irregular spectrum)."""
    if x < pairs[0][0] or x > pairs[-1][0]:
        return 0.0
    lo, hi = 0, len(pairs) - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if pairs[mid][0] <= x:
            lo = mid
        else:
            hi = mid
    (x0, y0), (x1, y1) = pairs[lo], pairs[hi]
    return y0 if x1 == x0 else y0 + (y1 - y0) * (x - x0) / (x1 - x0)


def srgb_of(spectra, scale=1.0):
    """Linear sRGB of the product of `spectra` (lists of (nm, value)) at 1 nm, 360-830 nm."""
    cmf = [read_table(os.path.join(DATA, "cie", "cie1931_2deg.csv"), c) for c in (1, 2, 3)]
    xyz, ysum = [0.0, 0.0, 0.0], 0.0
    for nm in range(360, 831):
        s = scale
        for sp in spectra:
            s *= interp(sp, nm)
        bars = [interp(c, nm) for c in cmf]
        for i in range(3):
            xyz[i] += s * bars[i]
        ysum += bars[1]
    xyz = [v / ysum for v in xyz]
    return [sum(XYZ_TO_SRGB[r][c] * xyz[c] for c in range(3)) for r in range(3)]


def constant(v):
    return [(360.0, v), (830.0, v)]


def irregular(pairs, scale=1.0):
    return {"type": "irregular", "wavelengths": ", ".join(repr(w) for w, _ in pairs),
            "values": ", ".join(repr(v * scale) for _, v in pairs)}


def write_ply(path, verts, faces, normals=None):
    with open(path, "wb") as f:
        props = "property float x\nproperty float y\nproperty float z\n"
        if normals is not None:
            props += "property float nx\nproperty float ny\nproperty float nz\n"
        f.write(("ply\nformat binary_little_endian 1.0\nelement vertex %d\n%selement face %d\n"
                 "property list uchar int vertex_indices\nend_header\n"
                 % (len(verts), props, len(faces))).encode())
        for i, v in enumerate(verts):
            f.write(struct.pack("<3f", *v))
            if normals is not None:
                f.write(struct.pack("<3f", *normals[i]))
        for fc in faces:
            f.write(struct.pack("<B3i", 3, *fc))
    return path


def quads_ply(path, quads):
    """Each quad (4 vertices, spectrace's winding) as triangles (0,1,2), (0,2,3)."""
    verts, faces = [], []
    for q in quads:
        b = len(verts)
        verts.extend(q)
        faces += [(b, b + 1, b + 2), (b, b + 2, b + 3)]
    return write_ply(path, verts, faces)


def quad(corner, e0, e1):
    c = corner
    return [c, [c[i] + e0[i] for i in range(3)], [c[i] + e0[i] + e1[i] for i in range(3)],
            [c[i] + e1[i] for i in range(3)]]


def sphere_ply(path, center, radius, n_theta=256, n_phi=512):
    """A finely tessellated sphere with smooth normals (LuxCore has no analytic sphere)."""
    verts, normals, faces = [], [], []
    for i in range(n_theta + 1):
        th = math.pi * i / n_theta
        for j in range(n_phi):
            ph = 2 * math.pi * j / n_phi
            n = (math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph))
            normals.append(n)
            verts.append(tuple(center[k] + radius * n[k] for k in range(3)))
    idx = lambda i, j: i * n_phi + (j % n_phi)
    for i in range(n_theta):
        for j in range(n_phi):
            a, b, c, d = idx(i, j), idx(i, j + 1), idx(i + 1, j + 1), idx(i + 1, j)
            if i != 0:
                faces.append((a, c, b))
            if i != n_theta - 1:
                faces.append((a, d, c))
    return write_ply(path, verts, faces, normals)


# ------------------------------------------------------------------------------------ scenes
def cornell(tmp):
    d = json.load(open(os.path.join(DATA, "scenes", "cornell_box.json")))
    cam = d["camera"]
    sp = d["spectra"]
    surfaces = []
    for name, s in d["surfaces"].items():
        surfaces.append((name, quads_ply(os.path.join(tmp, name + ".ply"), s["quads"]), s["material"]))
    w, h = cam["image_size"]
    return {
        "name": "cornell", "width": w, "height": h, "max_depth": 64,
        "camera": (cam["position"], cam["look_at"], cam["up"], cam["fov_deg"]),
        "light_spectrum": sp["light_emission"], "light_scale": 1.0,
        "reflectance": {m: sp[m] for m in ("white", "red", "green")},
        "surfaces": [(n, p, "light" if m == "light_emitter" else m) for n, p, m in surfaces],
        "spheres": [],
    }


def caustic(tmp):
    d65 = read_table(os.path.join(DATA, "illuminants", "d65.csv"), 1)
    integral = sum(0.5 * (d65[i][1] + d65[i + 1][1]) * (d65[i + 1][0] - d65[i][0])
                   for i in range(len(d65) - 1))
    blue = read_table(os.path.join(DATA, "reflectance", "colorchecker_babelcolor_average.csv"), 13)
    return {
        "name": "caustic", "width": 160, "height": 120, "max_depth": 16,
        "camera": ([0, 1.6, 4.5], [0, 0.5, 0], [0, 1, 0], 45.0),
        "light_spectrum": d65, "light_scale": 480000.0 / integral,
        "reflectance": {"floor": constant(0.7), "wall": blue},
        "surfaces": [
            ("floor", quads_ply(os.path.join(tmp, "floor.ply"), [quad([-2, 0, 2], [4, 0, 0], [0, 0, -4])]), "floor"),
            ("back", quads_ply(os.path.join(tmp, "back.ply"), [quad([-2, 0, -2], [4, 0, 0], [0, 3, 0])]), "wall"),
            ("lamp", quads_ply(os.path.join(tmp, "lamp.ply"),
                               [quad([-0.025, 2.6, -0.025], [0.05, 0, 0], [0, 0, 0.05])]), "light"),
        ],
        "spheres": [("glass_ball", [0, 0.8, 0], 0.5, 1.5)],
    }


# ------------------------------------------------------------------------------------ Mitsuba
def run_mitsuba(sc, args, tmp):
    import numpy as np
    import mitsuba as mi, drjit as dr
    mi.set_variant(args.variant)
    dr.set_thread_count(args.threads)
    pos, target, up, fov = sc["camera"]
    diffuse = lambda r: {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": irregular(r)}}
    scene = {
        "type": "scene",
        # Mitsuba counts vertices: spectrace's depth d is its d + 1.
        "integrator": {"type": "path", "max_depth": sc["max_depth"] + 1},
        "sensor": {
            "type": "perspective", "fov": fov, "fov_axis": "x",
            "to_world": mi.ScalarTransform4f().look_at(origin=pos, target=target, up=up),
            "sampler": {"type": "independent"},
            "film": {"type": "hdrfilm", "width": sc["width"], "height": sc["height"],
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        },
    }
    for name, path, mat in sc["surfaces"]:
        shape = {"type": "ply", "filename": path, "face_normals": True}
        if mat == "light":
            shape["bsdf"] = {"type": "diffuse", "reflectance": {"type": "spectrum", "value": 0.0}}
            shape["emitter"] = {"type": "area", "radiance": irregular(sc["light_spectrum"], sc["light_scale"])}
        else:
            shape["bsdf"] = diffuse(sc["reflectance"][mat])
        scene[name] = shape
    for name, c, r, ior in sc["spheres"]:
        scene[name] = {"type": "sphere", "center": c, "radius": r,
                       "bsdf": {"type": "dielectric", "int_ior": ior, "ext_ior": 1.0}}
    scene = mi.load_dict(scene)
    # JIT warm-up and calibration: a 1-spp and a 4-spp render; their rate sizes the timed render.
    np.array(mi.render(scene, spp=1, seed=1))
    t0 = time.perf_counter()
    np.array(mi.render(scene, spp=4, seed=2))
    rate = 4 / max(time.perf_counter() - t0, 1e-3)
    spp = args.spp if args.spp else max(1, int(rate * args.seconds))
    t0 = time.perf_counter()
    img = np.array(mi.render(scene, spp=spp, seed=args.seed), dtype=np.float64)
    secs = time.perf_counter() - t0
    return img, spp, secs, f"mitsuba {mi.__version__}", f"path ({args.variant})"


# ------------------------------------------------------------------------------------ LuxCore
def run_luxcore(sc, args, tmp):
    import numpy as np
    import OpenEXR  # noqa: F401  -- must come before pyluxcore (their bundled OpenEXR clashes)
    import pyluxcore
    pyluxcore.Init(lambda msg: None)
    pos, target, up, fov_x = sc["camera"]
    w, h = sc["width"], sc["height"]
    f = lambda v: " ".join("%.9g" % x for x in v)
    # LuxCore's field of view spans the shorter image side.
    fov = fov_x if w <= h else math.degrees(2 * math.atan(math.tan(math.radians(fov_x) / 2) * h / w))
    aspect = max(w, h) / min(w, h)
    sx, sy = (aspect, 1.0) if w >= h else (1.0, aspect)
    light = [(nm, v) for nm, v in sc["light_spectrum"]]
    light_rgb = srgb_of([light], sc["light_scale"])
    lines = [
        "scene.camera.type = perspective",
        f"scene.camera.lookat.orig = {f(pos)}", f"scene.camera.lookat.target = {f(target)}",
        f"scene.camera.up = {f(up)}", f"scene.camera.fieldofview = {fov:.9g}",
        # LuxCore's raster lands one pixel lower than Mitsuba's and spectrace's: shift one row.
        f"scene.camera.screenwindow = {-sx:.9g} {sx:.9g} {-sy - 2.0 / h:.9g} {sy - 2.0 / h:.9g}",
    ]
    for m, refl in sc["reflectance"].items():
        lit = srgb_of([refl, light], sc["light_scale"])
        kd = [min(max(lit[i] / light_rgb[i], 0.0), 1.0) for i in range(3)]
        lines += [f"scene.materials.{m}.type = matte", f"scene.materials.{m}.kd = {f(kd)}"]
    lines += ["scene.materials.light.type = matte", "scene.materials.light.kd = 0 0 0",
              f"scene.materials.light.emission = {f(light_rgb)}",
              "scene.materials.light.emission.gain = 1 1 1",
              "scene.materials.light.emission.power = 0", "scene.materials.light.emission.efficency = 0"]
    for name, c, r, ior in sc["spheres"]:
        path = sphere_ply(os.path.join(tmp, name + ".ply"), c, r)
        lines += [f"scene.materials.{name}.type = glass", f"scene.materials.{name}.kr = 1 1 1",
                  f"scene.materials.{name}.kt = 1 1 1", f"scene.materials.{name}.interiorior = {ior}",
                  f"scene.materials.{name}.exteriorior = 1.0",
                  f"scene.shapes.{name}.type = mesh", f'scene.shapes.{name}.ply = "{path}"',
                  f"scene.objects.{name}.shape = {name}", f"scene.objects.{name}.material = {name}"]
    for name, path, mat in sc["surfaces"]:
        lines += [f"scene.shapes.{name}.type = mesh", f'scene.shapes.{name}.ply = "{path}"',
                  f"scene.objects.{name}.shape = {name}", f"scene.objects.{name}.material = {mat}"]
    d = sc["max_depth"]
    config = [
        f"renderengine.type = {args.engine}", f"renderengine.seed = {args.seed + 1}",
        "sampler.type = RANDOM", f"native.threads.count = {args.threads}",
        f"film.width = {w}", f"film.height = {h}",
        "film.filter.type = BOX", "film.filter.width = 0.5",
        "film.outputs.0.type = RGB", "film.outputs.0.filename = unused.exr",
        # --spp: a fixed sample count (time unlimited), for checking that seeds change the
        # sample sequence; otherwise the time budget.
        f"batch.haltspp = {args.spp}", f"batch.halttime = {0 if args.spp else args.seconds}",
        f"path.maxdepth = {d}", f"light.maxdepth = {d}",
        f"path.pathdepth.total = {d}", f"path.pathdepth.diffuse = {d}",
        f"path.pathdepth.glossy = {d}", f"path.pathdepth.specular = {d}",
        "path.russianroulette.depth = 1000", "light.russianroulette.depth = 1000",
        "path.clamping.variance.maxvalue = 0",
        "film.noiseestimation.warmup = 1000000000",
    ]
    scene = pyluxcore.Scene()
    p = pyluxcore.Properties(); p.SetFromString("\n".join(lines) + "\n"); scene.Parse(p)
    c = pyluxcore.Properties(); c.SetFromString("\n".join(config) + "\n")
    session = pyluxcore.RenderSession(pyluxcore.RenderConfig(c, scene))
    t0 = time.perf_counter()
    session.Start()
    while True:  # halt conditions are only checked inside UpdateStats()
        time.sleep(0.005)
        session.UpdateStats()
        if session.HasDone():
            break
    secs = time.perf_counter() - t0
    # Samples taken (the pass counter lags behind for BIDIRCPU); as samples per pixel.
    samples = session.GetStats().Get("stats.renderengine.total.samplecount").GetFloat()
    spp = int(round(samples / (w * h)))
    buf = np.zeros((h, w, 3), dtype=np.float32)
    session.GetFilm().GetOutputFloat(pyluxcore.FilmOutputType.RGB, buf)
    session.Stop()
    return buf[::-1].astype(np.float64), spp, secs, f"luxcore {pyluxcore.Version()}", f"{args.engine} (RGB)"


def write_exr(path, rgb):
    import numpy as np
    import OpenEXR
    rgb = np.ascontiguousarray(rgb[..., :3].astype(np.float32))
    with OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage},
                      {"R": rgb[..., 0].copy(), "G": rgb[..., 1].copy(), "B": rgb[..., 2].copy()}) as f:
        f.write(path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--renderer", choices=["mitsuba", "luxcore"], required=True)
    ap.add_argument("--scene", choices=["cornell", "caustic"], required=True)
    ap.add_argument("--seconds", type=float, required=True)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--seed", type=int, default=0,
                    help="Mitsuba: mi.render's seed; LuxCore: renderengine.seed = SEED + 1. "
                         "Different seeds give independent "
                         "sample sequences (checked with --spp, docs/performance.md)")
    ap.add_argument("--spp", type=int, default=0,
                    help="render this many samples per pixel instead of the time budget")
    ap.add_argument("--variant", default="llvm_ad_spectral", help="Mitsuba variant")
    ap.add_argument("--engine", default="BIDIRCPU", help="LuxCore engine (BIDIRCPU, PATHCPU)")
    ap.add_argument("--out", required=True, help="output OpenEXR (linear sRGB R, G, B)")
    a = ap.parse_args()
    module = "mitsuba" if a.renderer == "mitsuba" else "pyluxcore"
    try:
        __import__("OpenEXR")
        __import__(module)
    except Exception as e:  # not installed, or its shared libraries missing
        print(f"{module} cannot be imported here ({e}); pip install {module} openexr", file=sys.stderr)
        sys.exit(3)
    with tempfile.TemporaryDirectory() as tmp:
        sc = cornell(tmp) if a.scene == "cornell" else caustic(tmp)
        run = run_mitsuba if a.renderer == "mitsuba" else run_luxcore
        img, spp, secs, renderer, integrator = run(sc, a, tmp)
    write_exr(a.out, img)
    print(json.dumps({"renderer": renderer, "integrator": integrator, "spp": spp,
                      "seconds": round(secs, 4), "file": a.out}), flush=True)


if __name__ == "__main__":
    main()
    sys.stdout.flush(); sys.stderr.flush()
    os._exit(0)  # pyluxcore 2.11 can crash during interpreter teardown; the results are written
