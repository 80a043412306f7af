#!/usr/bin/env python3
"""Compare a winding machine's run with the simulation (issue 7).

  compare_bags.py RUN.bag --out DIR [--align time|angle]
  compare_bags.py --machine A.bag --sim B.bag --out DIR [--align time|angle]
  compare_bags.py --reference A.bag --sim B.bag --out DIR [--align time|angle]

Reads the machine/* and sim/* topics of docs/MACHINE_INTERFACE.md (one bag
holding both, or two bags), aligns them by header stamp (--align time, the
default) or by spindle angle (--align angle) and writes DIR/summary.json,
DIR/summary.md and PNG plots: tension error (sim - machine) RMS, peak, mean
offset; the lag (positive: the machine lags the simulation); the profile error
(measured points to the simulated wire); the bulging heights; the spindle speed
error. Exit 0 on success, 2 on bad input (the message names what is wrong).
summary.json is written last and atomically: when it exists, the run finished.

--reference takes a simulated cell's bag (winding_cell.launch record:=true)
in place of the machine's: its sim/* topics play the machine's part, so two
scene variants, or two runs of the cell, are compared the same way.

Custom messages are deserialized from the definitions stored in the bag, so
the package's generated Python messages need not be importable.
"""
import argparse
import json
import math
import os
import sys
import tempfile

import numpy as np

# The numerics (interpolation, lag, distances) live beside this script.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from series_math import (MIN_SAMPLES, RAD_S_PER_RPM, estimate_lag, hermite,  # noqa: E402
                         monotone_angle, point_to_polyline, rms)

# Errors are "sim minus machine"; percentages are of the machine's mean.
CONVENTIONS = {
    "error": "sim - machine",
    "lag_s": "positive: the machine lags the simulation, machine(t) ~ sim(t - lag_s)",
    "percent": "of the machine's value (mean measured tension, bulging height)",
}
OUTPUT_FILES = ("summary.json", "summary.md", "tension_vs_angle.png", "profile_overlay.png",
                "spindle_speed.png")
TYPES = {   # relative topic -> (expected type, required)
    "spindle/state": ("sensor_msgs/JointState", True),
    "tension/measured": ("coil_winding_sim/WireTension", True),
    "spindle/command": ("sensor_msgs/JointState", False),
    "tension/command": ("coil_winding_sim/TensionSetpoint", False),
    "profile": ("sensor_msgs/PointCloud2", False),
}
JOINT = "spindle"


class InputError(Exception):
    """Bad input: reported on stderr, exit 2."""


# ---------------------------------------------------------------------------
# Reading
# ---------------------------------------------------------------------------
def _norm(topic):
    return topic.lstrip("/")


def read_role(paths, ns):
    """The ns/* topics (ns = machine or sim) from the bag(s) at paths:
    {relative topic: [(stamp [s], msg)]} in bag order."""
    import rosbag   # late: --help works without ROS
    wanted = {ns + "/" + rel: rel for rel in TYPES}
    found = {}
    for path in paths:
        try:
            bag = rosbag.Bag(path)
        except Exception as e:  # not a bag, truncated, unindexed ...
            raise InputError("cannot read bag %s: %s" % (path, e))
        with bag:
            info = bag.get_type_and_topic_info().topics
            topics = [t for t in info if _norm(t) in wanted]
            for t in topics:
                rel = wanted[_norm(t)]
                if info[t].msg_type != TYPES[rel][0]:
                    raise InputError("topic %s in %s has type %s, expected %s"
                                     % (_norm(t), path, info[t].msg_type, TYPES[rel][0]))
            if topics:
                for topic, msg, _ in bag.read_messages(topics=topics):
                    rel = wanted[_norm(topic)]
                    found.setdefault(rel, []).append((msg.header.stamp.to_sec(), msg))
    for rel, (_, required) in TYPES.items():
        if required and not found.get(rel):
            raise InputError("topic %s/%s is missing (no messages in %s)" % (ns, rel, ", ".join(paths)))
    for rel, items in found.items():
        check_stamps(ns + "/" + rel, np.array([s for s, _ in items]))
    return found


