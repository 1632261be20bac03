#!/usr/bin/env python3
"""Writes the small synthetic photometric files in host/tests/data/photometry/, each for a case
the real files in host/data/photometry/ lack. Every distribution is an analytic function so the
tests know the candela at any angle and the flux in closed form (see host/tests/photometry_files.rs).
Run from the repository root: python3 scripts/make_photometry_test_files.py
"""
import math
import os

OUT = "host/tests/data/photometry"


def wrap(values, per_line=10, sep=" ", fmt="{:.3f}"):
    out = []
    for i in range(0, len(values), per_line):
        out.append(sep.join(fmt.format(v) for v in values[i:i + per_line]))
    return "\n".join(out)


def frange(a, b, step):
    n = int(round((b - a) / step))
    return [a + i * step for i in range(n + 1)]


def write(name, text, newline="\n"):
    with open(os.path.join(OUT, name), "w", newline=newline) as f:
        f.write(text)


# Type A, lateral symmetry (h 0..90), LM-63-2002: I = 100 (1 + sin v)(1 + cos h).
h = frange(0, 90, 5)
v = frange(-90, 90, 5)
cd = [100 * (1 + math.sin(math.radians(b))) * (1 + math.cos(math.radians(a))) for a in h for b in v]
write("type_a_lateral_lm63_2002.ies", "\n".join([
    "IESNA:LM-63-2002",
    "[TEST] synthetic type A: I = 100 (1 + sin v)(1 + cos h) cd",
    "[TESTLAB] spectrace test data",
    "[ISSUEDATE] 2026-12-01",
    "[MANUFAC] none",
    "TILT=NONE",
    f"1 1000 1.0 {len(v)} {len(h)} 3 2 0.1 0.1 0.0",
    "1.0 1.0 10",
    wrap(v), wrap(h), wrap(cd), ""]))

# Type B, full (h -90..90), absolute photometry (lumens -1), candela multiplier 2:
# I = 100 (1 + 0.5 sin h)(1 + cos v); the file stores I / 2.
h = frange(-90, 90, 5)
v = frange(-90, 90, 5)
cd = [50 * (1 + 0.5 * math.sin(math.radians(a))) * (1 + math.cos(math.radians(b))) for a in h for b in v]
write("type_b_absolute_lm63_2002.ies", "\n".join([
    "IESNA:LM-63-2002",
    "[TEST] synthetic type B, absolute photometry: I = 100 (1 + 0.5 sin h)(1 + cos v) cd",
    "[TESTLAB] spectrace test data",
    "[ISSUEDATE] 2026-12-01",
    "[MANUFAC] none",
    "TILT=NONE",
    f"1 -1 2.0 {len(v)} {len(h)} 2 2 0.2 0.2 0.0",
    "1.0 1.0 25",
    wrap(v), wrap(h), wrap(cd), ""]))

# TILT=INCLUDE, type C without symmetry (0..360), LM-63-1995, commas and blanks mixed:
# I = 100 cos(gamma) (1 + 0.5 cos C) for gamma 0..90, 0 above.
h = frange(0, 360, 30)
v = frange(0, 180, 10)
cd = [100 * max(0.0, math.cos(math.radians(b))) * (1 + 0.5 * math.cos(math.radians(a))) for a in h for b in v]
write("tilt_include_lm63_1995.ies", "\n".join([
    "IESNA:LM-63-1995",
    "[TEST] synthetic TILT=INCLUDE: I = 100 cos(gamma)(1 + 0.5 cos C) cd, gamma < 90",
    "[MANUFAC] none",
    "TILT=INCLUDE",
    "1",
    "4",
    "0 30 60 90",
    "1.0 0.95 0.8 0.6",
    f"1 1500 1.0 {len(v)} {len(h)} 1 2 0.0 0.0 0.0",
    "1.0 1.0 15",
    wrap(v, 7, ", "), wrap(h, 7, ", "), wrap(cd, 7, ", "), ""]), newline="\r\n")

