#!/usr/bin/python3
"""Gaps and overlaps of a two-layer coil against tension and traverse pitch.

Runs wire_sim on config/scenes/two_layers.yaml, shortened to two passes of
seven turns between flanges 8 mm apart, over a grid of supply tensions and
traverse pitches; collects each run's coil report (summary.json "coil") and
the quality figures (the wire's permanent elongation, the load cell's peak
tension and ripple a turn);
writes coil_study.csv and coil_study.md and draws the coils' cross-sections
(coil_cross_section.png): every turn where it crosses the plane through the
core axis and the centre of the core's first cylinder, coloured by layer.

usage: coil_study.py WIRE_SIM OUT_DIR [--jobs N] [--runs RUNS_DIR]
  (the runs' own outputs go to RUNS_DIR, by default OUT_DIR/runs)
"""
import concurrent.futures
import csv
import json
import math
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402

TENSIONS_N = [20.0, 30.0, 70.0]
PITCHES_D = [0.9, 1.0, 1.25, 1.5]  # traverse pitch in wire diameters
D_M = 1.0e-3  # the scene's wire diameter
WIDTH_M = 8.0e-3
BASE = [
    "process.winding_width=%g" % WIDTH_M,
    "process.core_speed_rpm=1200",
]
FIGURE_CASES = [(30.0, 1.0), (30.0, 1.5), (70.0, 1.0), (30.0, 0.9)]


def case_dir(runs, tension, pitch_d):
    return os.path.join(runs, "T%gN_p%gd" % (tension, pitch_d))


def turns_for(pitch_d):
    """Two passes: the port travels W - d each way."""
    per_pass = (WIDTH_M - D_M) / (pitch_d * D_M)
    return round(2.0 * per_pass, 2)


def run_case(wire_sim, scene, runs, tension, pitch_d):
    d = case_dir(runs, tension, pitch_d)
    args = [wire_sim, "run", "--scene", scene, "--out", d]
    for kv in BASE + [
        "process.tension=%g" % tension,
        "process.traverse_pitch=%g" % (pitch_d * D_M),
        "process.turns=%g" % turns_for(pitch_d),
    ]:
        args += ["--set", kv]
    proc = subprocess.run(args, capture_output=True, text=True)
    if proc.returncode != 0:
        return tension, pitch_d, None, proc.stderr.strip().splitlines()[-1:]
    with open(os.path.join(d, "summary.json")) as f:
        return tension, pitch_d, json.load(f), []


def quality_columns(q):
    """The wire's permanent elongation [%], and the load cell's peak tension
    and mean ripple a turn [N] (summary.json "quality"; "" where absent)."""
    def rounded(key, scale=1.0, digits=3):
        v = q.get(key)
        return "" if v is None else round(v * scale, digits)
    return [rounded("plastic_elongation", 100.0), rounded("tension_peak_N", 1.0, 2),
            rounded("tension_ripple_mean_N", 1.0, 3)]