def check_stamps(topic, stamps):
    """Header stamps must be set and strictly increasing (interpolation needs it)."""
    if len(stamps) and np.all(stamps == 0):
        raise InputError("topic %s: header stamps are all zero (unset)" % topic)
    bad = np.nonzero(np.diff(stamps) <= 0)[0]
    if len(bad):
        i = int(bad[0]) + 1
        raise InputError("topic %s: header stamps not strictly increasing: message %d has stamp "
                         "%.6f s, message %d before it %.6f s" % (topic, i, stamps[i], i - 1, stamps[i - 1]))


def joint_series(topic, items, need_position):
    """Stamps, angle [rad] (None without position) and speed [rad/s] of the spindle joint."""
    t = np.array([s for s, _ in items])
    pos, vel = [], []
    for k, (_, m) in enumerate(items):
        if JOINT not in m.name:
            raise InputError("topic %s: message %d (stamp %.6f s) has no joint '%s' (names: %s)"
                             % (topic, k, t[k], JOINT, list(m.name)))
        j = list(m.name).index(JOINT)
        pos.append(m.position[j] if len(m.position) > j else math.nan)
        vel.append(m.velocity[j] if len(m.velocity) > j else math.nan)
    pos, vel = np.array(pos), np.array(vel)
    if np.isnan(pos).any():
        if need_position:
            k = int(np.nonzero(np.isnan(pos))[0][0])
            raise InputError("topic %s: message %d has no position for joint '%s'" % (topic, k, JOINT))
        pos = None
    if np.isnan(vel).any():
        if pos is None:
            raise InputError("topic %s: joint '%s' has neither velocity nor position" % (topic, JOINT))
        vel = np.gradient(pos, t)   # derive the speed from the angle
    return t, pos, vel


def cloud_points(msg):
    """(N x 3 points [m], stand_off [m] or None) of a PointCloud2, finite points only."""
    formats = {1: "i1", 2: "u1", 3: "i2", 4: "u2", 5: "i4", 6: "u4", 7: "f4", 8: "f8"}
    order = ">" if msg.is_bigendian else "<"
    fields = {f.name: f for f in msg.fields}
    for name in ("x", "y", "z"):
        if name not in fields:
            raise InputError("profile cloud has no field '%s' (fields: %s)" % (name, sorted(fields)))
    names = [n for n in ("x", "y", "z", "stand_off") if n in fields]
    dtype = np.dtype({"names": names, "formats": [order + formats[fields[n].datatype] for n in names],
                      "offsets": [fields[n].offset for n in names], "itemsize": msg.point_step})
    data = bytes(msg.data)
    rows = [np.frombuffer(data, dtype=dtype, count=msg.width, offset=r * msg.row_step)
            for r in range(msg.height)]
    arr = np.concatenate(rows) if rows else np.zeros(0, dtype=dtype)
    pts = np.stack([arr["x"], arr["y"], arr["z"]], axis=1).astype(float)
    so = arr["stand_off"].astype(float) if "stand_off" in names else None
    ok = np.isfinite(pts).all(axis=1)
    return pts[ok], (so[ok] if so is not None else None)


