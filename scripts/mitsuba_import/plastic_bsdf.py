"""Mitsuba 3's own `plastic` and `roughplastic` BSDF values at a few pairs of directions, the
numbers `host/tests/material_plastic.rs` (`matches_mitsuba_3s_plastic_values`) compares
spectrace's `plastic` / `rough_plastic` with.

Usage: python plastic_bsdf.py   (the anchors venv; variant scalar_spectral, 550 nm)

Prints, per material and pair (cos θ of the view direction, cos θ and azimuth of the light
direction), f(ωo, ωi) in 1/sr: Mitsuba's eval (which includes the cosine of its `wo`, our ωi)
divided by that cosine."""
import math
import mitsuba as mi

mi.set_variant("scalar_spectral")

MATERIALS = {
    "plastic_lin": {"type": "plastic", "int_ior": 1.5, "ext_ior": 1.0,
                    "diffuse_reflectance": {"type": "spectrum", "value": 0.5}},
    "plastic_nonlin": {"type": "plastic", "int_ior": 1.9, "ext_ior": 1.0, "nonlinear": True,
                       "diffuse_reflectance": {"type": "spectrum", "value": 0.5}},
    "rough_ggx": {"type": "roughplastic", "int_ior": 1.5, "ext_ior": 1.0, "alpha": 0.2,
                  "distribution": "ggx",
                  "diffuse_reflectance": {"type": "spectrum", "value": 0.5}},
    "rough_beckmann": {"type": "roughplastic", "int_ior": 1.5, "ext_ior": 1.0, "alpha": 0.3,
                       "distribution": "beckmann",
                       "diffuse_reflectance": {"type": "spectrum", "value": 0.5}},
}
PAIRS = [(0.9, 0.3, 2.0), (0.5, 0.5, math.pi), (0.7, 0.7, math.pi), (0.2, 0.95, 1.0),
         (0.6, 0.6, math.pi + 0.2)]


def direction(mu, phi):
    s = math.sqrt(max(0.0, 1.0 - mu * mu))
    return mi.Vector3f(s * math.cos(phi), s * math.sin(phi), mu)


for name, d in MATERIALS.items():
    bsdf = mi.load_dict(d)
    for mo, mi_, phi in PAIRS:
        si = mi.SurfaceInteraction3f()
        si.p = mi.Point3f(0, 0, 0)
        si.n = mi.Normal3f(0, 0, 1)
        si.sh_frame = mi.Frame3f(si.n)
        si.wi = direction(mo, 0.0)
        si.wavelengths = mi.UnpolarizedSpectrum(550.0)
        wo = direction(mi_, phi)
        v = bsdf.eval(mi.BSDFContext(), si, wo)
        f = float(v[0]) / mi_
        print(f"{name:<15} mu_o {mo:.2f} mu_i {mi_:.2f} phi {phi:.4f}  f {f:.6e}")