# TILT=<file>, axial type C, LM-63-1986 (no version line): I = 50 cd in the lower hemisphere.
v = frange(0, 90, 15)
cd = [50.0 for _ in v]
write("tilt_file_lm63_1986.ies", "\n".join([
    "synthetic tilt-file luminaire",
    "I = 50 cd in the lower hemisphere",
    "TILT=tilt_file_lamp.tlt",
    f"1 400 1.0 {len(v)} 1 1 1 0.0 0.0 0.0",
    "1.0 0.5 5",
    wrap(v), "0", wrap(cd), ""]))
write("tilt_file_lamp.tlt", "2\n3\n0 45 90\n1.0 0.9 0.7\n")

# LM-63-2019, bilateral about the C90-C270 plane (C 90..270): I = 100 (1 + 0.5 sin C) for
# gamma 0..180, candela multiplier 1, ballast factor 0.9 (applied), file generation type 1.10000
# (not a multiplier). The file stores I.
h = frange(90, 270, 15)
v = frange(0, 180, 15)
cd = [100 * (1 + 0.5 * math.sin(math.radians(a))) for a in h for b in v]
write("bilateral_c90_lm63_2019.ies", "\n".join([
    "IES:LM-63-2019",
    "[TEST] synthetic LM-63-2019: I = 0.9 x 100 (1 + 0.5 sin C) cd",
    "[TESTLAB] spectrace test data",
    "[ISSUEDATE] 2026-12-01",
    "[MANUFAC] none",
    "[LUMCAT] none",
    "[LUMINAIRE] synthetic",
    "[LAMP] synthetic lamp",
    "TILT=NONE",
    f"2 500 1.0 {len(v)} {len(h)} 1 2 0.3 0.3 0.1",
    "0.9 1.10000 40",
    wrap(v), wrap(h), wrap(cd), ""]))


def ldt(lines):
    return "\n".join(str(x) for x in lines) + "\n"


def comma(x, fmt="{:.3f}"):
    return fmt.format(x).replace(".", ",")


# EULUMDAT Isym 0 with decimal commas: I = 100 cos(gamma)(1 + 0.3 cos C + 0.2 sin C) cd/klm,
# gamma 0..90, 1000 lm lamp, conversion factor 1,0.
mc, dc = 8, 45
g = frange(0, 90, 5)
cs = [i * dc for i in range(mc)]
vals = [100 * math.cos(math.radians(b)) * (1 + 0.3 * math.cos(math.radians(a)) + 0.2 * math.sin(math.radians(a)))
        for a in cs for b in g]
write("isym0_decimal_comma.ldt", ldt(
    ["spectrace synthetic Isym 0, decimal commas", 1, 0, mc, "45,0", len(g), "5,0", "T-0", "synthetic", "S0",
     "isym0_decimal_comma.ldt", "01.12.2026", 100, 100, 50, 90, 90, 0, 0, 0, 0, "100,0", "75,5", "1,0", "0,0",
     1, 1, "synthetic", "1000,0", "3000K", "80", "12,5"]
    + ["0,5"] * 10 + [comma(c, "{:.1f}") for c in cs] + [comma(b, "{:.1f}") for b in g]
    + [comma(x) for x in vals]))

# EULUMDAT Isym 3 (C90..C270 stored) with two lamp sets: I = 100 cos(gamma)(1 + 0.5 sin C) cd/klm
# for gamma < 90, 0 above; set 1 is 2000 lm (the table's reference), set 2 3000 lm.
mc, dc = 24, 15
g = frange(0, 180, 5)
cs = [i * dc for i in range(mc)]
stored = [c for c in cs if 90 <= c <= 270]
vals = [100 * max(0.0, math.cos(math.radians(b))) * (1 + 0.5 * math.sin(math.radians(a))) for a in stored for b in g]
write("isym3_two_lamp_sets.ldt", ldt(
    ["spectrace synthetic Isym 3, two lamp sets", 1, 3, mc, 15, len(g), 5, "T-3", "synthetic", "S3",
     "isym3_two_lamp_sets.ldt", "01.12.2026", 600, 300, 80, 580, 280, 0, 0, 0, 0, 100, 100, 1, 0,
     2, 2, "LED module A", 2000, "4000K", "1B/85", 20, 3, "LED module B", 3000, "3000K", "1A/90", 30]
    + [0.5] * 10 + cs + g + ["{:.3f}".format(x) for x in vals]))
