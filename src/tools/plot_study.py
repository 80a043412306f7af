#!/usr/bin/python3
"""Plots the paper's 2 x 2 study written by `wire_sim study` (Fig. 8 in spirit).

usage: plot_study.py DIR   (reads DIR/study.csv, DIR/core_cylinders.csv and
                            DIR/<case>/shape_core.csv; writes DIR/study.png)
"""
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def hull(points):
    """Convex hull (Andrew's monotone chain) of 2-D points, counter-clockwise."""
    pts = sorted(set(points))
    if len(pts) <= 2:
        return pts

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


def winding_surface(cylinders, offset):
    """Outline of the hull of the cylinders widened by `offset` [m] (sampled)."""
    pts = []
    for c in cylinders:
        x, y, r = float(c["x_core"]), float(c["y_core"]), float(c["radius"]) + offset
        for k in range(180):
            a = 2 * math.pi * k / 180
            pts.append((x + r * math.cos(a), y + r * math.sin(a)))
    h = hull(pts)
    return h + h[:1]


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    d = sys.argv[1]
    try:
        cases = read_csv(os.path.join(d, "study.csv"))
        cylinders = read_csv(os.path.join(d, "core_cylinders.csv"))
    except OSError as e:
        sys.exit(f"plot_study.py: {e}")
    fig, axes = plt.subplots(2, 2, figsize=(10, 10), sharex=True, sharey=True)
    r_wire = 0.5e-3
    for ax, case in zip(axes.flat, cases):
        shape = read_csv(os.path.join(d, case["case"], "shape_core.csv"))
        for c in cylinders:
            ax.add_patch(plt.Circle((1e3 * float(c["x_core"]), 1e3 * float(c["y_core"])),
                                    1e3 * float(c["radius"]), color="0.75"))
        surf = winding_surface(cylinders, r_wire)
        ax.plot([1e3 * p[0] for p in surf], [1e3 * p[1] for p in surf], ":", color="0.5",
                lw=0.8, label="wire centre on the core")
        xs = [1e3 * float(p["x_core"]) for p in shape]
        ys = [1e3 * float(p["y_core"]) for p in shape]
        ax.plot(xs, ys, "-", color="tab:orange", lw=2.2, solid_capstyle="round")
        ax.plot(xs, ys, ".", color="tab:red", ms=3)
        contact = [(x, y) for x, y, p in zip(xs, ys, shape) if p["in_contact"] == "1"]
        if contact:
            ax.plot(*zip(*contact), "o", mfc="none", mec="tab:blue", ms=4, label="in contact")
        with open(os.path.join(d, case["case"], "summary.json")) as f:
            summary = json.load(f)
        k = summary.get("bulging_index")
        if k is not None:
            ax.plot([xs[k]], [ys[k]], "*", color="tab:red", ms=12, label="largest stand-off")
        ax.set_title(f'{float(case["core_speed_rpm"]):.0f} rpm, {float(case["tension_N"]):.0f} N:'
                     f' bulging {float(case["bulging_height_mm"]):.3f} mm')
        ax.set_aspect("equal")
        ax.grid(True, lw=0.3)
    for ax in axes[1]:
        ax.set_xlabel("x, core frame [mm]")
    for ax in axes[:, 0]:
        ax.set_ylabel("y, core frame [mm]")
    axes[0, 0].legend(loc="center", fontsize=8)
    fig.suptitle("Wire after 1 3/4 core turns (2 x 2 study)")
    fig.tight_layout()
    out = os.path.join(d, "study.png")
    fig.savefig(out, dpi=110)
    print(f"plot_study.py: wrote {out}")


if __name__ == "__main__":
    main()
