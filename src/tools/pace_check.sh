#!/bin/bash
# Does the winding cell keep pace with the wall clock? Launches
# winding_cell.launch (no rviz) at real_time_factor 1, commands the core to
# SPEED rad/s, records winding_metrics for SECONDS of wall time and prints:
# the core's angular velocity from the messages' stamps and core_turns,
# whether keeping_pace stayed true, the real-time factors the node reported,
# and the /diagnostics levels seen.
#
# usage: src/tools/pace_check.sh [SPEED_rad_s=20] [SECONDS=10] [extra roslaunch args...]
# needs: the workspace built and sourced (source .ws/devel/setup.bash), Debian's
# python first on PATH; starts its own roscore on port 11411.
set -u
SPEED=${1:-20}
SECONDS_WALL=${2:-10}
shift 2 2>/dev/null || true
export ROS_MASTER_URI=http://localhost:11411
OUT=$(mktemp -d)
if rostopic list > /dev/null 2>&1; then
  echo "pace_check: a ROS master already runs on port 11411; stop it first" >&2
  exit 2
fi
roscore -p 11411 > "$OUT/roscore.log" 2>&1 &
CORE=$!
LAUNCH=
cleanup() {
  [ -n "$LAUNCH" ] && kill -INT "$LAUNCH" 2>/dev/null
  sleep 1
  kill "$CORE" 2>/dev/null
  pkill -f "rosmaster --core -p 11411" 2>/dev/null
  kill $(jobs -p) 2>/dev/null
  wait 2>/dev/null
  rm -rf "$OUT"
}
trap cleanup EXIT
for _ in $(seq 50); do rostopic list > /dev/null 2>&1 && break; sleep 0.2; done
# Subscribers first, so the whole run is seen.
timeout $((SECONDS_WALL + 8)) rostopic echo -p winding_metrics > "$OUT/metrics.csv" 2>/dev/null &
timeout $((SECONDS_WALL + 8)) rostopic echo -p /diagnostics/status[0]/level > "$OUT/diag.csv" 2>/dev/null &
# (The cell runs until stopped.)
roslaunch coil_winding_sim winding_cell.launch rviz:=false "$@" > "$OUT/launch.log" 2>&1 &
LAUNCH=$!
for _ in $(seq 100); do rostopic list 2>/dev/null | grep -q core_speed_setpoint && break; sleep 0.1; done
rostopic pub -1 core_speed_setpoint coil_winding_sim/CoreSpeedSetpoint "{angular_velocity: $SPEED}" > /dev/null 2>&1 &
sleep $((SECONDS_WALL + 3))
/usr/bin/python3 - "$OUT" "$SPEED" <<'PY'
import csv, math, sys
out, speed = sys.argv[1], float(sys.argv[2])
rows = [r for r in csv.DictReader(open(out + "/metrics.csv"))
        if abs(float(r["field.core_angular_velocity"]) - speed) < 1e-9]
if len(rows) < 2:
    sys.exit("pace_check: too few winding_metrics at the commanded speed (see the launch log)")
t = [int(r["field.header.stamp"]) * 1e-9 for r in rows]
turns = [float(r["field.core_turns"]) for r in rows]
rtf = sorted(float(r["field.real_time_factor"]) for r in rows)
behind = [float(r["field.sim_time"]) for r in rows if r["field.keeping_pace"] not in ("1", "True")]
pace = not behind
levels = sorted({l.split(",")[1] for l in open(out + "/diag.csv").read().split()[1:]})
print(f"core: {2 * math.pi * (turns[-1] - turns[0]) / (t[-1] - t[0]):.3f} rad/s from stamps over "
      f"{t[-1] - t[0]:.2f} s (commanded {speed:g}); turns {turns[0]:.2f} -> {turns[-1]:.2f}; "
      f"points at the end {rows[-1]['field.points']}")
print(f"keeping_pace always true: {pace}"
      + (f" (false in {len(behind)} of {len(rows)} messages, simulated t = {behind[0]:.3f} to "
         f"{behind[-1]:.3f} s)" if behind else "")
      + f"; node real-time factor median {rtf[len(rtf) // 2]:.3f} "
      f"(min {rtf[0]:.3f}); /diagnostics levels seen: {levels} (0 OK, 1 WARN, 2 ERROR)")
PY
