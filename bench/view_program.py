"""A raster finishing program of N moves (zig-zag rows of 1,000 G1 moves over
a wavy surface, 0.1 mm apart), the kind of file `kezuri view` must open fast.

    python3 bench/view_program.py 1000000 > big.nc
"""
import math
import sys

n = int(sys.argv[1])
out = sys.stdout
out.write("%\nO0001 (VIEW BENCH)\nG21 G90 G17 G54\nT1 M6\nG43 H1 Z20.\nM3 S12000\nG0 X0. Y0. Z5.\nG1 Z-1. F1000.\n")
rows = max(1, n // 1000)
lines = []
for row in range(rows):
    y = row * 0.1
    for i in range(1000):
        x = (i if row % 2 == 0 else 999 - i) * 0.1
        z = -1 - 0.5 * math.sin(x * 0.3) * math.cos(y * 0.2)
        lines.append("G1 X%.3f Y%.3f Z%.3f\n" % (x, y, z))
    if len(lines) > 100_000:
        out.write("".join(lines))
        lines.clear()
out.write("".join(lines))
out.write("G0 Z20.\nM5\nM30\n%\n")