def section(run_dir, angle_rad):
    """Each turn's crossing of the plane at angle_rad about the core axis:
    (axial [mm], height of the centre above the core surface [mm], layer)."""
    with open(os.path.join(run_dir, "shape_core.csv")) as f:
        shape = list(csv.DictReader(f))
    with open(os.path.join(run_dir, "wire.csv")) as f:
        layer = [int(r["layer"]) for r in csv.DictReader(f)]
    out, unwrapped, prev = [], None, None
    for i, r in enumerate(shape):
        if i >= len(layer) or layer[i] == 0:
            break
        a = math.atan2(float(r["y_core"]), float(r["x_core"]))
        if prev is not None:
            step = (a - prev + math.pi) % (2 * math.pi) - math.pi
            u1 = unwrapped + step
            # A crossing of angle_rad + 2 pi k between the two points.
            k = math.floor((u1 - angle_rad) / (2 * math.pi))
            k0 = math.floor((unwrapped - angle_rad) / (2 * math.pi))
            if k != k0:
                target = angle_rad + 2 * math.pi * max(k, k0)
                f = (target - unwrapped) / (u1 - unwrapped)
                p = shape[i - 1]
                z = float(p["z_core"]) + f * (float(r["z_core"]) - float(p["z_core"]))
                s = float(p["stand_off_m"]) + f * (float(r["stand_off_m"]) - float(p["stand_off_m"]))
                out.append((z * 1e3, (s + D_M / 2) * 1e3, layer[i]))
            unwrapped = u1
        else:
            unwrapped = a
        prev = a
    return out


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    wire_sim, out = sys.argv[1], sys.argv[2]
    jobs = int(sys.argv[sys.argv.index("--jobs") + 1]) if "--jobs" in sys.argv else 2
    runs = sys.argv[sys.argv.index("--runs") + 1] if "--runs" in sys.argv else os.path.join(out, "runs")
    here = os.path.dirname(os.path.abspath(__file__))
    scene = os.path.join(here, "..", "..", "config", "scenes", "two_layers.yaml")
    os.makedirs(out, exist_ok=True)
    grid = [(t, p) for t in TENSIONS_N for p in PITCHES_D]
    results = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        for t, p, summary, err in pool.map(lambda c: run_case(wire_sim, scene, runs, *c), grid):
            print("T = %g N, pitch %g d: %s" % (t, p, "done" if summary else "failed %s" % err),
                  file=sys.stderr)
            results[(t, p)] = (summary, err)

    cols = ["tension_N", "pitch_d", "turns", "layers", "gaps", "largest_gap_d", "first_gap_turn",
            "overlaps", "first_overlap_turn", "bulging_layer1_mm", "bulging_layer2_mm",
            "plastic_elongation_pct", "tension_peak_N", "tension_ripple_N",
            "real_time_factor", "status"]
    rows = []
    for t, p in grid:
        summary, err = results[(t, p)]
        if summary is None or summary.get("coil") is None:
            rows.append([t, p] + [""] * (len(cols) - 3) + ["failed: " + " ".join(err)])
            continue
        c = summary["coil"]
        bulge = c["bulging_per_layer_m"] + [float("nan")] * 2
        rows.append([t, p, c["turns"], c["layers"], c["gaps"], round(c["largest_gap_m"] / D_M, 3),
                     c["first_gap_turn"], c["overlaps"], c["first_overlap_turn"],
                     round(bulge[0] * 1e3, 3), round(bulge[1] * 1e3, 3)] +
                    quality_columns(summary.get("quality") or {}) +
                    [round(summary["real_time_factor"], 3), "ok"])
    with open(os.path.join(out, "coil_study.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        w.writerows(rows)
    with open(os.path.join(out, "coil_study.md"), "w") as f:
        f.write("| " + " | ".join(cols) + " |\n|" + "---|" * len(cols) + "\n")
        for r in rows:
            f.write("| " + " | ".join(str(x) for x in r) + " |\n")

    # Cross-sections of a few cases through the first cylinder's centre.
    angle = math.atan2(2.5e-3, 7.5e-3)
    colors = {1: "#9ecae1", 2: "#fdae6b", 3: "#e6550d", 4: "#a63603"}
    fig, axes = plt.subplots(len(FIGURE_CASES), 1, figsize=(8, 2.3 * len(FIGURE_CASES)))
    for ax, (t, p) in zip(axes, FIGURE_CASES):
        summary, _ = results[(t, p)]
        ax.set_title("%g N, pitch %g d" % (t, p), fontsize=10)
        if summary is None:
            ax.text(0.5, 0.5, "run failed", transform=ax.transAxes, ha="center")
            continue
        for z, h, layer in section(case_dir(runs, t, p), angle):
            ax.add_patch(Circle((z, h), 0.5, facecolor=colors.get(layer, "k"), edgecolor="k",
                                lw=0.6))
        first = -0.5
        for x in (first, first + WIDTH_M * 1e3):
            ax.axvline(x, color="0.5", lw=2)
        ax.axhline(0.0, color="0.5", lw=2)
        ax.set_xlim(-1.5, WIDTH_M * 1e3 + 0.5)
        ax.set_ylim(-0.3, 3.6)
        ax.set_aspect("equal")
        ax.set_ylabel("height [mm]")
    axes[-1].set_xlabel("along the core axis from the port's start [mm] "
                        "(blue: layer 1, orange: 2, red: 3)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "coil_cross_section.png"), dpi=100)


if __name__ == "__main__":
    main()
