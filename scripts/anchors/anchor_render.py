"""Render a spectrace benchmark scene in an anchor renderer (Mitsuba 3, LuxCore).

The scene is the one spectrace builds, exported once by `spectrace bench export SCENE --out DIR`
(DIR/scene.json and one PLY per object: world-space geometry in metres, spectra every nm from
360 to 830 nm, camera). This script turns it into each renderer's scene; it never describes a
scene itself. Used by `spectrace bench speed`; runs on its own too:

    python scripts/anchors/anchor_render.py configs
    python scripts/anchors/anchor_render.py render --scene-json DIR/scene.json \
        --config mitsuba-multijitter --budgets 1,2,4 --threads 2 --seed 0 --out-prefix /tmp/x
    python scripts/anchors/anchor_render.py reference --scene-json DIR/scene.json --spp 4096 \
        --out-prefix /tmp/ref      # eight independent parts and their mean (Mitsuba 3)
    python scripts/anchors/anchor_render.py describe --scene-json DIR/scene.json --renderer mitsuba

Every renderer gets the scene in one frame, translated and uniformly scaled (`anchor_frame`):
centred on the specular objects and scaled so their bounding box's diagonal is 100 units, or
the scene's own frame when it has none. Radiance images do not change under it; Mitsuba 3's
ray-origin offsets, absolute below one scene unit, then shrink to the least its relative
epsilon allows (see `FRAME_SIZE`). `describe` reports in the scene's own frame.

`render` prints one JSON line per budget: renderer, config, spp, seconds, load_seconds,
jit_seconds, file. One timer definition for every renderer: `seconds` runs from the start of
sampling to the image in memory. Scene loading (for LuxCore: until RenderSession.Start()
returns, its preprocessing included) is `load_seconds`. Mitsuba's sampling time is the execution time of its kernels (Dr.Jit's
kernel history); the rest of the render call's wall time (tracing the program, compiling it)
is `jit_seconds`. This leaves out of Mitsuba's time all it spends outside its kernels: the
comparison errs in its favour.

Configurations (`configs` lists them), each with Russian roulette at the renderer's default and
off (`-rroff`):
  mitsuba-{independent,multijitter,orthogonal,ldsampler}: Mitsuba 3 `path` in llvm_ad_spectral
      (its spectral path tracer; the sampler is the only difference), its film a `specfilm`
      recording the CIE 1931 1 nm table's X, Y, Z, turned into linear sRGB as spectrace does
      (`observer.py`, which says why not `hdrfilm`); references likewise, their EXR headers
      stating that colour convention;
  luxcore-bidir-{sobol,random,metropolis}: LuxCore BIDIRCPU with that sampler;
  luxcore-bidirvm: LuxCore BIDIRVMCPU (vertex merging; its default sampler).
LuxCore is an RGB renderer: every reflectance is projected to linear sRGB under the scene's
(first) emitter's spectrum, conductors become a `fresnelcolor` of their normal-incidence
reflectance under that light with GGX-like roughness `uroughness = alpha` (LuxCore's metal2
uses Schlick's distribution, whose r equals alpha squared of GGX); LuxCore has no analytic
sphere (a scene with one is refused for it). Where these projections are not exact the
benchmark's fit shows LuxCore's error floor and calls it biased.

Exit status 3 with a message on stderr when the renderer's Python module cannot be imported.
Setup: `python3 -m venv VENV && VENV/bin/pip install mitsuba pyluxcore numpy openexr`; Mitsuba's
llvm variants need LLVM >= 16 (Debian: `apt-get install libllvm19`; the script sets
DRJIT_LIBLLVM_PATH to /usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 when that exists and the
variable is unset).
"""
import argparse, json, math, os, sys, time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from observer import COLOUR, COLOUR_ATTRIBUTE, film_to_srgb, mitsuba_film, srgb_of_spectrum  # noqa: E402

FORMAT = "spectrace-bench-scene/1"

MITSUBA_SAMPLERS = ["independent", "multijitter", "orthogonal", "ldsampler"]
LUX_SAMPLERS = ["sobol", "random", "metropolis"]


