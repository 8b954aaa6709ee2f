#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Checks of nacre.charts.dyn's rasterised crack picture (the path taken above
RASTER_TRIANGLES triangles, where drawing polygons one by one costs a minute per million bricks):
1. raster_image on a known mesh gives the exact pixels: two rectangles, [0, 0.5] x [0, 1] and
   [0.6, 1] x [0, 1], each cut along a diagonal into two triangles with values 1, 2 (left: below,
   above the diagonal y = 2x) and 3, 4 (right: below, above y = 2.5 (x - 0.6)), in a 10 x 2 image
   of the unit square. Pixel centres x = 0.05 .. 0.95, y = 0.25, 0.75; the column at x = 0.55
   lies in the gap (NaN); no centre lies on an edge;
2. with OUTDIR, the crack picture of its last dump drawn with --raster is a PNG.
Usage: check_dyn_plot.py SOURCE_DIR [OUTDIR]"""
import glob
import math
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(sys.argv[1], "python"))
import nacre.charts.dyn as plot  # noqa: E402  (python/nacre/charts/dyn.py)

pts = np.array([[0, 0], [0.5, 0], [0.5, 1], [0, 1], [0.6, 0], [1, 0], [1, 1], [0.6, 1]], dtype=float)
# vertex orders chosen so that each barycentric condition is the one cut by a diagonal in some
# triangle (l1 + l2 <= 1 in the first and third, l2 >= 0 in the second, l1 >= 0 in the fourth;
# the first and third are clockwise): a wrong inequality shows as a wrong pixel
conn = np.array([[1, 0, 2], [0, 2, 3], [5, 4, 6], [6, 7, 4]])
val = np.array([1.0, 2.0, 3.0, 4.0])
n = math.nan
want = [[2, 1, 1, 1, 1, n, 4, 3, 3, 3],   # y = 0.25: left diagonal at x = 0.125, right at 0.7
        [2, 2, 2, 2, 1, n, 4, 4, 4, 3]]   # y = 0.75: left diagonal at x = 0.375, right at 0.9
fail = []
# in both orders of the triangles: a pixel written by a triangle that does not hold its centre
# cannot hide behind the one written after it
for order in ([0, 1, 2, 3], [3, 2, 1, 0]):
    img = plot.raster_image(pts, conn[order], val[order], 10, 2, 0.0, 1.0, 0.0, 1.0)
    for row in range(2):
        for col in range(10):
            got, w = img[row, col], want[row][col]
            if not ((math.isnan(w) and math.isnan(got)) or got == w):
                fail.append(f"triangle order {order}, pixel (row {row}, column {col}): {got}, expected {w}")
if len(sys.argv) > 2:
    out = sys.argv[2]
    dump = sorted(glob.glob(os.path.join(out, "dump_*.h5")))[-1]
    with tempfile.TemporaryDirectory() as tmp:
        target = os.path.join(tmp, "crack_raster.png")
        plot.crack(out, dump, target=target, raster=True)
        if not (os.path.exists(target) and open(target, "rb").read(8) == b"\x89PNG\r\n\x1a\n"):
            fail.append("crack picture with --raster missing or not a PNG")
for f in fail:
    print("check_dyn_plot: " + f)
sys.exit(1 if fail else 0)
