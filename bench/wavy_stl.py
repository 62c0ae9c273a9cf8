#!/usr/bin/env python3
"""Writes a wavy surface as a binary STL, a row of squares at a time (never held whole).

    python3 bench/wavy_stl.py CELLS SIZE OUT.stl

A CELLS x CELLS grid of 2-triangle squares over [0, SIZE]^2 (2 * CELLS^2 triangles),
z = 4 sin(2 pi x / 23) cos(2 pi y / 17) + 1.5 sin(2 pi (x + y) / 9), as bench/ocl_dropcut.py's
surfaces. CELLS 3163 gives 20,009,138 triangles (1.0 GB).
"""
import math
import struct
import sys


def main():
    cells, size, out = int(sys.argv[1]), float(sys.argv[2]), sys.argv[3]
    n = cells + 1
    xs = [size * i / cells for i in range(n)]

    def row(y):
        return [(x, y, 4.0 * math.sin(2 * math.pi * x / 23.0) * math.cos(2 * math.pi * y / 17.0)
                 + 1.5 * math.sin(2 * math.pi * (x + y) / 9.0)) for x in xs]

    rec = struct.Struct("<12f2x")
    with open(out, "wb") as f:
        f.write(b"kezuri bench wavy surface".ljust(80, b" "))
        f.write(struct.pack("<I", 2 * cells * cells))
        below = row(xs[0])
        for j in range(cells):
            above = row(xs[j + 1])
            buf = bytearray()
            for i in range(cells):
                a, b, c, d = below[i], below[i + 1], above[i + 1], above[i]
                buf += rec.pack(0, 0, 0, *a, *b, *c)
                buf += rec.pack(0, 0, 0, *a, *c, *d)
            f.write(buf)
            below = above


if __name__ == "__main__":
    main()
