#!/usr/bin/python3
"""Compares wire_sim runs of one scene with a reference run, span by span.

usage: compare_runs.py REFERENCE_DIR RUN_DIR [RUN_DIR ...]
  reads DIR/summary.json and DIR/shape_core.csv of each run and prints a
  Markdown table: the error of the bulging height, of each span's largest
  stand-off (a span: the free wire between two stretches that touch the
  core, in order along the wire from the fixed end), the distance of the
  wound wire's curve from the reference's (point to polyline, both ways,
  core frame) and of corresponding points, both over the wire diameter,
  and the difference in fed length.
"""
import csv
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from convergence_table import distance_to_polyline  # noqa: E402


def load(d):
    with open(f"{d}/summary.json") as f:
        s = json.load(f)
    with open(f"{d}/shape_core.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    pts = [(float(r["x_core"]), float(r["y_core"]), float(r["z_core"])) for r in rows]
    stand_off = [float(r["stand_off_m"]) for r in rows]
    touching = [int(r["in_contact"]) for r in rows]
    return s, pts, stand_off, touching


def spans(stand_off, touching, wound):
    """Largest stand-off of each free stretch between touching ones [m]
    (the fixed end, held on the core, starts the first)."""
    out, best, seen_contact = [], 0.0, True
    for i in range(wound):
        if touching[i]:
            if seen_contact and best > 0.0:
                out.append(best)
            seen_contact, best = True, 0.0
        else:
            best = max(best, stand_off[i])
    return out


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    ref_dir, runs = sys.argv[1], sys.argv[2:]
    rs, rp, rso, rt = load(ref_dir)
    diameter = 1.0e-3
    rw = rs["wound_points"]
    ref_spans = spans(rso, rt, rw)
    head = " | ".join(f"span {k + 1}" for k in range(len(ref_spans)))
    print(f"| run | bulging | {head + ' | ' if head else ''}curve / d | points / d | fed [um] |")
    print("|---" * (len(ref_spans) + 5) + "|")
    print(f"| {ref_dir} (reference) | {1e3 * rs['bulging_height_m']:.4f} mm | "
          + "".join(f"{1e3 * h:.4f} mm | " for h in ref_spans) + " | | |")
    for d in runs:
        s, p, so, t = load(d)
        w = s["wound_points"]
        sp = spans(so, t, w)
        cells = [f"{100 * (a / b - 1):+.1f} %" if b > 0 else "-" for a, b in zip(sp, ref_spans)]
        cells += ["-"] * (len(ref_spans) - len(cells))
        curve = max(max(distance_to_polyline(x, rp[:rw]) for x in p[:w]),
                    max(distance_to_polyline(x, p[:w]) for x in rp[:rw])) / diameter
        n = min(len(p), len(rp))
        points = max(math.dist(p[i], rp[i]) for i in range(n)) / diameter
        rb = rs["bulging_height_m"]
        bulge = f"{100 * (s['bulging_height_m'] / rb - 1):+.2f} %" if rb > 0 else "-"
        fed = 1e6 * (s["fed_length_m"] - rs["fed_length_m"])
        print(f"| {d} | {bulge} | " + "".join(c + " | " for c in cells)
              + f"{curve:.4f} | {points:.4f} | {fed:+.1f} |")


if __name__ == "__main__":
    main()