def all_configs():
    out = []
    for s in MITSUBA_SAMPLERS:
        out += [f"mitsuba-{s}", f"mitsuba-{s}-rroff"]
    for s in LUX_SAMPLERS:
        out += [f"luxcore-bidir-{s}", f"luxcore-bidir-{s}-rroff"]
    out += ["luxcore-bidirvm", "luxcore-bidirvm-rroff"]
    return out


def parse_config(name):
    if name not in all_configs():
        raise SystemExit(f"unknown config {name!r}; known: {', '.join(all_configs())}")
    parts = name.split("-")
    rr_off = parts[-1] == "rroff"
    if rr_off:
        parts = parts[:-1]
    if parts[0] == "mitsuba":
        return {"renderer": "mitsuba", "sampler": parts[1], "rr_off": rr_off}
    if parts[1] == "bidirvm":
        return {"renderer": "luxcore", "engine": "BIDIRVMCPU", "sampler": None, "rr_off": rr_off}
    return {"renderer": "luxcore", "engine": "BIDIRCPU", "sampler": parts[2].upper(), "rr_off": rr_off}


def load_scene(path):
    sc = json.load(open(path))
    if sc.get("format") != FORMAT:
        raise SystemExit(f"{path}: not a {FORMAT} file (got {sc.get('format')!r}); "
                         "export it with `spectrace bench export`")
    sc["dir"] = os.path.dirname(os.path.abspath(path))
    return sc


# ---------------------------------------------------------------------------------- the frame
# The anchors render the scene in a similar frame (translated and uniformly scaled; radiance
# images are invariant under it: the emitters are given by radiance, there are no media and the
# camera's angles do not change). Why: Mitsuba 3 moves every spawned ray's origin
# (1 + max|p_i|)·1500·2^-24 scene units off the surface, an absolute 1e-4 m for a scene in
# metres near the origin. In a chain of specular vertices on a 0.1-m glass ball that is 0.1% of
# the radius and moves the lamp's images seen through the ball's grazing edge by up to 35%
# against the exact integral (docs/performance.md, "The glass spheres' reference"). Centred on the
# specular objects and scaled to FRAME_SIZE units, the offset falls to about 1e-4 of their size
# relative, and the same pixels agree with the exact integral within their noise.
FRAME_SIZE = 100.0


def ply_bounds(path):
    """Bounds of the vertices of a binary little-endian PLY as `spectrace bench export` writes
    it: the vertex element first, every vertex property a float, x y z first."""
    import numpy as np
    with open(path, "rb") as fh:
        elements = []  # [name, count, float properties]
        while True:
            line = fh.readline()
            if not line:
                raise SystemExit(f"{path}: PLY header without end_header")
            w = line.split()
            if w[:1] == [b"element"]:
                elements.append([w[1], int(w[2]), 0])
            elif w[:2] == [b"property", b"float"] and elements:
                elements[-1][2] += 1
            elif w[:1] == [b"end_header"]:
                break
        if not elements or elements[0][0] != b"vertex" or elements[0][2] < 3:
            raise SystemExit(f"{path}: the PLY does not start with float x y z vertices")
        _, n, props = elements[0]
        v = np.frombuffer(fh.read(4 * props * n), dtype="<f4")
        if v.size != props * n:
            raise SystemExit(f"{path}: {n} vertices announced, fewer stored")
        v = v.reshape(n, props)[:, :3].astype(np.float64)
    return v.min(0), v.max(0)


def shape_bounds(sc, s):
    if "sphere" in s:
        c, r = s["sphere"]["center"], s["sphere"]["radius"]
        return [x - r for x in c], [x + r for x in c]
    lo, hi = ply_bounds(os.path.join(sc["dir"], s["ply"]))
    return list(lo), list(hi)


def specular(m):
    return m["type"] == "dielectric" or (m["type"] == "conductor" and m["alpha"] == 0)


