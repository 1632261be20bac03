#!/usr/bin/env python3
"""Open a spectral EXR written by `spectrace render --spectral-exr` with the OpenEXR Python
package (an independent reader) and check the Fichet-Pacanowski-Wilkie 2021 layout: header
attributes spectralLayoutVersion and emissiveUnits, emissive channels `S0.<nm>nm` with a comma
as decimal separator, evenly spaced, values finite and non-negative, image not black.

Usage: spectral_exr_check.py FILE.exr
Exit 0: passed; 1: failed; 0 with "SKIPPED" when the OpenEXR package is missing.
"""
import re
import sys

try:
    import OpenEXR  # pip install openexr (3.x)
    import numpy as np
except ImportError:
    print("SKIPPED: the Python packages OpenEXR (3.x) and numpy are needed (pip install openexr)")
    sys.exit(0)

CHANNEL = re.compile(r"^S0\.(\d+),(\d+)nm$")


def main(path):
    with OpenEXR.File(path) as f:
        header = f.header()
        channels = f.channels()
        errors = []
        version = header.get("spectralLayoutVersion")
        units = header.get("emissiveUnits")
        if version != "1.0":
            errors.append(f"spectralLayoutVersion is {version!r}, expected '1.0'")
        if units != "W.m^-2.sr^-1":
            errors.append(f"emissiveUnits is {units!r}, expected 'W.m^-2.sr^-1'")
        bins = []
        for name, ch in channels.items():
            m = CHANNEL.match(name)
            if m is None:
                errors.append(f"channel {name!r} is not an emissive S0.<nm>nm channel")
                continue
            bins.append((float(f"{m.group(1)}.{m.group(2)}"), np.asarray(ch.pixels, dtype=np.float64)))
        bins.sort(key=lambda b: b[0])
        if not bins:
            errors.append("no spectral channels")
        else:
            lam = np.array([b[0] for b in bins])
            step = np.diff(lam)
            if len(step) and np.max(np.abs(step - step[0])) > 1e-6 * step[0]:
                errors.append("wavelengths are not evenly spaced")
            cube = np.stack([b[1] for b in bins], axis=-1)
            if not np.all(np.isfinite(cube)):
                errors.append("non-finite values")
            if np.any(cube < 0):
                errors.append("negative values")
            if not np.any(cube > 0):
                errors.append("the image is black")
            mean = cube.reshape(-1, len(bins)).mean(axis=0)
            k = int(np.argmax(mean))
            print(
                f"{path}: {cube.shape[1]}x{cube.shape[0]} pixels, {len(bins)} wavelengths "
                f"{lam[0]}..{lam[-1]} nm, image-mean radiance peak {mean[k]:.6g} W/(m^2 sr nm) at {lam[k]} nm"
            )
    for e in errors:
        print(f"{path}: {e}")
    return 1 if errors else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
