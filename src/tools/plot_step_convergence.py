#!/usr/bin/python3
"""Error of a Newton-step method against its step, for one or more cases.

usage: plot_step_convergence.py OUT.png TITLE REF H=RUN [H=RUN ...] [-- TITLE REF H=RUN ...]
  each case: a title, the reference run's folder and the runs at steps H [s]
  (folders written by wire_sim run). Prints a Markdown table per case (the
  bulging error and the wound curve's distance from the reference, as
  compare_runs.py measures them, and the wall time) and draws both errors
  against the step on log-log axes, with slopes 1/2 and 1 for the order.
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from compare_runs import load  # noqa: E402
from convergence_table import distance_to_polyline  # noqa: E402

DIAMETER = 1.0e-3  # [m], the Table 1 wire


def errors(ref_dir, run_dir):
    """Relative bulging error [-] and wound-curve distance over d [-]."""
    rs, rp, _, _ = load(ref_dir)
    s, p, _, _ = load(run_dir)
    rw, w = rs["wound_points"], s["wound_points"]
    curve = max(max(distance_to_polyline(x, rp[:rw]) for x in p[:w]),
                max(distance_to_polyline(x, p[:w]) for x in rp[:rw])) / DIAMETER
    bulge = abs(s["bulging_height_m"] / rs["bulging_height_m"] - 1.0)
    return bulge, curve, s["wall_time_s"]


def cases(args):
    out, current = [], []
    for a in args + ["--"]:
        if a == "--":
            if current:
                out.append((current[0], current[1], [x.split("=", 1) for x in current[2:]]))
            current = []
        else:
            current.append(a)
    return out


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    png, todo = sys.argv[1], cases(sys.argv[2:])
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for title, ref, runs in todo:
        rows = sorted(((float(h), *errors(ref, d)) for h, d in runs), reverse=True)
        print(f"\n{title} (reference {ref})\n")
        print("| step [s] | bulging error | shape (curve) / d | wall time [s] |")
        print("|---|---|---|---|")
        for h, b, c, wall in rows:
            print(f"| {h:g} | {100 * b:.2f} % | {c:.4f} | {wall:.3g} |")
        hs = [r[0] for r in rows]
        for ax, k in zip(axes, (1, 2)):
            ax.loglog(hs, [r[k] for r in rows], "o-", label=title)
    # Slopes 1/2 and 1 through the largest step's mean error.
    for k, (ax, name) in enumerate(zip(axes, ("bulging error [-]", "shape error: curve distance / d [-]"))):
        lines = ax.get_lines()
        h1 = max(max(line.get_xdata()) for line in lines)
        y1 = sum(line.get_ydata()[0] for line in lines) / len(lines)
        lim = ax.get_ylim()
        for order, style in ((0.5, ":"), (1.0, "--")):
            ax.loglog([1e-6, h1], [y1 * (1e-6 / h1) ** order, y1], "k" + style, lw=0.8,
                      label=f"slope {order:g}")
        ax.set_ylim(lim)
        ax.set_xlabel("Newton step [s]")
        ax.set_ylabel(name)
        ax.grid(True, which="both", lw=0.3)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    print(f"\nwrote {png}")


if __name__ == "__main__":
    main()
