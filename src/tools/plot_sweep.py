#!/usr/bin/python3
"""Plots a sweep written by `wire_sim sweep`: a heat map of one figure over two
swept keys, or curves of it against one key (one curve per value of a second).

usage: plot_sweep.py DIR [--value COLUMN] [--x KEY] [--y KEY] [--scale S] [--label TEXT]
                      [--limit L] [--log] [--title TEXT] [--out FILE]
  DIR/results.csv in, DIR/sweep.png (or FILE) out. COLUMN: a column of
  results.csv (default bulging_height_m, shown in mm); KEY: a swept key
  (default the first two). --limit marks the cases whose value (in the shown
  unit) exceeds L (red frame, ✗): the process window is the rest. --log: a logarithmic
  colour scale. Cases that failed or did not finish are marked "failed".
"""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.colors  # noqa: E402
import matplotlib.patches  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402


def number(text):
    try:
        return float(text)
    except ValueError:
        return None


def key_label(key):
    """A swept key with its unit, where the key says it or the scene defines it."""
    units = {"process.tension": "N", "process.core_speed": "rad/s"}
    if key in units:
        return f"{key} [{units[key]}]"
    for suffix, unit in (("_rpm", "rpm"), ("_m", "m"), ("_s", "s"), ("_N", "N")):
        if key.endswith(suffix):
            return f"{key} [{unit}]"
    return key


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir")
    ap.add_argument("--value", default="bulging_height_m")
    ap.add_argument("--x")
    ap.add_argument("--y")
    ap.add_argument("--scale", type=float)
    ap.add_argument("--label")
    ap.add_argument("--limit", type=float)
    ap.add_argument("--log", action="store_true")
    ap.add_argument("--title")
    ap.add_argument("--out")
    a = ap.parse_args()
    path = os.path.join(a.dir, "results.csv")
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"plot_sweep.py: {path} has no cases")
    header = list(rows[0].keys())
    keys = header[1:header.index("status")]
    x = a.x or keys[0]
    y = a.y or (keys[1] if len(keys) > 1 and keys[1] != x else None)
    for k in (x, y):
        if k is not None and k not in keys:
            sys.exit(f"plot_sweep.py: '{k}' is not a swept key (swept: {', '.join(keys)})")
    if a.value not in header:
        sys.exit(f"plot_sweep.py: no column '{a.value}' in {path}")
    scale = a.scale if a.scale is not None else (1e3 if a.value.endswith("_m") else 1.0)
    label = a.label or (a.value[:-2] + " [mm]" if a.value.endswith("_m") and scale == 1e3
                        else a.value)

    xs = sorted({number(r[x]) for r in rows})
    ys = sorted({number(r[y]) for r in rows}) if y else [None]
    grid = [[None] * len(xs) for _ in ys]
    for r in rows:
        v = number(r[a.value]) if r["status"] == "ok" else None
        j = xs.index(number(r[x]))
        i = ys.index(number(r[y])) if y else 0
        grid[i][j] = None if v is None else v * scale

    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    if y and len(xs) > 1 and len(ys) > 1:
        data = [[float("nan") if v is None else v for v in row] for row in grid]
        norm = matplotlib.colors.LogNorm() if a.log else None
        im = ax.imshow(data, origin="lower", aspect="auto", cmap="viridis", norm=norm,
                       interpolation="nearest")
        ax.set_xticks(range(len(xs)), [f"{v:g}" for v in xs])
        ax.set_yticks(range(len(ys)), [f"{v:g}" for v in ys])
        for i, row in enumerate(grid):
            for j, v in enumerate(row):
                over = a.limit is not None and v is not None and v > a.limit
                # Dark text on light cells, light text on dark ones.
                rgb = im.cmap(im.norm(v))[:3] if v is not None else (0, 0, 0)
                light = 0.299 * rgb[0] + 0.587 * rgb[1] + 0.114 * rgb[2] > 0.5
                ax.text(j, i, "failed" if v is None else f"{v:.3g}" + (" ✗" if over else ""),
                        ha="center", va="center", color="black" if light else "white",
                        fontsize=8, fontweight="bold" if over else "normal")
                if over:
                    ax.add_patch(matplotlib.patches.Rectangle(
                        (j - 0.45, i - 0.45), 0.9, 0.9, fill=False, edgecolor="tab:red",
                        linewidth=1.5))
        fig.colorbar(im, ax=ax, label=label)
        ax.set_ylabel(key_label(y))
    else:
        for i, row in enumerate(grid):
            pts = [(xv, v) for xv, v in zip(xs, row) if v is not None]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-",
                    label=None if ys[i] is None else f"{y} = {ys[i]:g}")
        if y:
            ax.legend()
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
    ax.set_xlabel(key_label(x))
    title = a.title or f"{label} over {len(rows)} cases"
    if a.limit is not None:
        title += f"\n(red, ✗: above {a.limit:g})"
    ax.set_title(title)
    fig.tight_layout()
    out = a.out or os.path.join(a.dir, "sweep.png")
    fig.savefig(out, dpi=110)
    print(f"plot_sweep.py: wrote {out}")


if __name__ == "__main__":
    main()
