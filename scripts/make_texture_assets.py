#!/usr/bin/env python3
"""Write the small procedural images that scenes/envmap.ron and scenes/textured.ron use
(standard library only; the output is deterministic, so re-running it reproduces the files):

- scenes/textures/sky.hdr: a 256 x 128 latitude-longitude Radiance HDR (RGBE, flat scanlines)
  in Mitsuba 3's envmap layout (top row = +y, u = 0 along -z, u = 1/4 along +x): a blue sky
  brightening towards the horizon, a sun of radius 2.5 degrees at elevation 35 degrees towards
  +x (u = 0.25), and a grey-brown ground below the horizon. Linear sRGB radiance, the sky's
  zenith about 0.3, the sun disc 2000.
- scenes/textures/checker.png: a 256 x 256 8-bit sRGB checkerboard of 8 x 8 squares in two
  colours (a warm orange and a light grey-blue), with a red stripe along the bottom (v = 0)
  and a green stripe along the left (u = 0) edge, so orientation is visible in renders.

Usage: python3 scripts/make_texture_assets.py
"""
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "scenes", "textures")


def rgbe(r, g, b):
    m = max(r, g, b)
    if m < 1e-32:
        return bytes([0, 0, 0, 0])
    e = math.frexp(m)[1]
    f = math.ldexp(1.0, -e) * 256.0
    return bytes([int(r * f), int(g * f), int(b * f), e + 128])


def sky(w=256, h=128):
    sun_el = math.radians(35.0)
    sun = (math.cos(sun_el), math.sin(sun_el), 0.0)  # towards +x, up +y
    sun_r = math.radians(2.5)
    rows = []
    for j in range(h):
        theta = j / (h - 1) * math.pi  # Mitsuba: rows at the poles inclusive
        row = bytearray()
        for i in range(w):
            phi = (i + 0.5) / w * 2.0 * math.pi
            d = (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))
            if d[1] < 0.0:
                c = (0.12, 0.10, 0.08)
            else:
                t = 1.0 - d[1]
                c = (0.08 + 0.35 * t ** 3, 0.15 + 0.35 * t ** 3, 0.30 + 0.25 * t ** 3)
                cosang = sum(a * b for a, b in zip(d, sun))
                if cosang > math.cos(sun_r):
                    c = (2000.0, 1900.0, 1750.0)
            row += rgbe(*c)
        rows.append(bytes(row))
    header = b"#?RADIANCE\n# procedural sky, scripts/make_texture_assets.py\nFORMAT=32-bit_rle_rgbe\n\n"
    header += b"-Y %d +X %d\n" % (h, w)
    with open(os.path.join(OUT, "sky.hdr"), "wb") as f:
        f.write(header + b"".join(rows))


def png(path, w, h, pixel):
    raw = bytearray()
    for y in range(h):
        raw.append(0)
        for x in range(w):
            raw += bytes(pixel(x, y))

    def chunk(tag, data):
        c = struct.pack(">I", len(data)) + tag + data
        return c + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    data = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    data += chunk(b"IDAT", zlib.compress(bytes(raw), 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(data)


def checker(x, y, n=256):
    if y >= n - 12:
        return (200, 30, 30)  # bottom row of the image = v = 0
    if x < 12:
        return (30, 170, 40)  # left column = u = 0
    return (235, 140, 40) if ((x // 32) + (y // 32)) % 2 == 0 else (170, 185, 215)


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    sky()
    png(os.path.join(OUT, "checker.png"), 256, 256, checker)
