"""Mitsuba 3's own `plastic` and `roughplastic` numbers that `host/tests/material_plastic.rs`
compares spectrace's `plastic` / `rough_plastic` with.

Usage (the anchors venv):
  python plastic_bsdf.py values   # f(ωo, ωi) at a few pairs of directions (scalar_spectral, 550 nm)
  python plastic_bsdf.py albedo   # white-base albedo E[f·cos/pdf] by Mitsuba's own sampling

`values` prints, per material and pair (cos θ of the view direction ωo at azimuth 0, cos θ
and azimuth of the light direction ωi), f in 1/sr: Mitsuba's eval (which includes the cosine
of its `wo`, our ωi) divided by that cosine. `albedo` prints the mean and standard error of
Mitsuba's sample weights over 2·10⁵ samples (numpy's default_rng(1)) at cos θo 0.9, 0.5, 0.2,
azimuth 0.7, for a white base (int_ior 1.5, ext_ior 1)."""
import math
import sys
import mitsuba as mi

PAIRS = [(0.9, 0.3, 2.0), (0.5, 0.5, math.pi), (0.7, 0.7, math.pi), (0.2, 0.95, 1.0),
         (0.6, 0.6, math.pi + 0.2)]


def direction(mu, phi):
    s = math.sqrt(max(0.0, 1.0 - mu * mu))
    return mi.Vector3f(s * math.cos(phi), s * math.sin(phi), mu)


def surface(wo):
    si = mi.SurfaceInteraction3f()
    si.p = mi.Point3f(0, 0, 0)
    si.n = mi.Normal3f(0, 0, 1)
    si.sh_frame = mi.Frame3f(si.n)
    si.wi = wo
    return si


def values():
    mi.set_variant("scalar_spectral")
    half = {"type": "spectrum", "value": 0.5}
    materials = {
        "plastic_lin": {"type": "plastic", "int_ior": 1.5, "ext_ior": 1.0,
                        "diffuse_reflectance": half},
        "plastic_nonlin": {"type": "plastic", "int_ior": 1.9, "ext_ior": 1.0,
                           "nonlinear": True, "diffuse_reflectance": half},
        "rough_ggx": {"type": "roughplastic", "int_ior": 1.5, "ext_ior": 1.0, "alpha": 0.2,
                      "distribution": "ggx", "diffuse_reflectance": half},
        "rough_beckmann": {"type": "roughplastic", "int_ior": 1.5, "ext_ior": 1.0,
                           "alpha": 0.3, "distribution": "beckmann",
                           "diffuse_reflectance": half},
    }
    for name, d in materials.items():
        bsdf = mi.load_dict(d)
        for mo, mu_i, phi in PAIRS:
            si = surface(direction(mo, 0.0))
            si.wavelengths = mi.UnpolarizedSpectrum(550.0)
            v = bsdf.eval(mi.BSDFContext(), si, direction(mu_i, phi))
            print(f"{name:<15} mu_o {mo:.2f} mu_i {mu_i:.2f} phi {phi:.4f}  f {float(v[0]) / mu_i:.6e}")


def albedo():
    import numpy as np
    mi.set_variant("scalar_rgb")
    for dist, a in [("ggx", 0.1), ("ggx", 0.3), ("beckmann", 0.2)]:
        bsdf = mi.load_dict({"type": "roughplastic", "distribution": dist, "alpha": a,
                             "int_ior": 1.5, "ext_ior": 1.0,
                             "diffuse_reflectance": {"type": "rgb", "value": [1, 1, 1]}})
        out = []
        for mu in (0.9, 0.5, 0.2):
            si = surface(direction(mu, 0.7))
            u = np.random.default_rng(1).random((200000, 3))
            w = np.empty(len(u))
            for k, (a0, a1, a2) in enumerate(u):
                _, v = bsdf.sample(mi.BSDFContext(), si, float(a0), mi.Point2f(float(a1), float(a2)))
                w[k] = v[0]
            out.append(f"{w.mean():.4f}±{w.std() / math.sqrt(len(w)):.4f}")
        print(dist, a, out)


{"values": values, "albedo": albedo}[sys.argv[1] if len(sys.argv) > 1 else "values"]()
