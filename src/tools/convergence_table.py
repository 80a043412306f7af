#!/usr/bin/python3
"""Spatial convergence: compares runs of one scene at several segment lengths.

usage: convergence_table.py LABEL=DIR [LABEL=DIR ...]   (finest last)
  reads DIR/summary.json and DIR/shape_core.csv of each run and prints a
  Markdown table: bulging height and where, fed length, wall time, and the
  largest distance of the run's wound wire from the finest run's wound wire
  (point to polyline, core frame) relative to the wire diameter.
"""
import csv
import json
import math
import sys


def load(d):
    with open(f"{d}/summary.json") as f:
        s = json.load(f)
    with open(f"{d}/shape_core.csv", newline="") as f:
        pts = [(float(r["x_core"]), float(r["y_core"]), float(r["z_core"])) for r in csv.DictReader(f)]
    return s, pts[: s["wound_points"]]


def point_segment(p, a, b):
    ab = [b[i] - a[i] for i in range(3)]
    ap = [p[i] - a[i] for i in range(3)]
    L2 = sum(x * x for x in ab)
    t = 0.0 if L2 == 0 else max(0.0, min(1.0, sum(ap[i] * ab[i] for i in range(3)) / L2))
    return math.dist(p, [a[i] + t * ab[i] for i in range(3)])


def distance_to_polyline(p, poly):
    return min(point_segment(p, poly[i], poly[i + 1]) for i in range(len(poly) - 1))


def main():
    runs = [a.split("=", 1) for a in sys.argv[1:]]
    if not runs:
        sys.exit(__doc__)
    data = [(label, *load(d)) for label, d in runs]
    _, finest, finest_pts = data[-1]
    diameter = 1.0e-3
    print("| segment length | bulging height [mm] | at arc length [mm] | fed [mm] | shape vs finest / d | wall time [s] | real-time factor |")
    print("|---|---|---|---|---|---|---|")
    for label, s, pts in data:
        dev = max(distance_to_polyline(p, finest_pts) for p in pts) / diameter if pts is not finest_pts else 0.0
        print(f"| {label} | {1e3 * s['bulging_height_m']:.4f} | {1e3 * s['bulging_arc_length_m']:.1f} | "
              f"{1e3 * s['fed_length_m']:.1f} | {dev:.3f} | {s['wall_time_s']:.1f} | {s['real_time_factor']:.3g} |")


if __name__ == "__main__":
    main()