def anchor_frame(sc):
    """(centre, scale): the anchors' frame is x' = scale·(x − centre), centred on the bounds of
    the shapes with a specular material and scaled so their diagonal is FRAME_SIZE; the scene's
    own frame (centre 0, scale 1) when it has no specular shape (the offset moves a diffuse or
    rough surface's point by a negligible amount)."""
    spec = [s for s in sc["shapes"] if specular(sc["materials"][s["material"]])]
    if not spec:
        return [0.0, 0.0, 0.0], 1.0
    b = [shape_bounds(sc, s) for s in spec]
    lo = [min(x[0][k] for x in b) for k in range(3)]
    hi = [max(x[1][k] for x in b) for k in range(3)]
    diag = math.sqrt(sum((h - l) ** 2 for l, h in zip(lo, hi)))
    if not diag > 0:
        return [0.0, 0.0, 0.0], 1.0
    return [float(l + h) / 2 for l, h in zip(lo, hi)], float(FRAME_SIZE / diag)


def to_frame(frame, p):
    c, k = frame
    return [k * (x - ci) for x, ci in zip(p, c)]


def from_frame(frame, p):
    c, k = frame
    return [x / k + ci for x, ci in zip(p, c)]


# ------------------------------------------------------------------------------- spectra → RGB
def srgb_of(grid, values):
    """Linear sRGB of a spectrum on `grid` (nm): the CIE integral (`observer.py`)."""
    return [float(v) for v in srgb_of_spectrum(grid, values)]


def fresnel_conductor(cos_i, eta, k):
    """Unpolarised Fresnel reflectance of a conductor (complex IOR eta + ik) at cos_i."""
    n = complex(eta, k)
    sin2 = 1 - cos_i * cos_i
    cos_t = (1 - sin2 / (n * n)) ** 0.5
    rs = (cos_i - n * cos_t) / (cos_i + n * cos_t)
    rp = (n * cos_i - cos_t) / (n * cos_i + cos_t)
    return 0.5 * (abs(rs) ** 2 + abs(rp) ** 2)


def first_emitter(sc):
    for m in sc["materials"].values():
        if m["type"] == "emitter":
            return m["radiance"]
    raise SystemExit("the scene has no emitter")


