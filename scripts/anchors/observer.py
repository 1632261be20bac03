"""The one colour convention of every anchor image: spectrum -> CIE 1931 XYZ -> linear sRGB.

| quantity | definition |
|---|---|
| colour-matching functions | CIE 1931 2-degree, the 1 nm table spectrace ships (`host/data/cie/cie1931_2deg.csv`, 360-830 nm), linear between entries |
| normalisation | XYZ = integral of spectrum x cmf over the integral of y-bar (trapezoid rule, the same table) |
| XYZ -> sRGB | computed from the sRGB primaries and the D65 white's xy (IEC 61966-2-1), as `host/src/color/rgb_space.rs` computes it |

Why Mitsuba's images go through this and not through its `hdrfilm`: `hdrfilm` converts with the
CIE 1931 table at 5 nm steps, linearly interpolated (`mi.cie1931_xyz`), normalised by its own
constant (1 / 106.750; the 1 nm table's integral of y-bar is 106.857). The constant scales every
image by 1.001; the 5 nm table differs from the 1 nm one by up to 0.5% between its entries, which
a smooth spectrum averages out and a line spectrum does not: under CIE FL11 (lines at 435, 545 and
610 nm) on the spectral caustic's orange floor it moves R, G, B by +0.14%, -0.05%, +0.43% against
the 1 nm table (`python scripts/anchors/observer.py --compare SCENE_JSON`). Mitsuba's `specfilm`
with the 1 nm table as its three bands records the integrals themselves, at the same sampling cost.
"""
import functools
import os
import sys

# numpy is imported where it is used: `anchor_render.py configs` runs without it.

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
CMF_FILE = os.path.join(ROOT, "host", "data", "cie", "cie1931_2deg.csv")

# What a reference's header says of its colour (attribute COLOUR_ATTRIBUTE); `spectrace bench
# speed` refuses a reference without it (host/src/cli/bench_speed.rs, REFERENCE_COLOUR).
COLOUR_ATTRIBUTE = "spectraceBenchColour"
COLOUR = "CIE 1931 2-degree, 1 nm table, XYZ over the integral of y-bar, linear sRGB (D65)"

SRGB_PRIMARIES = [(0.64, 0.33), (0.30, 0.60), (0.15, 0.06)]
D65_XY = (0.3127, 0.3290)


@functools.cache
def cmf_table():
    """(wavelengths nm, (n, 3) x-bar, y-bar, z-bar) of the shipped table, read once (callers
    only read the arrays)."""
    import numpy as np
    d = np.genfromtxt(CMF_FILE, delimiter=",", comments="#", skip_header=2)
    return d[:, 0], d[:, 1:4]


def cmf_on(wl):
    """The colour-matching functions at wavelengths `wl` (nm), linear between table entries."""
    import numpy as np
    w, c = cmf_table()
    return np.stack([np.interp(wl, w, c[:, k], left=0.0, right=0.0) for k in range(3)], -1)


@functools.cache
def y_integral():
    """Integral of y-bar over the table, nm (trapezoid rule): 106.857 for CIE 1931 2-degree."""
    import numpy as np
    w, c = cmf_table()
    return float(np.trapezoid(c[:, 1], w))


@functools.cache
def xyz_to_srgb_matrix():
    """Linear sRGB from XYZ, computed from the primaries and the white's xy."""
    import numpy as np
    xyz = lambda x, y: np.array([x / y, 1.0, (1.0 - x - y) / y])
    p = np.stack([xyz(*c) for c in SRGB_PRIMARIES], -1)
    s = np.linalg.solve(p, xyz(*D65_XY))
    return np.linalg.inv(p * s)


def srgb_of_spectrum(wl, values):
    """Linear sRGB of a spectrum sampled at `wl` (nm), by the CIE integral (trapezoid rule)."""
    import numpy as np
    wl = np.asarray(wl, float)
    xyz = np.trapezoid(np.asarray(values, float)[:, None] * cmf_on(wl), wl, axis=0) / y_integral()
    return xyz_to_srgb_matrix() @ xyz


def mitsuba_film(width, height):
    """Mitsuba's `specfilm` whose bands X, Y, Z are the 1 nm table: each pixel records the
    integral of its spectrum times each band (box filter, as every renderer in the bench)."""
    import numpy as np
    w, c = cmf_table()
    if w[0] != 360 or w[-1] != 830 or np.any(np.diff(w) != 1):
        raise SystemExit(f"{CMF_FILE}: expected one row a nm from 360 to 830")
    band = lambda k: {"type": "regular", "wavelength_min": 360, "wavelength_max": 830,
                      "values": ",".join(f"{v:.9g}" for v in c[:, k])}
    return {"type": "specfilm", "width": width, "height": height, "rfilter": {"type": "box"},
            "X": band(0), "Y": band(1), "Z": band(2)}


def film_to_srgb(img):
    """Linear sRGB (h, w, 3) from a `mitsuba_film` image (its three band integrals)."""
    import numpy as np
    img = np.asarray(img, dtype=np.float64)
    if img.shape[-1] != 3:
        raise SystemExit(f"expected the film's three bands X, Y, Z, got {img.shape[-1]} channels")
    return (img / y_integral()) @ xyz_to_srgb_matrix().T


def compare(scene_json, spp=1024):
    """One Mitsuba render recording both tables' bands from the same paths: how far `hdrfilm`'s
    5 nm table would move each channel's image mean against the 1 nm table."""
    import numpy as np
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import anchor_render as ar
    mi, dr = ar.import_mitsuba(2)
    sc = ar.load_scene(scene_json)
    d = ar.mitsuba_dict(sc, "independent", False, mi)
    w, c = cmf_table()
    five = w % 5 == 0
    c5 = np.stack([np.interp(w, w[five], c[five, k]) for k in range(3)], -1)
    film = d["sensor"]["film"]
    for k, name in enumerate("XYZ"):
        film[f"{name}5"] = {"type": "regular", "wavelength_min": 360, "wavelength_max": 830,
                            "values": ",".join(f"{v:.9g}" for v in c5[:, k])}
    img = np.array(mi.render(mi.load_dict(d), spp=spp, seed=1), dtype=np.float64)
    # The film's channels come in the order its bands were given: X, Y, Z, X5, Y5, Z5.
    one, five5 = img[..., :3].reshape(-1, 3).mean(0), img[..., 3:].reshape(-1, 3).mean(0)
    print(f"{scene_json}: image mean, 1 nm table over 5 nm table, R G B = "
          f"{np.round((xyz_to_srgb_matrix() @ one) / (xyz_to_srgb_matrix() @ five5), 5)}")


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--compare":
        compare(sys.argv[2])
    else:
        sys.exit(__doc__)
