"""How each image converts a directly seen emitter's spectrum to linear sRGB, against the CIE
integral of the same spectrum.

The bench's references come from Mitsuba 3; a renderer whose spectrum-to-RGB conversion differs
by a constant factor differs from them by that factor everywhere, which the means table
(`spectrace bench speed`) reads as an offset. This measures the factor on the pixels where the
camera sees an emitter fully (value within 3% of the emitter's expected RGB), independently of
every renderer: the exported spectrum (`spectrace bench export`, every nm 360-830 nm) times the
CIE 1931 2-degree colour-matching functions (host/data/cie/cie1931_2deg.csv), trapezoid rule,
divided by the integral of y-bar, then the sRGB (D65) matrix of IEC 61966-2-1 (`observer.py`).

    python scripts/anchors/emitter_calibration.py DIR/scene.json IMAGE.exr [IMAGE.exr ...]

With `--mitsuba` instead, Mitsuba 3 (`llvm_ad_spectral`, the bench's variant, with the bench's
film: `observer.mitsuba_film`) renders an 8 x 8-pixel view filling with an area emitter of an
equal-energy and of a ramp spectrum (16,384 spp, box filter) and prints each image's mean
against the same CIE integral: the factor of its spectrum-to-RGB conversion (1 within the
wavelength sampling's noise since the film records the integrals themselves).

    python scripts/anchors/emitter_calibration.py --mitsuba
"""
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from observer import film_to_srgb, mitsuba_film, srgb_of_spectrum  # noqa: E402


def read_exr(path):
    import Imath
    import OpenEXR
    f = OpenEXR.InputFile(str(path))
    dw = f.header()["dataWindow"]
    w, h = dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1
    pt = Imath.PixelType(Imath.PixelType.FLOAT)
    return np.stack([np.frombuffer(f.channel(c, pt), dtype=np.float32).reshape(h, w)
                     for c in "RGB"], -1).astype(np.float64)


def expected_rgb(scene_json):
    """Linear sRGB of every emitter's radiance spectrum, by the CIE integral."""
    sc = json.loads(Path(scene_json).read_text())
    out = {}
    for name, m in sc["materials"].items():
        if "radiance" in m:
            out[name] = srgb_of_spectrum(sc["wavelengths_nm"], m["radiance"])
    return out


def flat_emitter_dict(mi, values, spp, seed=0):
    """An 8 x 8-pixel view filled by an area emitter of radiance `values` (every nm 360-830)."""
    spectrum = {"type": "regular", "wavelength_min": 360, "wavelength_max": 830,
                "values": ",".join(f"{v:.6f}" for v in values)}
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 2},
        "sensor": {"type": "perspective", "fov": 10,
                   "to_world": mi.ScalarTransform4f.look_at(origin=[0, 0, 5], target=[0, 0, 0],
                                                            up=[0, 1, 0]),
                   "film": mitsuba_film(8, 8),
                   "sampler": {"type": "independent", "sample_count": spp, "seed": seed}},
        "light": {"type": "rectangle", "emitter": {"type": "area", "radiance": spectrum}},
    }


def mitsuba_colour_factor(mi, values, spp=16384, passes=1):
    """Mitsuba's image of the emitter over the CIE integral of `values`, per channel."""
    expected = srgb_of_spectrum(np.arange(360, 831, 1.0), values)
    got = np.zeros(3)
    for p in range(passes):
        scene = mi.load_dict(flat_emitter_dict(mi, values, spp, seed=p))
        got += film_to_srgb(mi.render(scene)).reshape(-1, 3).mean(0)
    return got / passes / expected


def mitsuba_factor():
    import mitsuba as mi
    mi.set_variant("llvm_ad_spectral")
    wl = np.arange(360, 831, 1.0)
    for name, values in [("equal energy", np.ones_like(wl)), ("ramp", (wl - 300.0) / 100.0)]:
        factor = mitsuba_colour_factor(mi, values)
        print(f"mitsuba {mi.__version__} llvm_ad_spectral, {name}: image / CIE integral = "
              f"{np.round(factor, 5)}")


def main(argv):
    if len(argv) == 2 and argv[1] == "--mitsuba":
        mitsuba_factor()
        return
    if len(argv) < 3:
        sys.exit(__doc__)
    emitters = expected_rgb(argv[1])
    images = [(p, read_exr(p)) for p in argv[2:]]
    for name, rgb in emitters.items():
        print(f"emitter {name}: expected linear sRGB {np.round(rgb, 5)}")
        mask = None
        for _, img in images:
            m = np.abs(img / rgb - 1.0).max(-1) < 0.03
            mask = m if mask is None else mask & m
        if not mask.any():
            print("  no pixel sees it fully in every image")
            continue
        for path, img in images:
            ratio = img[mask].mean(0) / rgb
            print(f"  {path}: {mask.sum()} px, image / CIE integral = {np.round(ratio, 5)}")


if __name__ == "__main__":
    main(sys.argv)
