#!/usr/bin/env python3
"""Drop-cutter side by side: OpenCAMLib's BatchDropCutter against `kezuri dropcut`.

Run through bench/ocl_dropcut.sh (it makes the venv and the release build). Builds wavy
surfaces as binary STL (coordinates rounded to float32 first, so both programs see the same
numbers), drops flat, ball and bull cutters on a 51 x 51 grid with both, and prints the times,
the ratio and the largest |z difference|.

  OpenCAMLib time: BatchDropCutter.setSTL (its kd-tree) + run(), in this process.
  kezuri time: the whole `kezuri dropcut` process, reading the STL included (best of 5).
"""
import math
import os
import struct
import subprocess
import sys
import tempfile
import time

import numpy as np
from opencamlib import ocl

KEZURI = os.environ.get("KEZURI", "target/release/kezuri")


def wavy(cells, size):
    """A cells x cells grid of 2-triangle squares over [0, size]^2: 2 * cells^2 triangles."""
    n = cells + 1
    xs = np.linspace(0.0, size, n)
    x, y = np.meshgrid(xs, xs)
    z = 4.0 * np.sin(2 * math.pi * x / 23.0) * np.cos(2 * math.pi * y / 17.0) + 1.5 * np.sin(2 * math.pi * (x + y) / 9.0)
    pts = np.stack([x, y, z], axis=-1).astype(np.float32).astype(np.float64)
    tris = []
    for j in range(cells):
        for i in range(cells):
            a, b, c, d = pts[j, i], pts[j, i + 1], pts[j + 1, i + 1], pts[j + 1, i]
            tris.append((a, b, c))
            tris.append((a, c, d))
    return tris


def write_stl(path, tris):
    with open(path, "wb") as f:
        f.write(b" " * 80)
        f.write(struct.pack("<I", len(tris)))
        for a, b, c in tris:
            f.write(struct.pack("<12fH", 0, 0, 0, *a, *b, *c, 0))


def ocl_surface(tris):
    s = ocl.STLSurf()
    for a, b, c in tris:
        s.addTriangle(ocl.Triangle(ocl.Point(*a), ocl.Point(*b), ocl.Point(*c)))
    return s


def ocl_cutter(kind):
    if kind == "flat":
        return ocl.CylCutter(6.0, 50.0)
    if kind == "ball":
        return ocl.BallCutter(6.0, 50.0)
    return ocl.BullCutter(6.0, 1.0, 50.0)


SPEC = {"flat": "flat:6", "ball": "ball:6", "bull": "bull:6,1"}


def grid_points(size, n=51):
    step = size / (n - 1)
    return step, [(i * step, j * step) for j in range(n) for i in range(n)]


def run_ocl(surf, kind, points, threads):
    bdc = ocl.BatchDropCutter()
    bdc.setThreads(threads)
    cutter = ocl_cutter(kind)  # kept alive: BatchDropCutter holds a bare pointer to it
    bdc.setCutter(cutter)
    for x, y in points:
        bdc.appendPoint(ocl.CLPoint(x, y, -100.0))
    t0 = time.perf_counter()
    bdc.setSTL(surf)
    bdc.run()
    t = time.perf_counter() - t0
    z = [p.z for p in bdc.getCLPoints()]
    del bdc, cutter
    return t, z


def run_kezuri(stl, kind, size, step, repeat=5):
    args = [KEZURI, "dropcut", stl, "--tool", SPEC[kind], "--grid", f"0,0,{size},{size},{step}"]
    best = math.inf
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        r = subprocess.run(args, capture_output=True, check=True)
        best = min(best, time.perf_counter() - t0)
        out = r.stdout
    z = [float(line.split()[2]) for line in out.decode().splitlines()]
    return best, z


def main():
    one_core_kinds = sys.argv[1].split(",") if len(sys.argv) > 1 else ["ball"]
    surfaces = [
        ("80,000 triangles, 100 x 100 mm", 200, 100.0),
        ("5,000 triangles, 25 x 25 mm (same triangle size)", 50, 25.0),
        ("5,000 triangles, 100 x 100 mm", 50, 100.0),
    ]
    print(f"opencamlib {ocl.version()}, {os.cpu_count()} cores, kezuri = {KEZURI}")
    print("| surface | tool | OCL 1 core s (pts/s) | OCL 2 cores s (pts/s) | kezuri s (pts/s) | ratio (OCL 2 cores / kezuri) | max abs dz mm |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name, cells, size in surfaces:
            tris = wavy(cells, size)
            stl = os.path.join(tmp, f"wavy{cells}_{int(size)}.stl")
            write_stl(stl, tris)
            surf = ocl_surface(tris)
            step, points = grid_points(size)
            npts = len(points)
            for kind in ["flat", "ball", "bull"]:
                one = ""
                if kind in one_core_kinds or cells <= 50:
                    t1, _ = run_ocl(surf, kind, points, 1)
                    one = f"{t1:.3f} ({npts / t1:,.0f})"
                t2, zo = run_ocl(surf, kind, points, 2)
                tk, zk = run_kezuri(stl, kind, size, step)
                if len(zk) != len(zo):
                    raise SystemExit(f"kezuri gave {len(zk)} points, OpenCAMLib {len(zo)}")
                dz = max(abs(a - b) for a, b in zip(zo, zk))
                print(
                    f"| {name} | {SPEC[kind]} | {one} | {t2:.3f} ({npts / t2:,.0f}) | {tk:.4f} ({npts / tk:,.0f}) "
                    f"| {t2 / tk:,.0f}x | {dz:.2e} |",
                    flush=True,
                )


if __name__ == "__main__":
    main()
