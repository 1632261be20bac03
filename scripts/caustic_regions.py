"""Where the error of a caustic render sits: RMSE per region against the reference, the share of
the mean squared error that is colour (not luminance), and, with strategy images, each BDPT
strategy's share of the mean and its variance per region (docs/performance.md, "The caustic").

    python scripts/caustic_regions.py REFERENCE.exr A.exr [B.exr ...]
    python scripts/caustic_regions.py REFERENCE.exr --strategies DIR1 DIR2 ... -- WHOLE1.exr WHOLE2.exr ...

The second form takes the `--strategy-images` directories of renders with different seeds (and
optionally their whole images after `--`): per-pixel variances are taken across the seeds.

Regions (160x120 caustic scene, from the reference alone; see `regions`):
  lamp images  - the lamp seen in the ball (reflected at its top, refracted at its bottom): camera
                 paths ending on the lamp through the glass, only the s = 0 strategy renders them;
  caustic      - the floor caustic with its core (reference luminance > 0.08 on the floor rows,
                 dilated by one pixel); "core" is its part brighter than 1.0, which
                 `spectrace compare --exclude-light` (and the speed benchmark) leave out;
  rest         - everything else.
Needs numpy and OpenEXR (the anchors' venv has both).
"""
import glob
import os
import sys

import numpy as np
import OpenEXR
import Imath


def load(path):
    f = OpenEXR.InputFile(path)
    dw = f.header()["dataWindow"]
    w, h = dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1
    pt = Imath.PixelType(Imath.PixelType.FLOAT)
    return np.stack([np.frombuffer(f.channel(c, pt), np.float32).reshape(h, w) for c in "RGB"],
                    -1).astype(np.float64)


def lum(a):
    return 0.2126 * a[..., 0] + 0.7152 * a[..., 1] + 0.0722 * a[..., 2]


def dilate(m):
    p = np.pad(m, 1)
    out = np.zeros_like(m)
    for dy in range(3):
        for dx in range(3):
            out |= p[dy:dy + m.shape[0], dx:dx + m.shape[1]]
    return out


def regions(ref):
    h = ref.shape[0]
    floor_row = int(round(h * 70 / 120))  # the ball's lowest point is above this row
    yy = np.mgrid[0:h, 0:ref.shape[1]][0]
    big = lum(ref)
    lamp = dilate((yy < floor_row) & (big > 0.08)) & (yy < floor_row)
    caustic = dilate((yy >= floor_row) & (big > 0.08)) & (yy >= floor_row)
    core = (yy >= floor_row) & (big > 1.0)
    rest = ~lamp & ~caustic
    return [("lamp images", lamp), ("caustic", caustic), ("core", core), ("rest", rest)]


def rmse(img, ref, m):
    return np.sqrt(((img - ref) ** 2)[m].mean())


def main():
    ref = load(sys.argv[1])
    regs = regions(ref)
    args = sys.argv[2:]
    print("pixels: " + ", ".join(f"{n} {m.sum()}" for n, m in regs))
    if args and args[0] == "--strategies":
        dirs, wholes = args[1:], []
        if "--" in dirs:
            i = dirs.index("--")
            dirs, wholes = dirs[:i], dirs[i + 1:]
        names = sorted(os.path.basename(p) for p in glob.glob(os.path.join(dirs[0], "strategy_*.exr")))
        rows = []
        for n in names:
            imgs = np.stack([lum(load(os.path.join(d, n))) for d in dirs])
            mean, var = imgs.mean(0), imgs.var(0, ddof=1)
            rows.append((n[len("strategy_"):-4], [(mean[m].mean(), var[m].mean()) for _, m in regs]))
        tot = [sum(r[1][i][0] for r in rows) for i in range(len(regs))]
        print("strategy: per region, share of the mean luminance and mean pixel variance")
        for name, vals in rows:
            if max(abs(vals[i][0]) / max(tot[i], 1e-12) for i in range(len(regs))) < 0.005:
                continue
            print(f"  {name:8s} " + "  ".join(
                f"{regs[i][0]}: {vals[i][0] / tot[i]:.3f} {vals[i][1]:.2e}" for i in range(len(regs))))
        if wholes:
            v = np.stack([lum(load(p)) for p in wholes]).var(0, ddof=1)
            print("  whole    " + "  ".join(f"{n}: {v[m].mean():.2e}" for n, m in regs))
        return
    for p in args:
        img = load(p)
        d = img - ref
        parts = [f"{n} {rmse(img, ref, m):.5f}" for n, m in regs]
        colour = []
        for n, m in regs[1:2] + regs[3:4]:
            tot = (d[m] ** 2).mean()
            grey = (d[m].mean(-1) ** 2).mean()
            colour.append(f"{n} {1 - grey / tot:.2f}")
        print(f"{p}: RMSE " + ", ".join(parts) + "; colour share of MSE: " + ", ".join(colour))


if __name__ == "__main__":
    main()
