#!/usr/bin/env python3
"""Tension and profile of a machine recording against the simulation before
and after a calibration (wire_sim calibrate writes the two replays).

  plot_calibration.py MACHINE.bag BEFORE.bag AFTER.bag OUTDIR

Writes OUTDIR/calibration.png: the tension at the nozzle over the spindle
angle (machine, before, after), and the last measured profile against the
simulated wire nearest to it in spindle angle, as the distance from the core
axis over the angle about it.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from compare_bags import cloud_points, joint_series, read_role  # noqa: E402
from series_math import hermite  # noqa: E402


def series(role, ns):
    t, theta, _ = joint_series(ns + "/spindle/state", role["spindle/state"], True)
    tt = np.array([s for s, _ in role["tension/measured"]])
    tension = np.array([m.tension for _, m in role["tension/measured"]])
    angle = hermite(tt, t, theta)
    clouds = [(s, cloud_points(m)) for s, m in role.get("profile", [])]
    return (t, theta), angle, tension, clouds


def main(argv):
    if len(argv) != 5:
        print(__doc__, file=sys.stderr)
        return 2
    machine_bag, before_bag, after_bag, out = argv[1:]
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    m_spindle, m_angle, m_tension, m_clouds = series(read_role([machine_bag], "machine"), "machine")
    sims = [(name, series(read_role([path], "sim"), "sim"))
            for name, path in (("before", before_bag), ("after", after_bag))]
    turns = 1.0 / (2.0 * math.pi)
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 8))
    ax1.plot(m_angle * turns, m_tension, ".", ms=3, color="0.4", label="machine")
    for (name, (_, angle, tension, _)), style in zip(sims, ("--", "-")):
        ax1.plot(angle * turns, tension, style, lw=1.2, label="simulation " + name)
    ax1.set_xlabel("spindle angle [turns]")
    ax1.set_ylabel("tension at the nozzle [N]")
    ax1.legend()
    ax1.set_title("tension")

    # The last measured profile and the simulated wire nearest in angle.
    measured = [(s, c) for s, c in m_clouds if len(c[0])]
    if measured:
        stamp, (pts, _) = measured[-1]
        a = float(np.interp(stamp, *m_spindle))

        def polar(p):
            phi = np.unwrap(np.arctan2(p[:, 1], p[:, 0]))
            return np.degrees(phi), 1e3 * np.hypot(p[:, 0], p[:, 1])

        phi, r = polar(pts)
        ax2.plot(phi, r, ".", ms=3, color="0.4", label="machine")
        for (name, (spindle, _, _, clouds)), style in zip(sims, ("--", "-")):
            good = [(s, c) for s, c in clouds if len(c[0]) >= 2]
            if not good:
                continue
            keys = np.array([np.interp(s, *spindle) for s, _ in good])
            spts = good[int(np.argmin(np.abs(keys - a)))][1][0]
            sphi, sr = polar(spts)
            ax2.plot(sphi, sr, style, lw=1.2, label="simulation " + name)
        ax2.set_xlabel("angle about the core axis [deg] (core frame)")
        ax2.set_ylabel("distance from the core axis [mm]")
        ax2.set_title("profile at %.3f s (spindle at %.2f turns)" % (stamp, a * turns))
        ax2.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "calibration.png"), dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
