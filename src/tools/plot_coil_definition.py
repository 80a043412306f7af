#!/usr/bin/python3
"""Draws the definitions of layers, gaps and overlaps (docs/coil_definition.png).

A section of a coil through the core axis: turns as circles of the wire's
diameter on the core's surface (layer 1) and in the grooves of the layer
below (layer 2, sqrt(3)/2 d higher), with a gap (axial spacing beyond d)
and an overlap (a turn on a neighbour where it should lie beside it).

usage: plot_coil_definition.py OUT.png
"""
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402

d = 1.0  # wire diameter [mm]
rise = math.sqrt(3.0) / 2.0 * d

fig, ax = plt.subplots(figsize=(9, 4.2))
# The core's surface and the flanges.
ax.fill_between([-1.2, 8.7], [-0.6, -0.6], [0.0, 0.0], color="0.8")
ax.text(3.7, -0.35, "core surface", ha="center", fontsize=9)
for left in (-0.3, 7.4):
    ax.fill_between([left, left + 0.3], [-0.6, -0.6], [3.2, 3.2], color="0.7")
ax.text(-0.15, 3.3, "flange", ha="center", fontsize=9)


def turn(x, y, color, label=None):
    ax.add_patch(Circle((x, y), d / 2, facecolor=color, edgecolor="k", lw=0.8))
    if label:
        ax.text(x, y, label, ha="center", va="center", fontsize=8)


# Layer 1: turns side by side, with one gap of 0.4 d before turn 5.
layer1 = [0.5, 1.5, 2.5, 3.5, 4.9, 5.9, 6.9]
for k, x in enumerate(layer1):
    turn(x, d / 2, "#9ecae1", str(k + 1))
# Layer 2: in the grooves, sqrt(3)/2 d higher; one turn (12) on top of a
# neighbour of its own layer: an overlap.
layer2 = [6.4, 5.4, 4.2, 3.0, 2.0]
for k, x in enumerate(layer2):
    # Over the gap the groove is wider: the turn sinks into it.
    below = [abs(x - x1) for x1 in layer1]
    half = min(below)
    y = d / 2 + math.sqrt(max(d * d - half * half, 0.0))
    turn(x, y, "#fdae6b", str(8 + k))
turn(2.0 + 0.5, d / 2 + rise + rise, "#e6550d", "13")

# Annotations: the layer rise, a gap, the overlap.
for y in (d / 2, d / 2 + rise):
    ax.plot([5.9, 8.3], [y, y], ":", color="0.4", lw=0.8)
ax.annotate("", xy=(8.2, d / 2 + rise), xytext=(8.2, d / 2),
            arrowprops=dict(arrowstyle="<->", lw=0.8))
ax.text(8.3, d / 2 + rise / 2, r"$\frac{\sqrt{3}}{2}d$", va="center", fontsize=11)
ax.annotate("", xy=(4.9, -0.9), xytext=(3.5, -0.9), arrowprops=dict(arrowstyle="<->", lw=0.8))
ax.text(4.2, -1.25, "spacing 1.4 d: gap 0.4 d", ha="center", fontsize=9)
ax.annotate("overlap: layer 3 where the\ntraverse lays layer 2", xy=(2.5, d / 2 + 2 * rise),
            xytext=(-0.2, 3.6), fontsize=9, arrowprops=dict(arrowstyle="->", lw=0.8))
ax.text(5.4, 2.55, "layer 2 (in the grooves)", fontsize=9, ha="center")
ax.text(8.9, 0.2, "layer 1", fontsize=9, va="center")
ax.set_xlim(-1.5, 9.8)
ax.set_ylim(-1.5, 4.4)
ax.set_aspect("equal")
ax.set_xlabel("along the core axis [mm]")
ax.set_ylabel("above the core surface [mm]")
ax.set_title("Turns, layers, gaps and overlaps (section through the core axis)")
fig.tight_layout()
fig.savefig(sys.argv[1] if len(sys.argv) > 1 else "coil_definition.png", dpi=110)
