#!/usr/bin/python3
"""Draws the definition of the bulging height (docs/bulging_definition.png).

usage: plot_bulging_definition.py OUT.png
"""
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

R, r = 2.5, 0.5  # cylinder radius, wire radius [mm]
centers = [(7.5, 2.5), (-7.5, 2.5), (-7.5, -2.5), (7.5, -2.5)]


def rounded_rectangle(offset, n=40):
    """Hull of the four discs widened by `offset`, counter-clockwise."""
    pts = []
    quadrant = {(7.5, 2.5): 0, (-7.5, 2.5): 1, (-7.5, -2.5): 2, (7.5, -2.5): 3}
    for c in [(7.5, 2.5), (-7.5, 2.5), (-7.5, -2.5), (7.5, -2.5)]:
        q = quadrant[c]
        for k in range(n + 1):
            a = math.pi / 2 * (q + k / n)
            pts.append((c[0] + (R + offset) * math.cos(a), c[1] + (R + offset) * math.sin(a)))
    return pts + pts[:1]


fig, ax = plt.subplots(figsize=(8, 5))
for c in centers:
    ax.add_patch(plt.Circle(c, R, color="0.8"))
hull = rounded_rectangle(0.0)
ax.plot(*zip(*hull), "-", color="0.45", lw=1, label="winding surface: convex hull of the cylinders")
on_core = rounded_rectangle(r)
ax.plot(*zip(*on_core), ":", color="0.3", lw=1, label="wire centreline lying on the core (hull + r)")
# A wound wire that lies on the core except for a span lifted off the bottom.
lift = 1.2
wire = [(x, 2.5 + R + r) for x in [7.5, 0.0, -7.5]]
wire += [(-7.5 - (R + r) * math.sin(a), 2.5 + (R + r) * math.cos(a))
         for a in [k * math.pi / 20 for k in range(11)]]
wire += [(-7.5 - (R + r) * math.sin(a), -2.5 + (R + r) * math.cos(a))
         for a in [math.pi / 2 + k * math.pi / 20 for k in range(11)]]
wire += [(-4.0, -5.5 - 0.6 * lift), (0.0, -5.5 - lift), (4.0, -5.5 - 0.6 * lift), (7.5, -5.5)]
ax.plot(*zip(*wire), "-", color="tab:orange", lw=3, label="wound wire centreline")
ax.annotate("", xy=(0.0, -5.5 - lift), xytext=(0.0, -5.5),
            arrowprops=dict(arrowstyle="<->", color="tab:red", lw=1.5))
ax.annotate("bulging height h: the largest stand-off of the\nwound centreline from the hull widened by r",
            xy=(0.0, -5.5 - lift / 2), xytext=(-12.0, -8.8), color="tab:red", fontsize=9,
            arrowprops=dict(arrowstyle="-", color="tab:red", lw=0.8))
ax.plot([7.5], [-5.5], "ks")
ax.text(8.3, -6.0, "fixed end\n(on a cylinder)", fontsize=9, va="top")
ax.annotate("to the port (wire not yet wound)", xy=(7.5, 5.5), xytext=(9.5, 7.5), fontsize=9,
            arrowprops=dict(arrowstyle="-", color="0.5"))
ax.plot([7.5, 12.0], [5.5, 7.0], "-", color="tab:orange", lw=3, alpha=0.4)
ax.set_aspect("equal")
ax.set_xlim(-13, 17)
ax.set_ylim(-9.5, 9.5)
ax.set_xlabel("x, core frame [mm]")
ax.set_ylabel("y, core frame [mm]")
ax.legend(loc="upper left", fontsize=8)
ax.set_title("Bulging height: stand-off of the wound wire from the core")
fig.tight_layout()
fig.savefig(sys.argv[1] if len(sys.argv) > 1 else "bulging_definition.png", dpi=110)
