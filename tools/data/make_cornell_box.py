#!/usr/bin/env python3
"""Writes the Cornell box (Cornell University Program of Computer Graphics, "Cornell Box Data":
the measured geometry of the physical box, in millimetres) as a Wavefront OBJ with one material
group per surface kind, facing into the room (walls, floor, ceiling) and out of the blocks:

    tools/data/make_cornell_box.py tests/data/cornell/cornell_box.obj

The light is the published 130 x 105 mm opening in the ceiling (y = 548.8), moved 0.1 mm down so
that it does not share the ceiling's plane. The published data gives reflectance spectra; the
scene file beside the OBJ uses RGB approximations of them (docs/baking.md says which).
"""
import sys

FLOOR = [(552.8, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 559.2), (549.6, 0.0, 559.2)]
LIGHT = [(343.0, 548.7, 227.0), (343.0, 548.7, 332.0), (213.0, 548.7, 332.0), (213.0, 548.7, 227.0)]
CEILING = [(556.0, 548.8, 0.0), (556.0, 548.8, 559.2), (0.0, 548.8, 559.2), (0.0, 548.8, 0.0)]
BACK = [(549.6, 0.0, 559.2), (0.0, 0.0, 559.2), (0.0, 548.8, 559.2), (556.0, 548.8, 559.2)]
RIGHT = [(0.0, 0.0, 559.2), (0.0, 0.0, 0.0), (0.0, 548.8, 0.0), (0.0, 548.8, 559.2)]  # green
LEFT = [(552.8, 0.0, 0.0), (549.6, 0.0, 559.2), (556.0, 548.8, 559.2), (556.0, 548.8, 0.0)]  # red
SHORT = [
    [(130.0, 165.0, 65.0), (82.0, 165.0, 225.0), (240.0, 165.0, 272.0), (290.0, 165.0, 114.0)],
    [(290.0, 0.0, 114.0), (290.0, 165.0, 114.0), (240.0, 165.0, 272.0), (240.0, 0.0, 272.0)],
    [(130.0, 0.0, 65.0), (130.0, 165.0, 65.0), (290.0, 165.0, 114.0), (290.0, 0.0, 114.0)],
    [(82.0, 0.0, 225.0), (82.0, 165.0, 225.0), (130.0, 165.0, 65.0), (130.0, 0.0, 65.0)],
    [(240.0, 0.0, 272.0), (240.0, 165.0, 272.0), (82.0, 165.0, 225.0), (82.0, 0.0, 225.0)],
]
TALL = [
    [(423.0, 330.0, 247.0), (265.0, 330.0, 296.0), (314.0, 330.0, 456.0), (472.0, 330.0, 406.0)],
    [(423.0, 0.0, 247.0), (423.0, 330.0, 247.0), (472.0, 330.0, 406.0), (472.0, 0.0, 406.0)],
    [(472.0, 0.0, 406.0), (472.0, 330.0, 406.0), (314.0, 330.0, 456.0), (314.0, 0.0, 456.0)],
    [(314.0, 0.0, 456.0), (314.0, 330.0, 456.0), (265.0, 330.0, 296.0), (265.0, 0.0, 296.0)],
    [(265.0, 0.0, 296.0), (265.0, 330.0, 296.0), (423.0, 330.0, 247.0), (423.0, 0.0, 247.0)],
]


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def centre(points):
    return tuple(sum(p[i] for p in points) / len(points) for i in range(3))


def oriented(quad, towards):
    """The quad wound counter-clockwise seen from the side of `towards` (a direction test at its centre)."""
    n = cross(sub(quad[1], quad[0]), sub(quad[2], quad[0]))
    return quad if dot(n, sub(towards, centre(quad))) > 0 else list(reversed(quad))


def away(quad, inside):
    n = cross(sub(quad[1], quad[0]), sub(quad[2], quad[0]))
    return quad if dot(n, sub(centre(quad), inside)) > 0 else list(reversed(quad))


def main():
    room = (278.0, 274.4, 279.6)
    groups = [
        ("white", [oriented(q, room) for q in (FLOOR, CEILING, BACK)]),
        ("red", [oriented(LEFT, room)]),
        ("green", [oriented(RIGHT, room)]),
        ("light", [oriented(LIGHT, (278.0, 0.0, 279.6))]),
        ("white", [away(q, centre([p for face in SHORT for p in face])) for q in SHORT]),
        ("white", [away(q, centre([p for face in TALL for p in face])) for q in TALL]),
    ]
    lines = ["# The Cornell box (Cornell University Program of Computer Graphics, Cornell Box Data),",
             "# millimetres; written by tools/data/make_cornell_box.py."]
    vertices = 0
    for name, quads in groups:
        lines.append(f"usemtl {name}")
        for q in quads:
            for p in q:
                lines.append("v %g %g %g" % p)
            lines.append("f %d %d %d %d" % (vertices + 1, vertices + 2, vertices + 3, vertices + 4))
            vertices += 4
    with open(sys.argv[1], "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