# ---------------------------------------------------------------------------
# The comparison
# ---------------------------------------------------------------------------
def compare(machine, sim, align, max_lag):
    """Summary dict (SI in, units in every key) and arrays for the plots."""
    notes = []
    tms, thm, wm = joint_series("machine/spindle/state", machine["spindle/state"], True)
    tss, ths, ws = joint_series("sim/spindle/state", sim["spindle/state"], True)
    tmt = np.array([s for s, _ in machine["tension/measured"]])
    Tm = np.array([m.tension for _, m in machine["tension/measured"]], float)
    tst = np.array([s for s, _ in sim["tension/measured"]])
    Ts = np.array([m.tension for _, m in sim["tension/measured"]], float)
    for topic, n in (("machine/spindle/state", len(tms)), ("sim/spindle/state", len(tss)),
                     ("machine/tension/measured", len(tmt)), ("sim/tension/measured", len(tst))):
        if n < MIN_SAMPLES:
            raise InputError("too few samples to align: %s has %d (need %d)" % (topic, n, MIN_SAMPLES))

    # Time overlap of the required traces: compare only where both have data.
    m_span = (max(tms[0], tmt[0]), min(tms[-1], tmt[-1]))
    s_span = (max(tss[0], tst[0]), min(tss[-1], tst[-1]))
    lo, hi = max(m_span[0], s_span[0]), min(m_span[1], s_span[1])
    if hi <= lo:
        raise InputError("no time overlap between machine and sim: machine stamps %.6f..%.6f s, "
                         "sim stamps %.6f..%.6f s" % (m_span + s_span))

    # Each tension sample's spindle angle, from its own side's spindle state.
    am = hermite(tmt, tms, thm)
    as_ = hermite(tst, tss, ths)

    if align == "time":
        sel = (tmt >= lo) & (tmt <= hi)
        if sel.sum() < MIN_SAMPLES:
            raise InputError("too few samples to align by time: %d machine tension samples in the "
                             "overlap %.6f..%.6f s (need %d)" % (sel.sum(), lo, hi, MIN_SAMPLES))
        Ts_at = hermite(tmt[sel], tst, Ts)
        wsel = (tms >= lo) & (tms <= hi)
        w_err = hermite(tms[wsel], tss, ws) - wm[wsel]
    else:
        um, keep_m = monotone_angle(am)
        us, keep_s = monotone_angle(as_)
        if keep_s.sum() < MIN_SAMPLES or keep_m.sum() < MIN_SAMPLES:
            raise InputError("too few samples to align by angle: the spindle turns in %d machine and "
                             "%d sim tension samples (need %d)" % (keep_m.sum(), keep_s.sum(), MIN_SAMPLES))
        # The common range, reaching a micro-radian beyond the sim's end (as
        # wire_sim calibrate's misfit does): a machine sample at the sim's
        # last angle must not come and go with the angle's last bits.
        ulo = max(um[keep_m][0], us[keep_s][0])
        uhi = min(um[keep_m][-1], us[keep_s][-1] + 1e-6)
        sel = keep_m & (um >= ulo) & (um <= uhi) & (tmt >= lo) & (tmt <= hi)
        if sel.sum() < MIN_SAMPLES:
            raise InputError("too few samples to align by angle: %d machine tension samples in the "
                             "common angle range %.3f..%.3f rad (need %d)" % (sel.sum(), ulo, uhi, MIN_SAMPLES))
        Ts_at = hermite(um[sel], us[keep_s], Ts[keep_s])
        uwm, kwm = monotone_angle(thm)
        uws, kws = monotone_angle(ths)
        wsel = kwm & (uwm >= max(uws[kws][0], uwm[kwm][0])) & (uwm <= uws[kws][-1])
        w_err = hermite(uwm[wsel], uws[kws], ws[kws]) - wm[wsel]

    err = Ts_at - Tm[sel]
    mean_m = float(np.mean(Tm[sel]))
    pct = (lambda v: 100.0 * v / mean_m) if mean_m != 0 else (lambda v: None)
    s = {"align": align, "conventions": CONVENTIONS}
    s["overlap_start_s"], s["overlap_end_s"] = float(lo), float(hi)
    s["tension"] = {
        "samples": int(sel.sum()),
        "machine_mean_N": mean_m,
        "sim_mean_N": float(np.mean(Ts_at)),
        "mean_offset_N": float(np.mean(err)),
        "rms_N": rms(err),
        "peak_N": float(np.max(np.abs(err))),
        "std_N": float(np.std(err)),
    }
    s["tension"].update({"mean_offset_pct": pct(s["tension"]["mean_offset_N"]),
                         "rms_pct": pct(s["tension"]["rms_N"]),
                         "peak_pct": pct(s["tension"]["peak_N"])})

    # Lag over time, whatever the alignment (an angle alignment hides it).
    lag, info = estimate_lag(tmt, Tm, tst, Ts, max_lag)
    lag_w, info_w = estimate_lag(tms, wm, tss, ws, max_lag)
    s["lag"] = {"lag_s": lag, "tension_residual_rms_N": info if lag is not None else None,
                "spindle_speed_lag_s": lag_w,
                "spindle_speed_residual_rms_rad_per_s": info_w if lag_w is not None else None,
                "max_lag_s": max_lag,
                "method": "least squares of machine(t) - sim(t - lag) (cubic Hermite, golden section) "
                          "after a coarse cross-correlation search"}
    if lag is None:
        notes.append("tension lag not estimated: %s" % info)
    if lag_w is None:
        notes.append("spindle speed lag not estimated: %s" % info_w)

    s["spindle_speed"] = {"samples": int(len(w_err)), "rms_rad_per_s": rms(w_err),
                          "rms_rpm": rms(w_err) / RAD_S_PER_RPM if len(w_err) else None,
                          "machine_max_rpm": float(np.max(np.abs(wm))) / RAD_S_PER_RPM}

    plots = {"tension": (am, Tm, as_, Ts, am[sel], err),
             "speed": (tms, wm, tss, ws)}
    s["profile"], plots["profile"] = compare_profiles(machine, sim, align, (tms, thm), (tss, ths),
                                                      lo, hi, notes)
    s["notes"] = notes
    return s, plots


