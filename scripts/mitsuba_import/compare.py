"""Render a Mitsuba 3 XML scene in Mitsuba 3 and compare a spectrace render of the same file.

Usage:
  python compare.py render SCENE.xml OUT.exr --spp N [--variant llvm_ad_spectral] [--max-depth D] [-D name=value ...]
  python compare.py compare SPECTRACE.exr MITSUBA_REF.exr
`render` loads the file with Mitsuba's own parser (the -D values as its parameters) and writes its
linear sRGB film to OUT.exr; `compare` prints per-channel means, their ratio and the RMSE.
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


def render(a):
    import mitsuba as mi
    mi.set_variant(a.variant)
    params = dict(kv.split("=", 1) for kv in a.define)
    scene = mi.load_file(a.scene, **params)
    kw = {}
    if a.max_depth is not None:
        kw["integrator"] = mi.load_dict({"type": "path", "max_depth": a.max_depth})
    img = mi.render(scene, spp=a.spp, seed=a.seed, **kw)
    mi.Bitmap(img).write(a.out)
    print("wrote", a.out, "mean", np.asarray(img).reshape(-1, np.asarray(img).shape[-1]).mean(0)[:3])


def compare(a):
    ours, ref = read_exr(a.ours), read_exr(a.ref)
    if ours.shape != ref.shape:
        sys.exit(f"shape {ours.shape} differs from {ref.shape}")
    mo, mr = ours.reshape(-1, 3).mean(0), ref.reshape(-1, 3).mean(0)
    print("mean spectrace R,G,B:", np.round(mo, 5).tolist())
    print("mean mitsuba   R,G,B:", np.round(mr, 5).tolist())
    print("ratio          R,G,B:", np.round(mo / mr, 4).tolist())
    print(f"RMSE: {np.sqrt(((ours - ref) ** 2).mean()):.5f}")


p = argparse.ArgumentParser()
sub = p.add_subparsers(dest="cmd", required=True)
r = sub.add_parser("render")
r.add_argument("scene"); r.add_argument("out")
r.add_argument("--spp", type=int, required=True)
r.add_argument("--seed", type=int, default=0)
r.add_argument("--variant", default="llvm_ad_spectral")
r.add_argument("--max-depth", type=int)
r.add_argument("-D", dest="define", action="append", default=[])
c = sub.add_parser("compare"); c.add_argument("ours"); c.add_argument("ref")
a = p.parse_args()
render(a) if a.cmd == "render" else compare(a)