# ------------------------------------------------------------------------------------- Mitsuba
def mitsuba_dict(sc, sampler, rr_off, mi):
    grid = sc["wavelengths_nm"]
    spec = lambda vals: {"type": "irregular", "wavelengths": ", ".join(repr(w) for w in grid),
                         "values": ", ".join(repr(v) for v in vals)}
    cam = sc["camera"]
    d = sc["max_depth"]
    frame = anchor_frame(sc)
    to_world = mi.ScalarTransform4f().scale(frame[1]) @ \
        mi.ScalarTransform4f().translate([-x for x in frame[0]])
    scene = {
        "type": "scene",
        # Mitsuba counts vertices (the camera's too): spectrace's depth d is its d + 1.
        "integrator": {"type": "path", "max_depth": d + 1,
                       **({"rr_depth": d + 2} if rr_off else {})},
        "sensor": {
            "type": "perspective", "fov": cam["fov_deg"], "fov_axis": cam["fov_axis"],
            "to_world": mi.ScalarTransform4f().look_at(origin=to_frame(frame, cam["position"]),
                                                       target=to_frame(frame, cam["look_at"]),
                                                       up=cam["up"]),
            "sampler": {"type": sampler},
            # The bands are the CIE 1931 1 nm table; `observer.film_to_srgb` makes the image.
            "film": mitsuba_film(sc["width"], sc["height"]),
        },
    }
    bsdfs = {}
    for name, m in sc["materials"].items():
        if m["type"] == "diffuse":
            b = {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": spec(m["reflectance"])}}
        elif m["type"] == "dielectric":
            b = {"type": "dielectric", "int_ior": m["ior"], "ext_ior": 1.0}
        elif m["type"] == "conductor":
            inner = {"type": "conductor", "eta": spec(m["eta"]), "k": spec(m["k"])}
            if m["alpha"] > 0:
                inner = {"type": "roughconductor", "distribution": "ggx", "alpha": m["alpha"],
                         "eta": spec(m["eta"]), "k": spec(m["k"])}
            b = {"type": "twosided", "bsdf": inner}
        elif m["type"] == "emitter":
            if m["two_sided"]:
                raise SystemExit(f"material {name}: Mitsuba's area emitter is one-sided")
            b = {"type": "diffuse", "reflectance": {"type": "spectrum", "value": 0.0}}
        else:
            raise SystemExit(f"material {name}: unknown type {m['type']}")
        bsdfs[name] = b
    for i, s in enumerate(sc["shapes"]):
        m = sc["materials"][s["material"]]
        if "sphere" in s:
            shape = {"type": "sphere", "center": to_frame(frame, s["sphere"]["center"]),
                     "radius": frame[1] * s["sphere"]["radius"]}
        else:
            shape = {"type": "ply", "filename": os.path.join(sc["dir"], s["ply"]),
                     "face_normals": not s["normals"], "to_world": to_world}
        shape["bsdf"] = bsdfs[s["material"]]
        if m["type"] == "emitter":
            shape["emitter"] = {"type": "area", "radiance": spec(m["radiance"])}
        shape["id"] = f"shape_{i}"
        scene[f"shape_{i}"] = shape
    return scene


def import_mitsuba(threads):
    lib = "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1"
    if "DRJIT_LIBLLVM_PATH" not in os.environ and os.path.exists(lib):
        os.environ["DRJIT_LIBLLVM_PATH"] = lib
    import mitsuba as mi, drjit as dr
    mi.set_variant("llvm_ad_spectral")
    dr.set_thread_count(threads)
    dr.set_flag(dr.JitFlag.KernelHistory, True)
    return mi, dr


def kernel_seconds(dr):
    """Execution time of the kernels launched since the last call, seconds (Dr.Jit's kernel
    history, in ms); clears the history."""
    return sum(k.get("execution_time", 0.0) for k in dr.kernel_history()) / 1000.0


def run_mitsuba(sc, cfg, args, budgets, out_prefix, spp_fixed=None):
    import numpy as np
    mi, dr = import_mitsuba(args.threads)
    t0 = time.perf_counter()
    scene = mi.load_dict(mitsuba_dict(sc, cfg["sampler"], cfg["rr_off"], mi))
    load = time.perf_counter() - t0
    dr.kernel_history()  # clear
    # Calibration (also compiles the kernels once): the rate at 4 spp sizes each budget.
    np.array(mi.render(scene, spp=1, seed=10_000 + args.seed))
    dr.kernel_history()  # clear: the calibration's time is the 4-spp render's alone
    t0 = time.perf_counter()
    np.array(mi.render(scene, spp=4, seed=20_000 + args.seed))
    wall = time.perf_counter() - t0
    rate = 4 / max(kernel_seconds(dr), 1e-3)
    results = []
    for i, b in enumerate(budgets):
        spp = spp_fixed or max(1, int(rate * b))
        dr.kernel_history()
        t0 = time.perf_counter()
        img = np.array(mi.render(scene, spp=spp, seed=args.seed * 1000 + i), dtype=np.float64)
        wall = time.perf_counter() - t0
        img = film_to_srgb(img)  # XYZ -> sRGB, 3×3 a pixel: microseconds, left out like loading
        secs = kernel_seconds(dr)
        sampler = scene.sensors()[0].sampler()
        results.append((img, {"spp": int(sampler.sample_count()), "requested_spp": spp,
                              "seconds": round(max(secs, 1e-6), 5),
                              "jit_seconds": round(max(wall - secs, 0.0), 4),
                              "load_seconds": round(load, 4), "budget": b}))
    return results, f"mitsuba {mi.__version__} llvm_ad_spectral path, sampler {cfg['sampler']}, " \
                    f"rr {'off' if cfg['rr_off'] else 'default (depth 5)'}"


# ------------------------------------------------------------------------------------- LuxCore
def luxcore_props(sc, cfg, args, budget):
    grid = sc["wavelengths_nm"]
    light = first_emitter(sc)
    light_rgb = srgb_of(grid, light)
    cam = sc["camera"]
    w, h = sc["width"], sc["height"]
    f = lambda v: " ".join("%.9g" % x for x in v)
    frame = anchor_frame(sc)
    k, c = frame[1], frame[0]
    # LuxCore reads a transformation's 16 numbers column by column.
    transformation = [k, 0, 0, 0, 0, k, 0, 0, 0, 0, k, 0, -k * c[0], -k * c[1], -k * c[2], 1]
    # LuxCore's field of view spans the shorter image side.
    fov_x = cam["fov_deg"]
    if cam["fov_axis"] == "y":
        fov_x = math.degrees(2 * math.atan(math.tan(math.radians(fov_x) / 2) * w / h))
    fov = fov_x if w <= h else math.degrees(2 * math.atan(math.tan(math.radians(fov_x) / 2) * h / w))
    aspect = max(w, h) / min(w, h)
    sx, sy = (aspect, 1.0) if w >= h else (1.0, aspect)
    lines = [
        "scene.camera.type = perspective",
        f"scene.camera.lookat.orig = {f(to_frame(frame, cam['position']))}",
        f"scene.camera.lookat.target = {f(to_frame(frame, cam['look_at']))}",
        f"scene.camera.up = {f(cam['up'])}", f"scene.camera.fieldofview = {fov:.9g}",
        # LuxCore's raster lands one pixel lower than Mitsuba's and spectrace's: shift one row.
        f"scene.camera.screenwindow = {-sx:.9g} {sx:.9g} {-sy - 2.0 / h:.9g} {sy - 2.0 / h:.9g}",
    ]
    under_light = lambda vals: [min(max(c / l, 0.0), 1.0) if l > 0 else 0.0 for c, l in
                                zip(srgb_of(grid, [v * e for v, e in zip(vals, light)]), light_rgb)]
    for name, m in sc["materials"].items():
        p = f"scene.materials.{name}"
        if m["type"] == "diffuse":
            lines += [f"{p}.type = matte", f"{p}.kd = {f(under_light(m['reflectance']))}"]
        elif m["type"] == "dielectric":
            lines += [f"{p}.type = glass", f"{p}.kr = 1 1 1", f"{p}.kt = 1 1 1",
                      f"{p}.interiorior = {m['ior']}", f"{p}.exteriorior = 1.0"]
        elif m["type"] == "conductor":
            r0 = [fresnel_conductor(1.0, n, k) for n, k in zip(m["eta"], m["k"])]
            lines += [f"scene.textures.{name}_fresnel.type = fresnelcolor",
                      f"scene.textures.{name}_fresnel.kr = {f(under_light(r0))}",
                      f"{p}.type = metal2", f"{p}.fresnel = {name}_fresnel",
                      f"{p}.uroughness = {max(m['alpha'], 1e-4):.9g}",
                      f"{p}.vroughness = {max(m['alpha'], 1e-4):.9g}"]
        elif m["type"] == "emitter":
            rgb = srgb_of(grid, m["radiance"])
            lines += [f"{p}.type = matte", f"{p}.kd = 0 0 0", f"{p}.emission = {f(rgb)}",
                      f"{p}.emission.gain = 1 1 1", f"{p}.emission.power = 0",
                      f"{p}.emission.efficency = 0"]
    for i, s in enumerate(sc["shapes"]):
        if "sphere" in s:
            raise SystemExit(f"shape {s['name']}: LuxCore has no analytic sphere; the bench scene "
                             "must use a mesh for every renderer")
        n = f"shape_{i}"
        lines += [f"scene.shapes.{n}.type = mesh",
                  f'scene.shapes.{n}.ply = "{os.path.join(sc["dir"], s["ply"])}"',
                  f"scene.objects.{n}.shape = {n}", f"scene.objects.{n}.material = {s['material']}",
                  f"scene.objects.{n}.transformation = {f(transformation)}"]
    d = sc["max_depth"]
    config = [
        f"renderengine.type = {cfg['engine']}", f"renderengine.seed = {args.seed + 1}",
        f"native.threads.count = {args.threads}",
        f"film.width = {w}", f"film.height = {h}",
        "film.filter.type = BOX", "film.filter.width = 0.5",
        "film.outputs.0.type = RGB", "film.outputs.0.filename = unused.exr",
        f"batch.halttime = {budget * 20 + 60}",  # a safety net; the script stops the session
        f"path.maxdepth = {d}", f"light.maxdepth = {d}",
        f"path.pathdepth.total = {d}", f"path.pathdepth.diffuse = {d}",
        f"path.pathdepth.glossy = {d}", f"path.pathdepth.specular = {d}",
        "path.clamping.variance.maxvalue = 0",
        "film.noiseestimation.warmup = 1000000000",
    ]
    if cfg["sampler"]:
        config.append(f"sampler.type = {cfg['sampler']}")
    if cfg["rr_off"]:
        config += ["path.russianroulette.depth = 1000", "light.russianroulette.depth = 1000"]
    return lines, config


def import_luxcore():
    import OpenEXR  # noqa: F401  -- must come before pyluxcore (their bundled OpenEXR clashes)
    import pyluxcore
    pyluxcore.Init(lambda msg: None)
    return pyluxcore


def run_luxcore(sc, cfg, args, budgets, out_prefix):
    import numpy as np
    lux = import_luxcore()
    w, h = sc["width"], sc["height"]
    results = []
    for b in budgets:
        lines, config = luxcore_props(sc, cfg, args, b)
        t0 = time.perf_counter()
        scene = lux.Scene()
        p = lux.Properties(); p.SetFromString("\n".join(lines) + "\n"); scene.Parse(p)
        c = lux.Properties(); c.SetFromString("\n".join(config) + "\n")
        session = lux.RenderSession(lux.RenderConfig(c, scene))
        session.Start()  # returns when the scene is prepared (BVH, light distributions)
        t_start = time.perf_counter()
        load = t_start - t0
        while time.perf_counter() - t_start < b:
            time.sleep(min(0.005, max(b - (time.perf_counter() - t_start), 0)))
        session.UpdateStats()
        samples = session.GetStats().Get("stats.renderengine.total.samplecount").GetFloat()
        buf = np.zeros((h, w, 3), dtype=np.float32)
        session.GetFilm().GetOutputFloat(lux.FilmOutputType.RGB, buf)
        secs = time.perf_counter() - t_start
        session.Stop()
        results.append((buf[::-1].astype(np.float64),
                        {"spp": round(samples / (w * h), 3), "seconds": round(secs, 5),
                         "load_seconds": round(load, 4), "jit_seconds": 0.0, "budget": b}))
    rr = "off" if cfg["rr_off"] else "default"
    return results, f"luxcore {lux.Version()} {cfg['engine']} sampler {cfg['sampler'] or 'default'}, " \
                    f"rr {rr} (RGB)"


# ------------------------------------------------------------------------------------ outputs
def write_exr(path, rgb, colour=None):
    """Linear sRGB as R, G, B; `colour` names the image's colour convention in the header
    attribute the bench checks on a reference (`observer.COLOUR_ATTRIBUTE`)."""
    import numpy as np
    import OpenEXR
    rgb = np.ascontiguousarray(rgb[..., :3].astype(np.float32))
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    if colour:
        header[COLOUR_ATTRIBUTE] = colour
    with OpenEXR.File(header,
                      {"R": rgb[..., 0].copy(), "G": rgb[..., 1].copy(), "B": rgb[..., 2].copy()}) as f:
        f.write(path)


def check_finite(img, what):
    import numpy as np
    bad = ~np.isfinite(img)
    if bad.any():
        y, x = np.argwhere(bad.any(axis=2))[0]
        raise SystemExit(f"{what}: {int(bad.any(axis=2).sum())} pixel(s) with a non-finite value, "
                         f"the first at ({x}, {y})")


def cmd_render(a):
    sc = load_scene(a.scene_json)
    cfg = parse_config(a.config)
    budgets = [float(x) for x in a.budgets.split(",")]
    if cfg["renderer"] == "mitsuba":
        results, desc = run_mitsuba(sc, cfg, a, budgets, a.out_prefix)
    else:
        results, desc = run_luxcore(sc, cfg, a, budgets, a.out_prefix)
    for i, (img, info) in enumerate(results):
        path = f"{a.out_prefix}_b{i}.exr"
        write_exr(path, img)  # written even when non-finite, for inspection
        check_finite(img, f"{a.config} at {info['budget']} s ({path})")
        print(json.dumps({"config": a.config, "renderer": desc, "file": path, **info}), flush=True)


def cmd_reference(a):
    """--parts independent Mitsuba renders (seeds differ) of --spp/parts each and their mean.
    The parts give the reference's own noise: eight give seven degrees of freedom per value
    where two halves give one, which matters for a path-traced caustic, whose per-pixel
    estimates are heavy-tailed (two halves typically underestimate its variance)."""
    import numpy as np
    sc = load_scene(a.scene_json)
    if a.parts < 2:
        raise SystemExit(f"--parts {a.parts}: at least two parts are needed for the noise")
    mi, dr = import_mitsuba(a.threads)
    scene = mi.load_dict(mitsuba_dict(sc, "independent", False, mi))
    part_spp = max(1, a.spp // a.parts)
    total, t0 = np.zeros((sc["height"], sc["width"], 3)), time.perf_counter()
    for k in range(a.parts):
        img = np.zeros((sc["height"], sc["width"], 3))
        # In passes of at most 1024 spp (memory), each pass with its own seed.
        done, p = 0, 0
        while done < part_spp:
            n = min(1024, part_spp - done)
            seed = 1_000_003 * (k + 1) + p + 4_000_037 * a.seed
            img += n * np.array(mi.render(scene, spp=n, seed=seed), dtype=np.float64)
            done += n
            p += 1
        img = film_to_srgb(img / part_spp)
        check_finite(img, f"reference part {k + 1}")
        total += img
        write_exr(f"{a.out_prefix}_part{k + 1}.exr", img, COLOUR)
    write_exr(f"{a.out_prefix}.exr", total / a.parts, COLOUR)
    print(json.dumps({"renderer": f"mitsuba {mi.__version__} llvm_ad_spectral path independent",
                      "spp": a.parts * part_spp, "parts": a.parts,
                      "seconds": round(time.perf_counter() - t0, 3),
                      "file": f"{a.out_prefix}.exr"}), flush=True)


def cmd_colour_factor(a):
    """Mitsuba's spectrum-to-RGB factor against the CIE integral (emitter_calibration.py): an
    equal-energy emitter filling the view, `--passes` renders of 16,384 spp."""
    import numpy as np
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from emitter_calibration import mitsuba_colour_factor
    mi, dr = import_mitsuba(a.threads)
    factor = mitsuba_colour_factor(mi, np.ones(471), 16384, a.passes)
    print(json.dumps({"renderer": f"mitsuba {mi.__version__} llvm_ad_spectral",
                      "factor": [round(float(f), 6) for f in factor],
                      "spp": 16384 * a.passes}), flush=True)


def cmd_describe(a):
    """What the renderer got, for the export test: per shape its bounds and triangle count, the
    materials' spectra at 450, 550 and 650 nm as the renderer evaluates them, the camera."""
    sc = load_scene(a.scene_json)
    frame = anchor_frame(sc)
    probe = [450.0, 550.0, 650.0]
    if a.renderer == "mitsuba":
        mi, dr = import_mitsuba(a.threads)
        # optimize=False: Mitsuba would merge the meshes that share a BSDF into one.
        scene = mi.load_dict(mitsuba_dict(sc, "independent", False, mi), optimize=False)
        shapes = {}
        for s in scene.shapes():
            i = int(s.id().split("_")[1])
            bb = s.bbox()
            entry = {"min": from_frame(frame, list(map(float, bb.min))),
                     "max": from_frame(frame, list(map(float, bb.max))),
                     "triangles": int(s.face_count()) if s.is_mesh() else 0}
            si = dr.zeros(mi.SurfaceInteraction3f)
            si.wavelengths = mi.Spectrum([probe[0], probe[1], probe[2], 500.0])
            si.n = mi.Normal3f(0, 0, 1)
            si.sh_frame = mi.Frame3f(si.n)
            si.wi = mi.Vector3f(0, 0, 1)
            bsdf = s.bsdf()
            if s.emitter() is not None:
                v = s.emitter().eval(si)
                entry["radiance"] = [float(dr.slice(v)[j]) for j in range(3)]
            elif mi.has_flag(bsdf.flags(), mi.BSDFFlags.DiffuseReflection):
                v = bsdf.eval_diffuse_reflectance(si)
                entry["reflectance"] = [float(dr.slice(v)[j]) for j in range(3)]
            shapes[sc["shapes"][i]["name"]] = entry
        sensor = scene.sensors()[0]
        m = sensor.world_transform().matrix
        params = mi.traverse(sensor)
        out = {"frame": {"centre": frame[0], "scale": frame[1]}, "shapes": shapes, "camera": {
            "origin": from_frame(frame, [float(dr.slice(m[r, 3])) for r in range(3)]),
            "forward": [float(dr.slice(m[r, 2])) for r in range(3)],
            "x_fov": float(dr.slice(params["x_fov"])) if "x_fov" in params else None},
            "size": [int(v) for v in sensor.film().size()]}
    else:
        lux = import_luxcore()
        lines, _ = luxcore_props(sc, parse_config("luxcore-bidir-sobol"), a, 1.0)
        scene = lux.Scene()
        p = lux.Properties(); p.SetFromString("\n".join(lines) + "\n"); scene.Parse(p)
        props = scene.ToProperties()
        get = lambda k: [float(x) for x in props.Get(k).GetFloats()] if props.IsDefined(k) else None
        objs = {}
        for i, s in enumerate(sc["shapes"]):
            objs[s["name"]] = {"defined": bool(scene.IsMeshDefined(f"shape_{i}"))
                               and bool(scene.IsMaterialDefined(s["material"]))}
        out = {"frame": {"centre": frame[0], "scale": frame[1]}, "shapes": objs,
               "objects": int(scene.GetObjectCount()),
               "camera": {"origin": from_frame(frame, get("scene.camera.lookat.orig")),
                          "target": from_frame(frame, get("scene.camera.lookat.target"))}}
    print(json.dumps(out), flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    sub.add_parser("configs", help="list the configurations")
    r = sub.add_parser("render", help="render at each budget")
    r.add_argument("--scene-json", required=True)
    r.add_argument("--config", required=True)
    r.add_argument("--budgets", required=True, help="comma-separated seconds")
    r.add_argument("--threads", type=int, default=2)
    r.add_argument("--seed", type=int, default=0)
    r.add_argument("--out-prefix", required=True)
    f = sub.add_parser("reference", help="long Mitsuba render in independent parts")
    f.add_argument("--scene-json", required=True)
    f.add_argument("--spp", type=int, required=True)
    f.add_argument("--threads", type=int, default=2)
    f.add_argument("--out-prefix", required=True)
    f.add_argument("--parts", type=int, default=8,
                   help="independent parts (PREFIX_partK.exr), for the reference's own noise")
    f.add_argument("--seed", type=int, default=0,
                   help="another seed gives another independent reference (0: the bench's)")
    c = sub.add_parser("colour-factor",
                       help="Mitsuba's spectrum-to-RGB conversion over the CIE integral")
    c.add_argument("--threads", type=int, default=2)
    c.add_argument("--passes", type=int, default=16)
    d = sub.add_parser("describe", help="what a renderer gets from the exported scene")
    d.add_argument("--scene-json", required=True)
    d.add_argument("--renderer", choices=["mitsuba", "luxcore"], required=True)
    d.add_argument("--threads", type=int, default=2)
    d.add_argument("--seed", type=int, default=0)
    a = ap.parse_args()
    if a.cmd == "configs":
        print("\n".join(all_configs()))
        return
    renderer = getattr(a, "renderer", None) or (parse_config(a.config)["renderer"]
                                                if a.cmd == "render" else "mitsuba")
    module = "mitsuba" if renderer == "mitsuba" else "pyluxcore"
    try:
        __import__("OpenEXR")
        __import__("numpy")
        if module == "mitsuba":
            import_mitsuba(getattr(a, "threads", 2))
        else:
            __import__(module)
    except Exception as e:  # not installed, or its shared libraries missing
        print(f"{module} cannot be imported here ({e}); pip install {module} openexr numpy",
              file=sys.stderr)
        sys.stdout.flush(); sys.stderr.flush()
        os._exit(3)
    {"render": cmd_render, "reference": cmd_reference, "describe": cmd_describe,
     "colour-factor": cmd_colour_factor}[a.cmd](a)


if __name__ == "__main__":
    try:
        main()
        code = 0
    except SystemExit as e:
        if isinstance(e.code, str):
            print(e.code, file=sys.stderr)
            code = 2
        else:
            code = e.code or 0
    sys.stdout.flush(); sys.stderr.flush()
    os._exit(code)  # pyluxcore 2.11 can crash during interpreter teardown; the results are written