def compare_profiles(machine, sim, align, m_spindle, s_spindle, lo, hi, notes):
    """Profile and bulging comparison: each machine cloud matched to the sim
    cloud nearest in stamp (align time) or spindle angle (align angle)."""
    if "profile" not in machine or "profile" not in sim:
        missing = [n + "/profile" for n, d in (("machine", machine), ("sim", sim)) if "profile" not in d]
        notes.append("profile comparison skipped: %s missing" % " and ".join(missing))
        return {"compared": False, "reason": "%s missing" % " and ".join(missing)}, None
    mc = [(t, cloud_points(m)) for t, m in machine["profile"]]
    sc = [(t, cloud_points(m)) for t, m in sim["profile"]]
    sc = [(t, c) for t, c in sc if len(c[0]) >= 2]   # a polyline needs two points
    if not sc:
        notes.append("profile comparison skipped: no sim/profile cloud with 2 points or more")
        return {"compared": False, "reason": "empty sim/profile"}, None
    st = np.array([t for t, _ in sc])
    if align == "angle":
        # Angle at each cloud's stamp, each side from its own spindle (made increasing).
        def angle_at(tq, spindle):
            t, th = spindle
            sign = 1.0 if th[-1] >= th[0] else -1.0
            return sign * np.interp(tq, t, th)
        skey = angle_at(st, s_spindle)
    pairs = []
    for t, (pts, so) in mc:
        if not (lo <= t <= hi) or len(pts) == 0:
            continue
        if align == "time":
            k, key_gap = int(np.argmin(np.abs(st - t))), None
        else:
            a = float(angle_at(t, m_spindle))
            k = int(np.argmin(np.abs(skey - a)))
            key_gap = float(abs(skey[k] - a))
        spts, sso = sc[k][1]
        d = point_to_polyline(pts, spts)
        pairs.append({"machine_stamp_s": float(t), "sim_stamp_s": float(st[k]),
                      "angle_gap_rad": key_gap, "points": int(len(pts)),
                      "rms_mm": rms(d) * 1e3, "max_mm": float(np.max(d)) * 1e3,
                      "_d": d, "_m": (pts, so), "_s": (spts, sso)})
    if not pairs:
        notes.append("profile comparison skipped: no machine/profile cloud in the overlap")
        return {"compared": False, "reason": "no machine/profile cloud in the overlap"}, None
    last = pairs[-1]
    all_d = np.concatenate([p["_d"] for p in pairs])
    out = {"compared": True, "pairs": len(pairs),
           "last": {k: v for k, v in last.items() if not k.startswith("_")},
           "all_pairs": {"rms_mm": rms(all_d) * 1e3, "max_mm": float(np.max(all_d)) * 1e3,
                         "largest_pair_rms_mm": max(p["rms_mm"] for p in pairs),
                         "max_stamp_gap_s": max(abs(p["machine_stamp_s"] - p["sim_stamp_s"]) for p in pairs)}}
    # Bulging: the largest stand_off in a profile.
    if last["_m"][1] is None:
        notes.append("bulging not compared: machine/profile has no stand_off field")
        out["bulging"] = {"compared": False, "reason": "machine/profile has no stand_off field"}
    elif last["_s"][1] is None:
        notes.append("bulging not compared: sim/profile has no stand_off field")
        out["bulging"] = {"compared": False, "reason": "sim/profile has no stand_off field"}
    else:
        bm, bs = float(np.max(last["_m"][1])) * 1e3, float(np.max(last["_s"][1])) * 1e3
        diffs = [float(np.max(p["_s"][1]) - np.max(p["_m"][1])) * 1e3 for p in pairs
                 if p["_m"][1] is not None and p["_s"][1] is not None]
        out["bulging"] = {"compared": True, "machine_mm": bm, "sim_mm": bs, "diff_mm": bs - bm,
                          "diff_pct": 100.0 * (bs - bm) / bm if bm != 0 else None,
                          "all_pairs_diff_rms_mm": rms(np.array(diffs)),
                          "all_pairs_diff_max_abs_mm": float(np.max(np.abs(diffs)))}
    return out, last


