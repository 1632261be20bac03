#!/usr/bin/env python3
"""Per-pixel agreement of two estimates beyond their noise (docs/performance.md, "BDPT's floor on
the glass spheres").

An estimate is either several renders with different seeds (their mean, and the variance of that
mean from their spread) or a reference with its K independent parts of equal spp (variance of
the mean = their sample variance / K per value; for two halves ((h1 - h2) / 2)^2). For two unbiased estimates of the same image, the mean squared
difference per value equals the sum of their variances; the excess (MSD minus both variances)
estimates the squared bias between them, and is printed for the whole image, for the bright
pixels (reference luminance above 4x the median, as the bench's bright regions) and, with
--through, separately for the pixels seen through glass (where the light-tracing renders given
by --through are below a fifth of B, or of --bright-from: light tracing cannot see those) and
the others.

  pixel_excess.py --a bdpt_s*.exr --b-reference REF.exr --b-parts REF_part*.exr [--through lt_s*.exr]
  pixel_excess.py --a bdpt_s*.exr --b lt_s*.exr --bright-from REF.exr --through lt_s*.exr

Needs numpy and OpenEXR (the anchors' Python environment).
"""
import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "anchors"))
from emitter_calibration import read_exr as load  # noqa: E402  (R, G, B as float64)


def seeds(paths):
    if len(paths) < 2:
        sys.exit("an estimate from renders needs at least two seeds")
    x = np.stack([load(p) for p in paths])
    return x.mean(0), x.var(0, ddof=1) / len(paths)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--a", nargs="+", required=True, help="renders of estimate A (one per seed)")
    ap.add_argument("--b", nargs="+", help="renders of estimate B (one per seed)")
    ap.add_argument("--b-reference", help="estimate B as a reference image ...")
    ap.add_argument("--b-parts", nargs="+", help="... with its independent parts (two or more)")
    ap.add_argument("--through", nargs="+", help="light-tracing renders: marks pixels seen through glass")
    ap.add_argument("--bright-from", help="image whose luminance defines the bright pixels (default: B)")
    args = ap.parse_args()
    a, va = seeds(args.a)
    if args.b:
        b, vb = seeds(args.b)
    elif args.b_reference and args.b_parts:
        b = load(args.b_reference)
        _, vb = seeds(args.b_parts)
    else:
        sys.exit("give --b, or --b-reference with --b-parts")
    base = load(args.bright_from) if args.bright_from else b
    y = base @ np.array([0.2126, 0.7152, 0.0722])
    bright = y > 4 * np.median(y)
    excess = ((a - b) ** 2 - va - vb).mean(-1)  # per pixel, per value
    masks = [("all", np.ones_like(bright)), ("bright", bright)]
    if args.through:
        lt = np.stack([load(p) for p in args.through]).mean(0)
        through = lt.mean(-1) < 0.2 * base.mean(-1)
        masks += [("bright, seen through glass", bright & through),
                  ("bright, seen directly", bright & ~through)]
    print(f"{'pixels':28s} {'count':>6s} {'excess/value':>13s} {'share':>6s} {'mean(A-B)/B':>12s}")
    for name, m in masks:
        if not m.any():
            continue
        share = excess[m].sum() / excess.sum()
        rel = (a - b)[m].sum() / b[m].sum()
        print(f"{name:28s} {m.sum():6d} {excess[m].mean():13.3e} {share:6.2f} {rel:+12.4%}")
    print(f"(whole-image excess per value {excess.mean():.3e}; A's variance {va.mean():.3e}, "
          f"B's {vb.mean():.3e})")


if __name__ == "__main__":
    main()
