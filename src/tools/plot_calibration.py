#!/usr/bin/env python3
"""Tension and profile of a machine recording against the simulation before
and after a calibration (wire_sim calibrate writes the two replays).

  plot_calibration.py MACHINE.bag BEFORE.bag AFTER.bag OUTDIR [OFFSET_BEFORE_MM OFFSET_AFTER_MM]

Writes OUTDIR/calibration.png: the tension error (sim - machine) over the
spindle angle, before and after; the last measured profile against the
simulated wire nearest to it in spindle angle (the distance from the core
axis over the angle about it); and each of its points' distance to that
wire [um], before and after, the points first moved towards the axis by
the profile sensor's offset the calibration found (the optional offsets).
The differences are micrometres and hundredths of a newton: the errors are
drawn, not only the traces.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from compare_bags import cloud_points, joint_series, read_role  # noqa: E402
from series_math import hermite, monotone_angle, point_to_polyline  # noqa: E402


def series(role, ns):
    t, theta, _ = joint_series(ns + "/spindle/state", role["spindle/state"], True)
    tt = np.array([s for s, _ in role["tension/measured"]])
    tension = np.array([m.tension for _, m in role["tension/measured"]])
    angle = hermite(tt, t, theta)
    clouds = [(s, cloud_points(m)) for s, m in role.get("profile", [])]
    return (t, theta), angle, tension, clouds


def main(argv):
    if len(argv) not in (5, 7):
        print(__doc__, file=sys.stderr)
        return 2
    machine_bag, before_bag, after_bag, out = argv[1:5]
    offsets_mm = [float(v) for v in argv[5:7]] if len(argv) == 7 else [0.0, 0.0]
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    m_spindle, m_angle, m_tension, m_clouds = series(read_role([machine_bag], "machine"), "machine")
    sims = [(name, series(read_role([path], "sim"), "sim"))
            for name, path in (("before", before_bag), ("after", after_bag))]
    turns = 1.0 / (2.0 * math.pi)
    fig, (ax1, ax2, ax3) = plt.subplots(3, 1, figsize=(9, 11))
    # Tension by angle: each side's tension at its own spindle angle.
    um, keep_m = monotone_angle(m_angle)
    for (name, (_, angle, tension, _)), style in zip(sims, ("--", "-")):
        us, keep_s = monotone_angle(angle)
        sel = keep_m & (um >= us[keep_s][0]) & (um <= us[keep_s][-1])
        err = hermite(um[sel], us[keep_s], tension[keep_s]) - m_tension[sel]
        ax1.plot(um[sel] * turns, err, style, lw=1.0,
                 label="%s: RMS %.4f N" % (name, math.sqrt(np.mean(err ** 2))))
    ax1.axhline(0.0, color="0.6", lw=0.5)
    ax1.set_xlabel("spindle angle [turns]")
    ax1.set_ylabel("tension, sim - machine [N]")
    ax1.legend()
    ax1.set_title("tension at the nozzle")

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
        for (name, (spindle, _, _, clouds)), style, offset in zip(sims, ("--", "-"), offsets_mm):
            good = [(s, c) for s, c in clouds if len(c[0]) >= 2]
            if not good:
                continue
            keys = np.array([np.interp(s, *spindle) for s, _ in good])
            spts = good[int(np.argmin(np.abs(keys - a)))][1][0]
            sphi, sr = polar(spts)
            ax2.plot(sphi, sr, style, lw=1.2, label="simulation " + name)
            # The sensor's offset taken off: each point moved radially.
            rr = np.hypot(pts[:, 0], pts[:, 1])
            scale = np.where(rr > 0, (rr - 1e-3 * offset) / np.where(rr > 0, rr, 1.0), 1.0)
            moved = pts * np.stack([scale, scale, np.ones_like(scale)], axis=1)
            d = 1e6 * point_to_polyline(moved, spts)
            ax3.plot(phi, d, style, lw=1.0,
                     label="%s: RMS %.2f um" % (name, math.sqrt(np.mean(d ** 2))))
        ax2.set_xlabel("angle about the core axis [deg] (core frame)")
        ax2.set_ylabel("distance from the core axis [mm]")
        ax2.set_title("profile at %.3f s (spindle at %.2f turns)" % (stamp, a * turns))
        ax2.legend()
        ax3.set_xlabel("angle about the core axis [deg] (core frame)")
        ax3.set_ylabel("measured point to simulated wire [um]")
        ax3.set_title("the profile's error (the sensor's offset %s)" %
                      ("removed: %.4f / %.4f mm" % tuple(offsets_mm) if any(offsets_mm) else "kept"))
        ax3.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "calibration.png"), dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
