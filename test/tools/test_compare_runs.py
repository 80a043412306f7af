#!/usr/bin/env python3
"""Tests of compare_runs.py on synthetic runs with known differences.

Each run directory is written here: a wound wire along the x axis of the core
frame with free spans whose stand-off is a half sine, and a run that differs
from it by a chosen amount, so every expected figure follows from that choice.

Run: python3 test/tools/test_compare_runs.py; registered for ctest in
CMakeLists.txt.
"""
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
TOOL = os.path.normpath(os.path.join(HERE, "..", "..", "src", "tools", "compare_runs.py"))
L = 1.0e-3  # segment length [m]
# Free spans: (first point, last point, peak stand-off [m]); the points
# between them touch the core.
SPANS = [(3, 9, 0.3e-3), (13, 19, 0.5e-3), (23, 29, 0.4e-3)]
N = 33


def profile(scale=(1.0, 1.0, 1.0)):
    stand_off, touching = [0.0] * N, [1] * N
    for (a, b, h), s in zip(SPANS, scale):
        for i in range(a, b + 1):
            touching[i] = 0
            stand_off[i] = s * h * math.sin(math.pi * (i - a + 1) / (b - a + 2))
    return stand_off, touching


def write_run(d, xs, stand_off, touching, fed_m):
    os.makedirs(d)
    with open(os.path.join(d, "shape_core.csv"), "w") as f:
        f.write("index,x_core,y_core,z_core,stand_off_m,in_contact,stick\n")
        for i in range(N):
            f.write(f"{i},{xs[i]!r},{stand_off[i]!r},0,{stand_off[i]!r},{touching[i]},0\n")
    with open(os.path.join(d, "summary.json"), "w") as f:
        json.dump({"wound_points": N, "bulging_height_m": max(stand_off), "fed_length_m": fed_m}, f)


def compare(ref, run):
    p = subprocess.run([sys.executable, TOOL, ref, run], stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, universal_newlines=True, check=True)
    row = p.stdout.strip().splitlines()[-1]
    return [c.strip() for c in row.strip("|").split("|")]


class CompareRuns(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp()
        self.ref = os.path.join(self.dir, "ref")
        so, t = profile()
        write_run(self.ref, [i * L for i in range(N)], so, t, 0.100)

    def tearDown(self):
        shutil.rmtree(self.dir)

    def test_one_span_higher(self):
        # Span 2 is 2 % higher: it and the bulging height (span 2 holds the
        # largest stand-off) read +2.0 %, the other spans 0; the curve and
        # the points are at most 2 % of its 0.5 mm peak apart (10 um =
        # 0.010 d; the half sine is flat at its peak, so point-to-polyline
        # is the vertical offset there within 1 %).
        run = os.path.join(self.dir, "run")
        so, t = profile((1.0, 1.02, 1.0))
        write_run(run, [i * L for i in range(N)], so, t, 0.100)
        cells = compare(self.ref, run)
        self.assertEqual(cells[1], "+2.00 %")
        self.assertEqual(cells[2:5], ["+0.0 %", "+2.0 %", "+0.0 %"])
        peak = 0.02 * 0.5e-3 * math.sin(math.pi * 4 / 8) / 1e-3  # [d]
        self.assertAlmostEqual(float(cells[5]), peak, delta=0.01 * peak)
        self.assertAlmostEqual(float(cells[6]), peak, delta=1e-4)
        self.assertEqual(cells[7], "+0.0")

    def test_material_slid_along_a_flat_wire(self):
        # A wire lying flat on the core (no spans): the run's points slid by
        # 0.3 mm along it (its fixed end and its last point kept where the
        # reference's are, so the two curves cover the same line): the curve distance is 0, the
        # points are 0.3 d apart, and 5 um more wire was fed.
        flat = [0.0] * N, [1] * N
        ref = os.path.join(self.dir, "flat_ref")
        write_run(ref, [i * L for i in range(N)], *flat, 0.100)
        run = os.path.join(self.dir, "flat_run")
        xs = [0.0] + [i * L + 0.3e-3 for i in range(1, N - 1)] + [(N - 1) * L]
        write_run(run, xs, *flat, 0.100005)
        cells = compare(ref, run)
        self.assertAlmostEqual(float(cells[-3]), 0.0, delta=1e-9)
        self.assertAlmostEqual(float(cells[-2]), 0.3, delta=1e-4)
        self.assertEqual(cells[-1], "+5.0")


def suite():
    return unittest.TestLoader().loadTestsFromTestCase(CompareRuns)


if __name__ == "__main__":
    if "--gtest_output" in " ".join(sys.argv):
        import rosunit
        rosunit.unitrun("coil_winding_sim", "compare_runs", "test_compare_runs.suite")
    else:
        unittest.main()