# ---------------------------------------------------------------------------
# Output
# ---------------------------------------------------------------------------
def fmt(v, spec=".4g"):
    return "n/a" if v is None else format(v, spec)


def summary_markdown(s, sources):
    t, lag, w, p = s["tension"], s["lag"], s["spindle_speed"], s["profile"]
    lines = ["# Machine run vs simulation", "",
             "Sources: %s. Aligned by %s; errors are sim - machine; lag > 0: the machine lags."
             % (sources, "header stamp" if s["align"] == "time" else "spindle angle"), "",
             "| quantity | value |", "|---|---|",
             "| tension samples compared | %d |" % t["samples"],
             "| machine mean tension | %s N |" % fmt(t["machine_mean_N"]),
             "| tension mean offset | %s N (%s %%) |" % (fmt(t["mean_offset_N"]), fmt(t["mean_offset_pct"], ".3g")),
             "| tension RMS error | %s N (%s %%) |" % (fmt(t["rms_N"]), fmt(t["rms_pct"], ".3g")),
             "| tension peak error | %s N (%s %%) |" % (fmt(t["peak_N"]), fmt(t["peak_pct"], ".3g")),
             "| lag (tension) | %s ms |" % fmt(None if lag["lag_s"] is None else lag["lag_s"] * 1e3),
             "| lag (spindle speed) | %s ms |" % fmt(None if lag["spindle_speed_lag_s"] is None
                                                  else lag["spindle_speed_lag_s"] * 1e3),
             "| spindle speed RMS error | %s rpm |" % fmt(w["rms_rpm"])]
    if p.get("compared"):
        lines += ["| profile pairs compared | %d |" % p["pairs"],
                  "| profile RMS / largest, last pair | %s / %s mm |" % (fmt(p["last"]["rms_mm"]), fmt(p["last"]["max_mm"])),
                  "| profile RMS / largest, all pairs | %s / %s mm |" % (fmt(p["all_pairs"]["rms_mm"]),
                                                                      fmt(p["all_pairs"]["max_mm"]))]
        b = p["bulging"]
        if b["compared"]:
            lines += ["| bulging height machine / sim | %s / %s mm |" % (fmt(b["machine_mm"]), fmt(b["sim_mm"])),
                      "| bulging difference | %s mm (%s %%) |" % (fmt(b["diff_mm"]), fmt(b["diff_pct"], ".3g"))]
    if s["notes"]:
        lines += ["", "Notes:", ""] + ["- " + n for n in s["notes"]]
    return "\n".join(lines) + "\n"


