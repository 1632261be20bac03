"""Render a Mitsuba 3 XML scene in Mitsuba 3 and compare a spectrace render of the same file.

Usage:
  python compare.py render SCENE.xml OUT.exr --spp N [--variant llvm_ad_spectral] [--max-depth D]
                    [--size W H] [--threads T] [-D name=value ...]
  python compare.py mask SCENE.xml MASK.exr --size W H
  python compare.py compare SPECTRACE.exr MITSUBA_REF.exr [--mask MASK.exr] [--same-spp MITSUBA.exr]
`render` loads the file with Mitsuba's own parser (the -D values as its parameters) and writes its
linear sRGB film to OUT.exr; `--size` renders through a perspective camera of the file's first
sensor (same transform, same horizontal field of view) with a W × H film and Mitsuba's default
Gaussian filter, for scenes whose film size is not a parameter. `mask` writes Mitsuba's
`shape_index` AOV (the scene's shapes in file order, 0 where no shape is hit) averaged over 16
samples per pixel; pixels whose value is not a whole number are edges. `compare` prints
per-channel means, their ratio and the RMSE, per shape region when a mask is given (edges left
out), and, with `--same-spp`, Mitsuba's own RMSE at the spectrace render's sample count.
Needs the anchors venv (mitsuba, numpy, OpenEXR); the llvm variants need DRJIT_LIBLLVM_PATH."""
import sys, argparse
import numpy as np


def read_exr(path):
    import OpenEXR
    with OpenEXR.File(path) as f:
        ch = f.channels()
        if "RGB" in ch:
            return np.asarray(ch["RGB"].pixels, dtype=np.float64)
        return np.stack([np.asarray(ch[c].pixels, dtype=np.float64) for c in "RGB"], -1)


def sized_sensor(mi, scene, size, spp, rfilter="gaussian"):
    """A perspective camera like the scene's first sensor, with a W x H film."""
    s = scene.sensors()[0]
    fov = mi.traverse(s)["x_fov"]
    fov = float(fov[0] if hasattr(fov, "__len__") else fov)
    return mi.load_dict({
        "type": "perspective", "fov": fov, "fov_axis": "x",
        "to_world": mi.ScalarTransform4f(
            np.asarray(s.world_transform().matrix, dtype=np.float64).reshape(4, 4).tolist()),
        "film": {"type": "hdrfilm", "width": size[0], "height": size[1],
                 "rfilter": {"type": rfilter}, "pixel_format": "rgb"},
        "sampler": {"type": "independent", "sample_count": spp},
    })


def render(a):
    import mitsuba as mi
    if a.threads:
        import drjit as dr
        dr.set_thread_count(a.threads)
    mi.set_variant(a.variant)
    params = dict(kv.split("=", 1) for kv in a.define)
    scene = mi.load_file(a.scene, **params)
    kw = {}
    if a.max_depth is not None:
        kw["integrator"] = mi.load_dict({"type": "path", "max_depth": a.max_depth})
    if a.size:
        kw["sensor"] = sized_sensor(mi, scene, a.size, a.spp)
    img = mi.render(scene, spp=a.spp, seed=a.seed, **kw)
    mi.Bitmap(img).write(a.out)
    print("wrote", a.out, "mean", np.asarray(img).reshape(-1, np.asarray(img).shape[-1]).mean(0)[:3])


def mask(a):
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    scene = mi.load_file(a.scene)
    # Box filter: a pixel's value is the mean over its own area only.
    sensor = sized_sensor(mi, scene, a.size, 16, rfilter="box")
    integ = mi.load_dict({"type": "aov", "aovs": "si:shape_index"})
    img = np.asarray(mi.render(scene, sensor=sensor, integrator=integ, spp=16))
    m = img[..., -1]
    for i, sh in enumerate(scene.shapes()):
        print(i + 1, sh.id())
    mi.Bitmap(np.repeat(m[..., None], 3, -1).astype(np.float32)).write(a.out)


def stats(name, o, r, s=None):
    mo, mr = o.mean(0), r.mean(0)
    line = (f"{name:<14} n={len(o):>6}  spectrace {np.round(mo, 5).tolist()}  mitsuba "
            f"{np.round(mr, 5).tolist()}  ratio {np.round(mo / mr, 4).tolist()}  "
            f"RMSE {np.sqrt(((o - r) ** 2).mean()):.5f}")
    if s is not None:
        line += f"  (mitsuba same spp: ratio {np.round(s.mean(0) / mr, 4).tolist()}, RMSE {np.sqrt(((s - r) ** 2).mean()):.5f})"
    print(line)


def compare(a):
    ours, ref = read_exr(a.ours), read_exr(a.ref)
    if ours.shape != ref.shape:
        sys.exit(f"shape {ours.shape} differs from {ref.shape}")
    same = read_exr(a.same_spp).reshape(-1, 3) if a.same_spp else None
    o, r = ours.reshape(-1, 3), ref.reshape(-1, 3)
    stats("whole image", o, r, same)
    if a.mask:
        m = read_exr(a.mask)[..., 0].reshape(-1)
        whole = np.abs(m - np.round(m)) < 1e-3
        for k in np.unique(np.round(m[whole])).astype(int):
            sel = whole & (np.round(m) == k)
            stats("env (none)" if k == 0 else f"shape {k}", o[sel], r[sel],
                  same[sel] if same is not None else None)


p = argparse.ArgumentParser()
sub = p.add_subparsers(dest="cmd", required=True)
r = sub.add_parser("render")
r.add_argument("scene"); r.add_argument("out")
r.add_argument("--spp", type=int, required=True)
r.add_argument("--seed", type=int, default=0)
r.add_argument("--variant", default="llvm_ad_spectral")
r.add_argument("--max-depth", type=int)
r.add_argument("--size", type=int, nargs=2, metavar=("W", "H"))
r.add_argument("--threads", type=int)
r.add_argument("-D", dest="define", action="append", default=[])
m = sub.add_parser("mask"); m.add_argument("scene"); m.add_argument("out")
m.add_argument("--size", type=int, nargs=2, metavar=("W", "H"), required=True)
c = sub.add_parser("compare"); c.add_argument("ours"); c.add_argument("ref")
c.add_argument("--mask"); c.add_argument("--same-spp")
a = p.parse_args()
{"render": render, "mask": mask, "compare": compare}[a.cmd](a)
