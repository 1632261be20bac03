#!/usr/bin/env python3
"""Independent colour of the bundled bispectral matrices (host/data/fluorescence/*.BFC).

Plain sums over the files' own 10 nm grid, written apart from the Rust code (which integrates
on a 1 nm grid with interpolated illuminants and band-integrated excitation):
  D cleaned: diagonal max(0, D); off-diagonal kept where emission > excitation and D > 0.
  S(lo) = sum_i D(lo, li) E(li)        (E at the excitation nodes, read from the CSV)
  k = 100 / sum_lo E(lo) ybar(lo)      (over the emission grid, 380..780 nm)
  X = k sum_lo S(lo) xbar(lo), etc.    (CIE 1931 2 deg CMFs at the 10 nm nodes)
Prints, per file and illuminant: X Y Z x y of the total, and of the reflected part alone.
Run from the repository root: python3 host/tests/data/bfc_colour_reference.py
"""
import csv, glob, os

def table(path, cols):
    out = {}
    with open(path) as f:
        rows = [r for r in csv.reader(l for l in f if not l.startswith('#'))]
    for r in rows[1:]:
        out[float(r[0])] = [float(r[c]) for c in cols]
    return out

cmf = table('host/data/cie/cie1931_2deg.csv', [1, 2, 3])
ill = {n: {k: v[0] for k, v in table('host/data/illuminants/%s.csv' % n, [1]).items()} for n in ('d65', 'a')}

def read_bfc(path):
    lines = [l.strip() for l in open(path, newline='').read().splitlines()]
    i = lines.index('BFC-450 Matrix File') + 1
    while lines[i].startswith(';'):
        i += 1
    i += 1  # grid header
    exc = [float(v) for v in lines[i].split()[1:]]
    i += 1
    rows = {}
    while lines[i] != 'EOD':
        f = lines[i].split()
        rows[float(f[0])] = [float(v) for v in f[1:]]
        i += 1
    return exc, rows

for path in sorted(glob.glob('host/data/fluorescence/*.BFC')):
    exc, rows = read_bfc(path)
    worst = 0.0
    for j, li in enumerate(exc):
        tot = 0.0
        for lo, vals in rows.items():
            d = vals[j]
            if lo == li:
                tot += max(d, 0.0)
            elif lo > li and d > 0:
                tot += d
        worst = max(worst, tot)
    for name, E in ill.items():
        k = 100.0 / sum(E[lo] * cmf[lo][1] for lo in rows)
        tot = [0.0] * 3
        refl = [0.0] * 3
        for lo, vals in rows.items():
            s = 0.0
            r = 0.0
            for j, li in enumerate(exc):
                d = vals[j]
                if lo == li:
                    r = max(d, 0.0) * E[li]
                    s += r
                elif lo > li and d > 0:
                    s += d * E[li]
            for c in range(3):
                tot[c] += k * s * cmf[lo][c]
                refl[c] += k * r * cmf[lo][c]
        def xy(v):
            t = sum(v)
            return v[0] / t, v[1] / t
        print('%s %s total %.4f %.4f %.4f xy %.5f %.5f refl %.4f %.4f %.4f xy %.5f %.5f max_column_sum %.4f'
              % (os.path.basename(path), name, *tot, *xy(tot), *refl, *xy(refl), worst))
