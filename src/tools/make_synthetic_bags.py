#!/usr/bin/env python3
"""Synthetic bags for compare_bags.py (issue 7): a "simulation" bag with the
sim/* topics of docs/MACHINE_INTERFACE.md from closed-form signals, and a
"machine" bag made from the same messages renamed to machine/* with a known
perturbation (tension offset and noise, time shift, profile offset and scale,
bulge scale, a missing topic, non-monotonic stamps, a renamed joint).

  make_synthetic_bags.py --sim-bag S.bag --machine-bag M.bag [perturbation]
  make_synthetic_bags.py --combined-bag C.bag [perturbation]     one bag, both
  make_synthetic_bags.py --from-sim-bag run.bag --machine-bag M.bag [...]
      perturbs the sim/* topics of an existing bag (e.g. the simulation's)

The closed-form signals (t from the first stamp, SI units):
  spindle   omega(t) = omega_max min(t / t_ramp, 1)  (1200 rpm after 0.5 s),
            theta(t) its integral; command = state
  tension   command 30 N; measured T(t) = 30 (1 - exp(-t / 0.05))
            + A sin(lobes theta(t)), A = 1 N, lobes = 2 (a ripple tied to the angle)
  port      x = 30 mm, y = 0, z = pitch theta / (2 pi)
  profile   the last --profile-turns turns of a helix wound on a cylinder,
            core radius 10 mm, wire radius 0.25 mm, pitch 0.5 mm, points every
            0.5 mm of arc, in frame core; centre-line radius
            r = r_core + r_wire + stand_off, stand_off = B c(psi)^8,
            c = cos(psi) (two bulges at psi = 0 and pi, B = 0.3 mm).
The machine's profile samples the same helix at other points (spacing 0.4 mm,
shifted), like a line sensor that does not see the simulation's mass points.

Only Debian's python3-rosbag, -genpy, -numpy, -sensor-msgs, -geometry-msgs
and -std-msgs are needed; the package's custom messages are built from msg/
with genpy.dynamic (the package's generated Python need not be importable).
"""
import argparse
import copy
import math
import os
import sys

import numpy as np

import genpy
import genpy.dynamic
import rosbag
from geometry_msgs.msg import PointStamped
from sensor_msgs.msg import JointState, PointCloud2, PointField
from std_msgs.msg import Header

# The rpm conversion, shared with compare_bags.py (beside this script).
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from series_math import RAD_S_PER_RPM  # noqa: E402

PKG = "coil_winding_sim"

# The closed-form signals' constants (SI units).
T0 = 100.0                      # first stamp [s] (not 0: stamps are absolute)
OMEGA_MAX = 1200.0 * RAD_S_PER_RPM   # [rad/s]
T_RAMP = 0.5                    # [s] spindle ramp time
TENSION_CMD = 30.0              # [N]
TENSION_RISE = 0.05             # [s] time constant of the tension's rise
RIPPLE_N = 1.0                  # [N] ripple amplitude
RIPPLE_LOBES = 2                # ripple periods per spindle turn
R_CORE = 10e-3                  # [m]
R_WIRE = 0.25e-3                # [m]
PITCH = 0.5e-3                  # [m] axial advance per turn
BULGE = 0.3e-3                  # [m] largest stand-off (at psi = 0, pi)
SIM_SPACING = 0.5e-3            # [m] arc length between the sim's profile points
MACHINE_SPACING = 0.4e-3        # [m] ... between the machine's
PORT_X = 30e-3                  # [m]


# ---------------------------------------------------------------------------
# Messages
# ---------------------------------------------------------------------------
def _msg_dirs():
    """Where the package's msg/ files are: next to the sources (devel space,
    the relay script runs this file from the source tree) or via rospkg."""
    here = os.path.dirname(os.path.abspath(__file__))
    dirs = [os.path.join(here, "..", "..", "msg")]
    try:
        import rospkg
        dirs.append(os.path.join(rospkg.RosPack().get_path(PKG), "msg"))
    except Exception:  # not on ROS_PACKAGE_PATH: the source tree must do
        pass
    return dirs


