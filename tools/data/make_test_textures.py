#!/usr/bin/env python3
"""Writes three 64x64 test pictures into DIR (tests/data/textures):

slide.png: for projector tests, inside a round frame (black outside a disc of radius 26 texels,
so the spot cone's edge, which the square picture circumscribes, falls where the picture is
dark). Soft colour gradients, and a bright square in the top-right quarter so a picture turned or
mirrored shows.

waves_normal.png: a tangent-space normal map of the smooth height field
h = 0.06 P sin(2 pi x / P) sin(2 pi y / P) (P = 32 texels; y up), encoded 127.5 (n + 1), each
texel the 8-bit vector nearest to unit length among its neighbours' roundings. Smooth, so a
bilinear blend of texels stays within about 0.2 % of unit length (DOT3 bump mapping in GL 2.1
dots the unnormalised texel).

leaves.png: RGBA foliage for alpha to coverage and alpha tests: five leaves (ellipses along a
twig) in greens, opaque inside, their alpha falling linearly to 0 over the outer 4 texels of each
leaf (soft cut-out edges), clear (alpha 0, a mid green) between them.

    tools/data/make_test_textures.py tests/data/textures
"""
import itertools
import math
import os
import struct
import sys
import zlib

W = H = 64


def slide(x, y):  # y = 0 is the top row (PNG order)
    cx, cy = x + 0.5 - 32, 32 - (y + 0.5)  # cy up
    if cx * cx + cy * cy > 26 * 26:
        return (0, 0, 0)
    if 6 <= cx <= 18 and 6 <= cy <= 18:
        return (250, 250, 230)
    r = 0.55 + 0.4 * math.cos(cx / 9.0)
    g = 0.5 + 0.35 * math.sin(cy / 8.0)
    b = 0.6 - 0.3 * math.cos((cx + cy) / 14.0)
    return tuple(int(round(255 * max(0.0, min(1.0, v)))) for v in (r, g, b))


def waves(x, y):
    P, A = 32.0, 0.06 * 32.0
    u, v = x + 0.5, (H - 1 - y) + 0.5  # v up: texture t grows upwards
    w = 2 * math.pi / P
    dhdu = A * w * math.cos(w * u) * math.sin(w * v)
    dhdv = A * w * math.sin(w * u) * math.cos(w * v)
    n = (-dhdu, -dhdv, 1.0)
    length = math.sqrt(sum(c * c for c in n))
    n = [c / length for c in n]
    exact = [127.5 * (c + 1) for c in n]
    best = None
    for rounding in itertools.product(*[(math.floor(e), math.ceil(e)) for e in exact]):
        q = [min(255, max(0, r)) for r in rounding]
        err = abs(math.sqrt(sum((c / 127.5 - 1) ** 2 for c in q)) - 1)
        if best is None or err < best[0]:
            best = (err, tuple(q))
    return best[1]


LEAVES = [(20, 44, 13, 6, 0.6), (40, 40, 12, 6, -0.5), (30, 24, 12, 7, 1.2), (46, 18, 10, 5, 0.3),
          (16, 16, 10, 5, -0.9)]  # centre x, y (y down), half length, half width, angle


def leaves(x, y):
    px, py = x + 0.5, y + 0.5
    best = None
    for k, (cx, cy, a, b, t) in enumerate(LEAVES):
        dx, dy = px - cx, py - cy
        u = dx * math.cos(t) + dy * math.sin(t)
        v = -dx * math.sin(t) + dy * math.cos(t)
        r = math.sqrt((u / a) ** 2 + (v / b) ** 2)  # 1 on the leaf's edge
        inside = (1 - r) * b  # texels inside the edge, roughly
        alpha = max(0.0, min(1.0, inside / 4))
        if alpha > 0 and (best is None or alpha > best[0]):
            shade = 0.75 + 0.25 * math.cos(3 * u / a)
            best = (alpha, (int(40 + 20 * k), int(150 * shade + 40), int(30 + 10 * k)))
    if best is None:  # a mid green, so that filtering across a leaf's edge draws no dark fringe
        return (60, 140, 40, 0)
    return best[1] + (int(round(255 * best[0])),)


def chunk(kind, data):
    body = kind + data
    return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)


def write(path, texel, colour_type=2):  # 2: RGB, 6: RGBA
    rows = b"".join(b"\x00" + bytes(c for x in range(W) for c in texel(x, y)) for y in range(H))
    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, colour_type, 0, 0, 0)) +
           chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))
    with open(path, "wb") as f:
        f.write(png)


write(os.path.join(sys.argv[1], "slide.png"), slide)
write(os.path.join(sys.argv[1], "waves_normal.png"), waves)
write(os.path.join(sys.argv[1], "leaves.png"), leaves, 6)
