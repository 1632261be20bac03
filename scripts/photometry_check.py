#!/usr/bin/env python3
"""Independent reading of the real photometric files in host/data/photometry/.

Written separately from the Rust readers (host/src/photometry/) and sharing no code with them:
a second, plain-Python reading to check `spectrace luminaire` against. For each file it prints
the total flux (lm) and the candela at a few fixed angles. Its method:
  * IES: everything after the TILT= line is split on blanks and commas; the candela values are
    multiplied by the candela multiplier and the ballast factor (and the ballast-lamp factor
    for files without a 1995/2002/2019 version line).
  * EULUMDAT: lines read by position; cd = value x (first lamp set flux) / 1000 x conversion factor.
  * The full C-plane set 0..360 is rebuilt from the stored planes by symmetry, the candela at any
    angle is bilinear in (C, gamma), and the flux is the trapezoid rule over gamma of
    I sin(gamma) and over C (periodic) of that.
Run from the repository root: python3 scripts/photometry_check.py
"""
import math
import os

DIR = "host/data/photometry"
ANGLES = [(0.0, 0.0), (0.0, 30.0), (45.0, 30.0), (90.0, 60.0), (135.0, 45.0), (200.0, 20.0), (300.0, 75.0)]


def read_ies(path):
    raw = open(path, "rb").read().decode("latin-1")
    lines = raw.replace("\r", "").split("\n")
    first = next(l for l in lines if l.strip()).strip().upper()
    old = not (first.startswith("IESNA:") or first.startswith("IES:") or first == "IESNA95")
    k = next(i for i, l in enumerate(lines) if l.strip().upper().startswith("TILT="))
    if lines[k].strip().upper() != "TILT=NONE":
        raise SystemExit("only TILT=NONE in the real files")
    toks = " ".join(lines[k + 1:]).replace(",", " ").split()
    vals = []
    for t in toks:
        try:
            vals.append(float(t))
        except ValueError:
            pass  # END, 0x1A after the table
    nl, lm, mult, nv, nh, ptype, units, w, l, hgt, bf, blp, watts = vals[:13]
    nv, nh = int(nv), int(nh)
    assert int(ptype) == 1, "type C only in the real files"
    p = 13
    vang = vals[p:p + nv]; p += nv
    hang = vals[p:p + nh]; p += nh
    factor = mult * bf * (blp if old else 1.0)
    table = []
    for i in range(nh):
        table.append([x * factor for x in vals[p:p + nv]])
        p += nv
    return hang, vang, table


def read_ldt(path):
    lines = open(path, "rb").read().decode("latin-1").replace("\r", "").split("\n")
    num = lambda s: float(s.strip().replace(",", "."))
    isym = int(num(lines[2])); mc = int(num(lines[3])); ng = int(num(lines[5]))
    conv = num(lines[23])
    nsets = int(num(lines[25]))
    flux1 = num(lines[26 + 2])
    p = 26 + 6 * nsets + 10
    rest = [num(t) for l in lines[p:] for t in l.split()]
    cang = rest[:mc]; gang = rest[mc:mc + ng]; data = rest[mc + ng:]
    if isym == 0: idx = list(range(mc))
    elif isym == 1: idx = [0]
    elif isym == 2: idx = list(range(mc // 2 + 1))
    elif isym == 3: idx = list(range(mc // 4, mc // 4 + mc // 2 + 1))
    else: idx = list(range(mc // 4 + 1))
    table = []
    for n, _ in enumerate(idx):
        table.append([x * flux1 / 1000.0 * conv for x in data[n * ng:(n + 1) * ng]])
    return [cang[i] for i in idx], gang, table


def full_planes(hang, table):
    """All planes over [0, 360) as (angle, column) after applying the LM-63/EULUMDAT symmetry."""
    planes = {}
    def put(a, col):
        a = a % 360.0
        if abs(a - 360.0) < 1e-9:
            a = 0.0
        planes[round(a, 6)] = col
    first, last = hang[0], hang[-1]
    for a, col in zip(hang, table):
        put(a, col)
        if len(hang) == 1:
            continue
        if first == 0 and last == 90:
            put(180 - a, col); put(180 + a, col); put(360 - a, col)
        elif first == 0 and last == 180:
            put(360 - a, col)
        elif first == 90 and last == 270:
            put(180 - a, col)
    return sorted(planes.items())


def interp(xs, ys, x):
    if x < xs[0] - 1e-9 or x > xs[-1] + 1e-9:
        return 0.0
    for i in range(len(xs) - 1):
        if xs[i] - 1e-9 <= x <= xs[i + 1] + 1e-9:
            t = (x - xs[i]) / (xs[i + 1] - xs[i])
            return ys[i] + t * (ys[i + 1] - ys[i])
    return ys[-1]


def candela(planes, vang, c, g):
    if len(planes) == 1:
        return interp(vang, planes[0][1], g)
    angs = [a for a, _ in planes] + [planes[0][0] + 360.0]
    cols = [col for _, col in planes] + [planes[0][1]]
    c = c % 360.0
    for i in range(len(angs) - 1):
        if angs[i] <= c <= angs[i + 1]:
            t = (c - angs[i]) / (angs[i + 1] - angs[i])
            return (1 - t) * interp(vang, cols[i], g) + t * interp(vang, cols[i + 1], g)
    raise ValueError


def flux(planes, vang):
    def zone(col):
        s = 0.0
        for j in range(len(vang) - 1):
            a, b = math.radians(vang[j]), math.radians(vang[j + 1])
            s += 0.5 * (b - a) * (col[j] * math.sin(a) + col[j + 1] * math.sin(b))
        return s
    if len(planes) == 1:
        return 2 * math.pi * zone(planes[0][1])
    angs = [a for a, _ in planes] + [planes[0][0] + 360.0]
    zs = [zone(col) for _, col in planes] + [zone(planes[0][1])]
    return sum(0.5 * math.radians(angs[i + 1] - angs[i]) * (zs[i] + zs[i + 1]) for i in range(len(angs) - 1))


for name in sorted(os.listdir(DIR)):
    path = os.path.join(DIR, name)
    if name.endswith(".ies"):
        hang, vang, table = read_ies(path)
    elif name.endswith(".ldt"):
        hang, vang, table = read_ldt(path)
    else:
        continue
    planes = full_planes(hang, table)
    cds = ", ".join(f"({c}, {g}, {candela(planes, vang, c, g):.4f})" for c, g in ANGLES)
    print(f'("{name}", {flux(planes, vang):.4f}, &[{cds}]),')