def write_atomic(path, text):
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(path), prefix=".tmp_")
    # mkstemp makes the file private (0600); an output gets the usual mode
    # (0644 under the common umask 022).
    umask = os.umask(0)
    os.umask(umask)
    os.fchmod(fd, 0o666 & ~umask)
    with os.fdopen(fd, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def make_plots(out, plots, profile_out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    am, Tm, as_, Ts, a_sel, err = plots["tension"]
    turns = 1 / (2 * math.pi)
    fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(9, 6))
    ax1.plot(as_ * turns, Ts, lw=0.8, label="sim")
    ax1.plot(am * turns, Tm, lw=0.8, alpha=0.8, label="machine")
    ax1.set_ylabel("tension [N]")
    ax1.legend()
    ax2.plot(a_sel * turns, err, lw=0.8, color="k")
    ax2.set_ylabel("sim - machine [N]")
    ax2.set_xlabel("spindle angle [turns]")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "tension_vs_angle.png"), dpi=110)
    plt.close(fig)

    tms, wm, tss, ws = plots["speed"]
    rpm = 1.0 / RAD_S_PER_RPM
    fig, ax = plt.subplots(figsize=(9, 3.5))
    ax.plot(tss - tms[0], ws * rpm, lw=0.8, label="sim")
    ax.plot(tms - tms[0], wm * rpm, lw=0.8, alpha=0.8, label="machine")
    ax.set_xlabel("time from the machine's first stamp [s]")
    ax.set_ylabel("spindle speed [rpm]")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "spindle_speed.png"), dpi=110)
    plt.close(fig)

    if plots["profile"] is None:
        return
    last = plots["profile"]
    mp, sp = last["_m"][0] * 1e3, last["_s"][0] * 1e3
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 5))
    ax1.plot(sp[:, 0], sp[:, 1], lw=0.8, label="sim wire")
    ax1.plot(mp[:, 0], mp[:, 1], ".", ms=2, label="machine points")
    ax1.set_aspect("equal")
    ax1.set_xlabel("x [mm] (core)")
    ax1.set_ylabel("y [mm] (core)")
    ax1.set_title("cross-section")
    ax1.legend()
    ax2.plot(sp[:, 2], np.hypot(sp[:, 0], sp[:, 1]), lw=0.8, label="sim wire")
    ax2.plot(mp[:, 2], np.hypot(mp[:, 0], mp[:, 1]), ".", ms=2, label="machine points")
    ax2.set_xlabel("z along the core axis [mm]")
    ax2.set_ylabel("distance from the axis [mm]")
    ax2.set_title("along the axis")
    fig.suptitle("profile at machine stamp %.3f s: RMS %.4f mm, largest %.4f mm"
                 % (last["machine_stamp_s"], last["rms_mm"], last["max_mm"]))
    fig.tight_layout()
    fig.savefig(os.path.join(out, "profile_overlay.png"), dpi=110)
    plt.close(fig)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] + ".",
                                formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    p.add_argument("bag", nargs="?", help="one bag with both machine/* and sim/* topics")
    p.add_argument("--machine", help="bag with the machine/* topics")
    p.add_argument("--sim", help="bag with the sim/* topics")
    p.add_argument("--reference", help="a simulated cell's bag whose sim/* topics take the "
                   "machine's part (e.g. another scene variant)")
    p.add_argument("--out", required=True, help="output directory")
    p.add_argument("--align", choices=("time", "angle"), default="time")
    p.add_argument("--max-lag", type=float, default=0.25, help="[s] lag search range (default 0.25)")
    p.add_argument("--no-plots", action="store_true", help="summary only")
    args = p.parse_args(argv)
    if args.bag and (args.machine or args.sim or args.reference):
        p.error("give either one bag, or --machine (or --reference) and --sim")
    if args.machine and args.reference:
        p.error("--machine and --reference exclude each other")
    if not args.bag and not ((args.machine or args.reference) and args.sim):
        p.error("give one bag, or --machine (or --reference) and --sim")

    # Remove stale outputs first: a failed run must not leave an old summary behind.
    os.makedirs(args.out, exist_ok=True)
    for name in OUTPUT_FILES:
        path = os.path.join(args.out, name)
        if os.path.exists(path):
            os.remove(path)
    try:
        m_paths = [args.bag] if args.bag else [args.machine or args.reference]
        s_paths = [args.bag] if args.bag else [args.sim]
        for path in set(m_paths + s_paths):
            if not os.path.isfile(path):
                raise InputError("no such bag: %s" % path)
        machine = read_role(m_paths, "sim" if args.reference else "machine")
        sim = read_role(s_paths, "sim")
        summary, plots = compare(machine, sim, args.align, args.max_lag)
    except InputError as e:
        print("compare_bags: error: %s" % e, file=sys.stderr)
        return 2
    summary["machine_bag"], summary["sim_bag"] = m_paths[0], s_paths[0]
    if not args.no_plots:
        make_plots(args.out, plots, summary["profile"])
    sources = args.bag if args.bag else "%s (%s), %s (sim)" % (
        args.machine or args.reference, "machine" if args.machine else "reference", args.sim)
    md = summary_markdown(summary, sources)
    write_atomic(os.path.join(args.out, "summary.md"), md)
    write_atomic(os.path.join(args.out, "summary.json"), json.dumps(summary, indent=2) + "\n")
    sys.stdout.write(md)
    return 0


if __name__ == "__main__":
    sys.exit(main())
