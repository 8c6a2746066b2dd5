#!/usr/bin/env python3
"""Prints engine/src/texture/srgb_table.hpp's table: byte i -> 255 x the sRGB decoding of i / 255,
computed in double precision and rounded to the nearest float (printed with 9 significant digits,
which read back as the same float)."""
import struct


def f32(x):
    return struct.unpack("f", struct.pack("f", x))[0]


def linear(c):
    c = c / 255.0
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


values = [("%.9g" % f32(255.0 * linear(i))) for i in range(256)]
values = [v + (".0f" if "." not in v and "e" not in v else "f") for v in values]
for k in range(0, 256, 8):
    print("    " + ", ".join(values[k:k + 8]) + ",")