def custom_message_class(name):
    """coil_winding_sim/<name> built from msg/<name>.msg with genpy.dynamic."""
    for d in _msg_dirs():
        path = os.path.join(d, name + ".msg")
        if os.path.isfile(path):
            with open(path) as f:
                text = f.read()
            # Dependencies follow the main text, as in a bag's connection header.
            cat = text + "\n" + "=" * 80 + "\nMSG: std_msgs/Header\n" + Header._full_text
            full = PKG + "/" + name
            return genpy.dynamic.generate_dynamic(full, cat)[full]
    raise RuntimeError("message definition %s.msg not found in %s" % (name, _msg_dirs()))


def stamp(t):
    # To the nearest nanosecond (from_sec truncates: 100.02 became
    # 100.019999999, a stamp 1 ns off the replay's grid).
    ns = int(round(t * 1e9))
    return genpy.Time(ns // 1000000000, ns % 1000000000)


def make_cloud(t, frame, fields):
    """PointCloud2 with float32 fields, fields = [(name, array)] (same length)."""
    names = [n for n, _ in fields]
    dtype = np.dtype({"names": names, "formats": ["<f4"] * len(names),
                      "offsets": [4 * i for i in range(len(names))],
                      "itemsize": 4 * len(names)})
    n = len(fields[0][1])
    arr = np.zeros(n, dtype=dtype)
    for name, values in fields:
        arr[name] = values
    msg = PointCloud2()
    msg.header = Header(stamp=stamp(t), frame_id=frame)
    msg.height, msg.width = 1, n
    msg.fields = [PointField(name=nm, offset=4 * i, datatype=PointField.FLOAT32, count=1)
                  for i, nm in enumerate(names)]
    msg.is_bigendian = False
    msg.point_step = 4 * len(names)
    msg.row_step = msg.point_step * n
    msg.data = arr.tobytes()
    msg.is_dense = True
    return msg


def cloud_array(msg):
    """The cloud's points as a numpy structured array (a writable copy)."""
    formats = {1: "i1", 2: "u1", 3: "i2", 4: "u2", 5: "i4", 6: "u4", 7: "f4", 8: "f8"}
    order = ">" if msg.is_bigendian else "<"
    dtype = np.dtype({"names": [f.name for f in msg.fields],
                      "formats": [order + formats[f.datatype] for f in msg.fields],
                      "offsets": [f.offset for f in msg.fields],
                      "itemsize": msg.point_step})
    n = msg.width * msg.height
    if msg.row_step != msg.width * msg.point_step:   # padded rows: take each row
        rows = [np.frombuffer(msg.data, dtype=dtype, count=msg.width, offset=r * msg.row_step)
                for r in range(msg.height)]
        return np.concatenate(rows) if rows else np.zeros(0, dtype=dtype)
    return np.frombuffer(msg.data, dtype=dtype, count=n).copy()


# ---------------------------------------------------------------------------
# Closed-form signals
# ---------------------------------------------------------------------------
def spindle(t):
    """Spindle angle [rad] and speed [rad/s] at t [s] after the start."""
    t = np.asarray(t, dtype=float)
    omega = OMEGA_MAX * np.minimum(t / T_RAMP, 1.0)
    theta = np.where(t < T_RAMP, 0.5 * OMEGA_MAX * t * t / T_RAMP,
                     OMEGA_MAX * (0.5 * T_RAMP + (t - T_RAMP)))
    return theta, omega


def tension(t):
    theta, _ = spindle(t)
    return TENSION_CMD * (1.0 - np.exp(-t / TENSION_RISE)) + RIPPLE_N * np.sin(RIPPLE_LOBES * theta)


def helix(phi):
    """Wire centre line wound up to spindle angle phi (core frame): x, y, z,
    stand_off. The wire laid at spindle angle phi sits at core angle psi = -phi."""
    psi = -phi
    stand_off = BULGE * np.cos(psi) ** 8
    r = R_CORE + R_WIRE + stand_off
    return r * np.cos(psi), r * np.sin(psi), PITCH * phi / (2 * math.pi), stand_off


def profile_points(theta, turns, spacing, phase):
    """Points of the last `turns` turns wound by spindle angle theta, every
    `spacing` of arc (approximately), starting `phase` (0..1) of a spacing in."""
    dphi = spacing / (R_CORE + R_WIRE)
    start = max(0.0, theta - turns * 2 * math.pi)
    phi = np.arange(start + phase * dphi, theta, dphi)
    if theta > 0:
        phi = np.append(phi, theta)   # both end at the last laid point
    return helix(phi)


def synthetic_sim_messages(duration, rate_hz, profile_rate_hz, profile_turns, record_delay,
                           tension_command=TENSION_CMD):
    """[(topic, msg, bag_time)] of every sim/* topic, in time order."""
    WireTension = custom_message_class("WireTension")
    TensionSetpoint = custom_message_class("TensionSetpoint")
    out = []
    n = int(round(duration * rate_hz)) + 1
    ts = np.arange(n) / rate_hz
    theta, omega = spindle(ts)
    tens = tension(ts)
    for k, t in enumerate(ts):
        st = T0 + t
        cmd = JointState(header=Header(stamp=stamp(st)), name=["spindle"],
                         position=[], velocity=[float(omega[k])], effort=[])
        state = JointState(header=Header(stamp=stamp(st)), name=["spindle"],
                           position=[float(theta[k])], velocity=[float(omega[k])], effort=[])
        tc = TensionSetpoint(header=Header(stamp=stamp(st)), tension=tension_command)
        tm = WireTension(header=Header(stamp=stamp(st)), tension=float(tens[k]))
        port = PointStamped(header=Header(stamp=stamp(st), frame_id="world"))
        port.point.x, port.point.y = PORT_X, 0.0
        port.point.z = PITCH * float(theta[k]) / (2 * math.pi)
        port_meas = copy.deepcopy(port)
        bag_t = st + record_delay   # written after it held
        out += [("sim/spindle/command", cmd, bag_t), ("sim/spindle/state", state, bag_t),
                ("sim/tension/command", tc, bag_t), ("sim/tension/measured", tm, bag_t),
                ("sim/port/command", port, bag_t), ("sim/port/position", port_meas, bag_t)]
    n_prof = int(math.floor(duration * profile_rate_hz + 1e-9)) + 1
    for k in range(n_prof):
        t = k / profile_rate_hz
        th, _ = spindle(t)
        x, y, z, so = profile_points(float(th), profile_turns, SIM_SPACING, 0.0)
        msg = make_cloud(T0 + t, "core", [("x", x), ("y", y), ("z", z), ("stand_off", so)])
        out.append(("sim/profile", msg, T0 + t + record_delay))
    out.sort(key=lambda item: item[2])
    return out


def resample_machine_profile(msg, theta, profile_turns):
    """The machine's line sensor: the same helix at its own points."""
    x, y, z, so = profile_points(theta, profile_turns, MACHINE_SPACING, 0.37)
    return make_cloud(msg.header.stamp.to_sec(), "core",
                      [("x", x), ("y", y), ("z", z), ("stand_off", so)])


# ---------------------------------------------------------------------------
# The perturbation: sim/* -> machine/*
# ---------------------------------------------------------------------------
def strip(topic):
    return topic.lstrip("/")


def perturb(messages, args, synthetic):
    """machine/* messages from sim/* messages: [(topic, msg, bag_time)]."""
    rng = np.random.default_rng(args.seed)
    args.rng = rng   # the profile's noise draws from the same stream
    shift = genpy.Duration(0, int(round(args.time_shift * 1e9)))
    drop = {strip(d).split("/", 1)[1] if strip(d).startswith(("sim/", "machine/")) else strip(d)
            for d in args.drop_topic}
    out = []
    for topic, msg, bag_t in messages:
        rel = strip(topic)[len("sim/"):]
        if rel in drop:
            continue
        msg = copy.deepcopy(msg)
        if hasattr(msg, "header"):
            msg.header.stamp = msg.header.stamp + shift
        if rel == "tension/measured":
            msg.tension = float(msg.tension + args.tension_offset
                                + (rng.normal(0.0, args.tension_noise) if args.tension_noise > 0 else 0.0))
        if rel.startswith("spindle/") and args.rename_joint:
            msg.name = [args.rename_joint if n == "spindle" else n for n in msg.name]
        if rel == "profile":
            if synthetic:
                th, _ = spindle(msg.header.stamp.to_sec() - args.time_shift - T0)
                msg = resample_machine_profile(msg, float(th), args.profile_turns)
            msg = perturb_cloud(msg, args)
        bag_t = float(bag_t) + args.time_shift
        out.append(("machine/" + rel, msg, bag_t))
    for rel in args.non_monotonic:
        rel = strip(rel)
        rel = rel.split("/", 1)[1] if rel.startswith(("sim/", "machine/")) else rel
        idx = [i for i, (tp, _, _) in enumerate(out) if tp == "machine/" + rel]
        if len(idx) < 4:
            raise SystemExit("make_synthetic_bags: --non-monotonic %s: too few messages" % rel)
        # Swap the stamps of two neighbours in the middle: message k+1 (k = n // 2)
        # then carries an earlier stamp than message k; the bag order is unchanged.
        a, b = out[idx[len(idx) // 2]][1], out[idx[len(idx) // 2 + 1]][1]
        a.header.stamp, b.header.stamp = b.header.stamp, a.header.stamp
    return out


def perturb_cloud(msg, args):
    """Profile perturbation in frame core: scale about the origin, then move
    every point radially (away from the core axis z) by the profile offset plus
    (bulge_scale - 1) stand_off plus its noise; stand_off changes by the same
    radial amount."""
    if (args.profile_scale == 1.0 and args.profile_offset_mm == 0.0 and args.bulge_scale == 1.0
            and args.profile_noise_mm == 0.0 and not args.drop_stand_off):
        return msg
    arr = cloud_array(msg)
    names = arr.dtype.names
    x = arr["x"].astype(float) * args.profile_scale
    y = arr["y"].astype(float) * args.profile_scale
    z = arr["z"].astype(float) * args.profile_scale
    so = arr["stand_off"].astype(float) if "stand_off" in names else np.zeros(len(arr))
    dr = args.profile_offset_mm * 1e-3 + (args.bulge_scale - 1.0) * so
    if args.profile_noise_mm > 0:
        dr = dr + args.rng.normal(0.0, args.profile_noise_mm * 1e-3, len(arr))
    r = np.hypot(x, y)
    with np.errstate(invalid="ignore", divide="ignore"):
        ux, uy = np.where(r > 0, x / r, 0.0), np.where(r > 0, y / r, 0.0)
    arr["x"], arr["y"], arr["z"] = x + dr * ux, y + dr * uy, z
    if "stand_off" in names:
        # scaling moves the wire off the (unscaled) core surface as well
        arr["stand_off"] = np.hypot(x, y) - r / args.profile_scale + so + dr
    out = copy.deepcopy(msg)
    if args.drop_stand_off and "stand_off" in names:
        keep = [n for n in names if n != "stand_off"]
        return make_cloud(msg.header.stamp.to_sec(), msg.header.frame_id,
                          [(n, arr[n]) for n in keep])
    out.data = arr.tobytes()
    return out


def read_sim_messages(path):
    """[(topic, msg, bag_time)] of the sim/* topics of an existing bag."""
    if not os.path.isfile(path):
        raise SystemExit("make_synthetic_bags: no such bag: %s" % path)
    # TensionSetpoint and WireTension have the same definition, hence the same
    # md5sum: rosbag's reader (which caches classes by md5sum) may hand one out
    # as the other, and the copy would be written with the wrong type. Rebuild
    # them as the type their connection names.
    custom = {PKG + "/" + n: custom_message_class(n) for n in ("TensionSetpoint", "WireTension")}
    out = []
    with rosbag.Bag(path) as bag:
        types = {t: i.msg_type for t, i in bag.get_type_and_topic_info().topics.items()}
        for topic, msg, t in bag.read_messages():
            if strip(topic).startswith("sim/"):
                cls = custom.get(types[topic])
                if cls is not None and msg._type != cls._type:
                    msg = cls(header=msg.header, tension=msg.tension)
                out.append((strip(topic), msg, t.to_sec()))
    if not out:
        raise SystemExit("make_synthetic_bags: %s has no sim/* topic" % path)
    return out


def write_bag(path, messages):
    tmp = path + ".tmp"
    with rosbag.Bag(tmp, "w") as bag:
        for topic, msg, t in sorted(messages, key=lambda item: item[2]):
            bag.write(topic, msg, stamp(t))
    os.replace(tmp, path)   # never a half-written bag under the final name


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--sim-bag", help="write the sim/* topics here")
    p.add_argument("--machine-bag", help="write the perturbed machine/* topics here")
    p.add_argument("--combined-bag", help="write sim/* and machine/* into one bag")
    p.add_argument("--from-sim-bag", help="take the sim/* topics from this bag instead of the closed forms")
    p.add_argument("--duration", type=float, default=2.0, help="[s] (synthetic)")
    p.add_argument("--rate", type=float, default=250.0, help="[Hz] spindle, tension and port (synthetic)")
    p.add_argument("--profile-rate", type=float, default=10.0, help="[Hz] (synthetic)")
    p.add_argument("--profile-turns", type=float, default=2.0, help="turns of wire in a profile (synthetic)")
    p.add_argument("--max-speed-rpm", type=float, default=1200.0,
                   help="[rpm] the spindle's speed after its 0.5 s ramp (synthetic); 0: at rest")
    p.add_argument("--tension-command", type=float, default=TENSION_CMD,
                   help="[N] the commanded tension (synthetic)")
    p.add_argument("--record-delay", type=float, default=0.002,
                   help="[s] each message written this long after its stamp (synthetic); 0 puts the "
                        "commands on the replay's grid")
    g = p.add_argument_group("perturbation of the machine bag")
    g.add_argument("--tension-offset", type=float, default=0.0, help="[N] added to machine/tension/measured")
    g.add_argument("--tension-noise", type=float, default=0.0, help="[N] sigma of Gaussian noise added to it")
    g.add_argument("--seed", type=int, default=1, help="noise seed")
    g.add_argument("--time-shift", type=float, default=0.0,
                   help="[s] added to every machine stamp (positive: the machine lags)")
    g.add_argument("--profile-offset-mm", type=float, default=0.0,
                   help="[mm] radial offset of the machine profile (outward)")
    g.add_argument("--profile-noise-mm", type=float, default=0.0,
                   help="[mm] sigma of Gaussian radial noise on each machine profile point (and its stand_off)")
    g.add_argument("--profile-scale", type=float, default=1.0, help="scale of the machine profile about the origin")
    g.add_argument("--bulge-scale", type=float, default=1.0,
                   help="machine stand-off = this x the simulated one (points move radially)")
    g.add_argument("--drop-stand-off", action="store_true", help="machine profile without a stand_off field")
    g.add_argument("--drop-topic", action="append", default=[], metavar="TOPIC",
                   help="leave this machine topic out, e.g. tension/measured (repeatable)")
    g.add_argument("--non-monotonic", action="append", default=[], metavar="TOPIC",
                   help="swap the stamps of messages n/2 and n/2+1 of this machine topic (repeatable)")
    g.add_argument("--rename-joint", default="", help="call the machine's spindle joint this instead")
    args = p.parse_args(argv)
    if not (args.sim_bag or args.machine_bag or args.combined_bag):
        p.error("give --sim-bag, --machine-bag and/or --combined-bag")

    global OMEGA_MAX
    OMEGA_MAX = args.max_speed_rpm * RAD_S_PER_RPM
    if args.from_sim_bag:
        sim = read_sim_messages(args.from_sim_bag)
    else:
        sim = synthetic_sim_messages(args.duration, args.rate, args.profile_rate, args.profile_turns,
                                     args.record_delay, args.tension_command)
    machine = perturb(sim, args, synthetic=not args.from_sim_bag)
    if args.sim_bag:
        write_bag(args.sim_bag, sim)
    if args.machine_bag:
        write_bag(args.machine_bag, machine)
    if args.combined_bag:
        write_bag(args.combined_bag, sim + machine)
    return 0


if __name__ == "__main__":
    sys.exit(main())
