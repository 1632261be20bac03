#!/usr/bin/env python3
"""Mitsuba 3's `envmap` radiance (scalar_rgb variant) along fixed directions, for
host/tests/envmap_mitsuba.rs: the independent check of spectrace's envmap mapping (which
texel a direction sees, the rotation by `to_world`, bilinear interpolation).

Reads host/tests/data/envmap/sky16x8.hdr (procedural, scripts/make_texture_assets.py) and writes
host/tests/data/envmap/mitsuba_lookup.csv: dx,dy,dz,r,g,b for directions d that a ray leaving
the scene travels along (world frame), with to_world = rotate 30 degrees about +y.

Usage: /tmp/anchors-venv/bin/python scripts/anchors/envmap_mitsuba_lookup.py
"""
import math
import os

import mitsuba as mi

mi.set_variant("scalar_rgb")
HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
MAP = os.path.join(ROOT, "host", "tests", "data", "envmap", "sky16x8.hdr")
OUT = os.path.join(ROOT, "host", "tests", "data", "envmap", "mitsuba_lookup.csv")

emitter = mi.load_dict({
    "type": "envmap",
    "filename": MAP,
    "to_world": mi.ScalarTransform4f().rotate([0, 1, 0], 30.0),
})
rows = ["dx,dy,dz,r,g,b"]
n = 0
k = 0
while n < 60:
    k += 1
    # A golden-ratio spiral over the sphere, skipping the exact poles.
    z = 1.0 - 2.0 * ((k * 0.61803398875) % 1.0)
    phi = 2.0 * math.pi * ((k * 0.7548776662) % 1.0)
    if abs(z) > 0.98:
        continue
    s = math.sqrt(1.0 - z * z)
    d = [s * math.cos(phi), z, s * math.sin(phi)]
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(-d[0], -d[1], -d[2])
    v = emitter.eval(si)
    rows.append("%.9f,%.9f,%.9f,%.9g,%.9g,%.9g" % (d[0], d[1], d[2], v[0], v[1], v[2]))
    n += 1
with open(OUT, "w") as f:
    f.write("\n".join(rows) + "\n")
print("wrote", OUT)
