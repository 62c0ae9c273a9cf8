#!/usr/bin/env python3
"""`kezuri relief` against LinuxCNC's image-to-gcode, headless, on the same picture.

Run through bench/relief_vs_image_to_gcode.sh (it makes the venv, fetches Debian's
linuxcnc-uspace package for its image-to-gcode script and builds kezuri). The issue's case:
a 1024 x 1024 PNG at 0.1 mm per pixel, a 6 mm ball, stepover 0.4 mm (image-to-gcode's pixel
step 4), tolerance 0.01 mm, rows only.

  image-to-gcode time: Converter(...).convert() in this process (its per-pixel tool stencil,
      row scanning and its Douglas-Peucker output), the picture already loaded.
  kezuri time: the whole `kezuri relief` process (reading the PNG and writing the program
      included; the relief surface STL for the comparison is written by a run of its own, not
      timed), median of RUNS.
Both programs then go through `kezuri sim --compare` against the relief surface.
"""
import io
import json
import math
import os
import runpy
import statistics
import subprocess
import sys
import tempfile
import time
import types

import numpy
from PIL import Image

KEZURI = os.environ.get("KEZURI", "target/release/kezuri")
I2G = os.environ["IMAGE_TO_GCODE"]  # the extracted package root
SIZE = int(os.environ.get("SIZE", "1024"))
RUNS = int(os.environ.get("RUNS", "3"))
PIXEL, DEPTH, TOOL_D, STEPOVER, TOL = 0.1, 3.0, 6.0, 0.4, 0.01


def picture(path):
    """Smooth bumps, a ring and flat-topped letters-like blocks: slopes and steps."""
    n = SIZE
    y, x = numpy.mgrid[0:n, 0:n] / n
    z = 0.25 + 0.35 * numpy.exp(-((x - 0.3) ** 2 + (y - 0.35) ** 2) / 0.02)
    z += 0.3 * numpy.exp(-((numpy.hypot(x - 0.7, y - 0.65) - 0.18) ** 2) / 0.002)
    for (x0, y0, w, h) in [(0.55, 0.1, 0.3, 0.08), (0.1, 0.7, 0.08, 0.22), (0.2, 0.75, 0.2, 0.05)]:
        z[(x >= x0) & (x < x0 + w) & (y >= y0) & (y < y0 + h)] = 0.95
    Image.fromarray(numpy.clip(z * 255.0, 0, 255).round().astype(numpy.uint8)).save(path)


def image_to_gcode(png, out):
    # Its rs274 package's __init__ loads LinuxCNC's C interpreter; image-to-gcode needs only
    # rs274/author.py (pure Python) and rs274.options for its Tk dialog, which is not used.
    package = types.ModuleType("rs274")
    package.__path__ = [os.path.join(I2G, "usr/lib/python3/dist-packages/rs274")]
    sys.modules["rs274"] = package
    sys.modules["rs274.options"] = types.ModuleType("rs274.options")
    m = runpy.run_path(os.path.join(I2G, "usr/bin/image-to-gcode"), run_name="image_to_gcode")
    im = Image.open(png).convert("L")
    w, h = im.size
    nim = numpy.frombuffer(im.tobytes(), dtype=numpy.uint8).reshape((h, w)).astype(numpy.float32)
    nim = nim / 255.0 * DEPTH - DEPTH  # white at 0, black DEPTH below, as in its main()
    tool = m["make_tool_shape"](m["ball_tool"], TOOL_D, PIXEL)
    lines = []
    converter = m["Converter"](
        nim, "G21", tool, PIXEL, int(round(STEPOVER / PIXEL)), 5.0, TOL, 1500.0,
        m["Convert_Scan_Alternating"](), None, False, m["SimpleEntryCut"](300.0), 10000, 0, 0, 0)
    stdout = sys.stdout
    sys.stdout = io.StringIO()
    t0 = time.perf_counter()
    converter.convert()
    seconds = time.perf_counter() - t0
    text = sys.stdout.getvalue()
    sys.stdout = stdout
    open(out, "w").write(text + "M2\n")
    return seconds, tool.shape[0]


def kezuri_relief(png, out, stl, origin):
    args = [KEZURI, "relief", png, "--pixel", str(PIXEL), "--depth", str(DEPTH), "--tool", f"ball:{TOOL_D:g}",
            "--stepover", str(STEPOVER), "--leave-tol", str(TOL), "--origin", origin, "--to", "linuxcnc",
            "-o", out]
    # The relief surface for the comparison, once and untimed (writing a 2-million-triangle
    # STL is not part of the conversion).
    subprocess.run(args + ["--surface-stl", stl], check=True, capture_output=True)
    times = []
    for _ in range(RUNS):
        t0 = time.perf_counter()
        subprocess.run(args, check=True, capture_output=True)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def sim(nc, stl, stock):
    o = subprocess.run([KEZURI, "sim", nc, "--tool", f"ball:{TOOL_D:g}", "--res", "0.1", "--compare", stl,
                        "--stock", stock, "--no-decimal", "units", "--json"], check=True, capture_output=True,
                       text=True)
    return json.loads(o.stdout)


def main():
    d = tempfile.mkdtemp()
    png = os.path.join(d, "relief.png")
    picture(png)
    i2g_nc = os.path.join(d, "i2g.ngc")
    t_i2g, ts = image_to_gcode(png, i2g_nc)
    # image-to-gcode puts the ball's centre over pixel column i + ts/2 at x = i * pixel and
    # row r at y = (rows - ts/2 - r) * pixel: the same surface in its frame is ours moved.
    half = ts // 2
    origin = f"{-(half + 0.5) * PIXEL:.6f},{-(half - 0.5) * PIXEL:.6f}"
    k_nc, stl = os.path.join(d, "kezuri.ngc"), os.path.join(d, "relief.stl")
    t_k = kezuri_relief(png, k_nc, stl, origin)
    print(f"{SIZE} x {SIZE} px at {PIXEL} mm, ball:{TOOL_D:g}, stepover {STEPOVER} mm, tolerance {TOL} mm, rows")
    print(f"{'':16} {'time s':>8} {'gouge mm':>9} {'left mm':>8} {'mean|dev|':>9} {'lines':>8}")
    # Compared where both programs cut: image-to-gcode's ball centres cover x 0 … (SIZE - ts - 1)
    # pixels and y 1 … (SIZE - ts) pixels; a cutter radius in from those.
    r = TOOL_D / 2
    stock = f"{r:g},{PIXEL + r:g},{(SIZE - ts - 1) * PIXEL - r:g},{(SIZE - ts) * PIXEL - r:g},0"
    print(f"compared over X Y Z {stock}")
    for name, nc, t in [("image-to-gcode", i2g_nc, t_i2g), ("kezuri relief", k_nc, t_k)]:
        v = sim(nc, stl, stock)
        lines = sum(1 for _ in open(nc))
        print(f"{name:16} {t:8.2f} {v['max_gouge_mm']:9.4f} {v['max_left_mm']:8.4f} {v['mean_abs_dev_mm']:9.4f} {lines:8}")
    print(f"ratio (image-to-gcode / kezuri): {t_i2g / t_k:.1f}x")


if __name__ == "__main__":
    main()
