#!/usr/bin/python3
"""Error against run time (work-precision diagram) from `wire_sim work-precision`.

usage: plot_work_precision.py OUT.png LABEL=DIR [LABEL=DIR ...]
  reads DIR/work_precision.csv for each case, draws the final-shape error
  (relative to the wire diameter) and the bulging-height error against wall
  time, log-log, one colour per method, one marker per case.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out = sys.argv[1]
    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    colours = {"rkf45": "tab:blue", "symplectic_euler": "tab:orange",
               "symplectic_euler+carry": "tab:green",
               "implicit_euler+carry": "tab:purple", "bdf2+carry": "tab:brown",
               # not a method: the paper's undamped springs against the reference model
               "model:damping_ratio=0": "0.5"}
    markers = ["o", "s", "^", "D"]
    for k, arg in enumerate(sys.argv[2:]):
        label, d = arg.split("=", 1)
        with open(f"{d}/work_precision.csv", newline="") as f:
            rows = [r for r in csv.DictReader(line for line in f if not line.startswith("#"))]
        for method in sorted({r["method"] for r in rows}):
            sel = [r for r in rows if r["method"] == method and r["shape_error_rel_diameter"] != "failed"]
            if not sel:
                continue  # every run of this method failed (listed in the CSV)
            sel.sort(key=lambda r: float(r["wall_time_s"]))
            t = [float(r["wall_time_s"]) for r in sel]
            for ax, key in zip(axes, ["shape_error_rel_diameter", "bulging_error_rel"]):
                e = [max(float(r[key]), 1e-7) for r in sel]
                ax.loglog(t, e, "-", marker=markers[k % len(markers)], color=colours.get(method, "k"),
                          label=f"{method}, {label}")
    axes[0].axhline(0.01, color="0.4", ls=":", lw=1)
    axes[0].text(axes[0].get_xlim()[0], 0.011, " 1 % of the wire diameter", fontsize=8, color="0.3")
    axes[1].axhline(0.02, color="0.4", ls=":", lw=1)
    axes[1].text(axes[1].get_xlim()[0], 0.022, " 2 %", fontsize=8, color="0.3")
    axes[0].set_ylabel("final shape: largest point distance / wire diameter")
    axes[1].set_ylabel("bulging height: relative error")
    for ax in axes:
        ax.set_xlabel("wall time [s]")
        ax.grid(True, which="both", lw=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("Error against run time (reference: rkf45, rtol 1e-8, atol 1e-13)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"plot_work_precision.py: wrote {out}")


if __name__ == "__main__":
    main()
