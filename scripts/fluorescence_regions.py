#!/usr/bin/env python3
"""Per-region RMSE of renders of scenes/fluorescence.ron against a reference.

    python scripts/fluorescence_regions.py REFERENCE.exr A.exr [B.exr ...]

Regions: the four 20 cm patches (projected from the scene file's geometry and camera:
position (0, 1, 1.4), looking at the origin, fov 40 degrees across the 160 pixel width),
each shrunk by one pixel so no edge pixel counts, the floor (everything else) and the whole
image. RMSE over the linear sRGB channels R, G, B, as `spectrace compare` computes it.
Needs numpy and OpenEXR.
"""
import sys

import numpy as np
import OpenEXR

PATCHES = {
    # name: (x0, x1) of the quad on the floor (y = 0.001), z from -0.1 to 0.1
    "yellow": (-0.55, -0.35),
    "yellow_twin": (-0.3, -0.1),
    "white": (0.1, 0.3),
    "white_twin": (0.35, 0.55),
}
W, H = 160, 96


def load(path):
    f = OpenEXR.InputFile(path)
    dw = f.header()["dataWindow"]
    w, h = dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1
    chans = [np.frombuffer(f.channel(c), dtype=np.float32).reshape(h, w) for c in "RGB"]
    return np.stack(chans, axis=-1).astype(np.float64)


def masks():
    pos = np.array([0.0, 1.0, 1.4])
    fwd = -pos / np.linalg.norm(pos)
    right = np.cross(fwd, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, fwd)
    tx = np.tan(np.radians(20.0))
    ty = tx * H / W
    out = {}
    yy, xx = np.mgrid[0:H, 0:W]
    # Ray through each pixel centre, hit with the plane y = 0.001.
    sx = ((xx + 0.5) / W * 2 - 1) * tx
    sy = (1 - (yy + 0.5) / H * 2) * ty
    d = fwd[None, None, :] + sx[..., None] * right + sy[..., None] * up
    t = (0.001 - pos[1]) / d[..., 1]
    p = pos + t[..., None] * d
    for name, (x0, x1) in PATCHES.items():
        m = (p[..., 0] > x0) & (p[..., 0] < x1) & (p[..., 2] > -0.1) & (p[..., 2] < 0.1)
        # shrink by one pixel
        core = m.copy()
        core[1:, :] &= m[:-1, :]
        core[:-1, :] &= m[1:, :]
        core[:, 1:] &= m[:, :-1]
        core[:, :-1] &= m[:, 1:]
        out[name] = core
    any_patch = np.zeros((H, W), bool)
    for name, (x0, x1) in PATCHES.items():
        any_patch |= (p[..., 0] > x0 - 0.02) & (p[..., 0] < x1 + 0.02) & (p[..., 2] > -0.12) & (p[..., 2] < 0.12)
    out["floor"] = ~any_patch
    out["whole"] = np.ones((H, W), bool)
    return out


def main():
    ref = load(sys.argv[1])
    ms = masks()
    print("image " + " ".join(f"{k:>12}" for k in ms))
    print("ref-mean " + " ".join(f"{ref[m].mean():12.5f}" for m in ms.values()))
    for path in sys.argv[2:]:
        img = load(path)
        row = []
        for m in ms.values():
            e = img[m] - ref[m]
            row.append(np.sqrt((e * e).mean()))
        print(path + " " + " ".join(f"{r:12.6f}" for r in row))


if __name__ == "__main__":
    main()
