#!/bin/bash
# A screenshot of the cell in rviz, as a user sees it: the cell launched
# with the given arguments (a job that ends, held at its end) on a ROS
# master of its own, rviz on a virtual screen (Xvfb), the picture taken
# once the job is done and rviz has drawn it. Every wait is bounded: the
# script ends within CWS_SCREENSHOT_DEADLINE seconds (default 150), and
# says what it waited for, with the launch's last lines, when it gives up.
#
# usage: src/tools/rviz_screenshot.sh OUT.png [roslaunch arguments of winding_cell.launch...]
# e.g.   src/tools/rviz_screenshot.sh docs/rviz_winding_cell.png real_time_factor:=0
# Needs the workspace built and sourced, Xvfb and ImageMagick's import.
set -eu
out=$1
shift
# A free port for the master and a free display (Xvfb picks it: -displayfd),
# unless given: a stale lock or another server cannot stand in the way.
port=${CWS_SCREENSHOT_PORT:-$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')}
deadline=$((SECONDS + ${CWS_SCREENSHOT_DEADLINE:-150}))
work=$(mktemp -d)
# Each background job in its own process group (setsid), so that the
# cleanup reaches rviz and the node too, and a hung one is killed.
stop_group() {
  local pid=$1
  [ -n "$pid" ] || return 0
  kill -INT -- "-$pid" 2>/dev/null || true
  for _ in $(seq 20); do
    kill -0 "$pid" 2>/dev/null || return 0
    sleep 0.5
  done
  kill -KILL -- "-$pid" 2>/dev/null || true
}
cleanup() {
  stop_group "${launch:-}"
  stop_group "${xvfb:-}"
  rm -rf "$work"
}
trap cleanup EXIT
trap "exit 143" TERM INT
fail() {
  echo "rviz_screenshot: $*" >&2
  echo "--- the launch's last lines:" >&2
  tail -30 "$work/launch.log" >&2 || true
  echo "--- Xvfb:" >&2
  tail -5 "$work/xvfb.log" >&2 || true
  exit 1
}
if [ -n "${CWS_SCREENSHOT_DISPLAY:-}" ]; then
  setsid Xvfb "$CWS_SCREENSHOT_DISPLAY" -screen 0 1200x800x24 -nolisten tcp \
    > "$work/xvfb.log" 2>&1 &
  xvfb=$!
  display=$CWS_SCREENSHOT_DISPLAY
  sleep 1
else
  setsid Xvfb -displayfd 3 -screen 0 1200x800x24 -nolisten tcp \
    3> "$work/display" > "$work/xvfb.log" 2>&1 &
  xvfb=$!
  for _ in $(seq 50); do
    [ -s "$work/display" ] && break
    sleep 0.2
  done
  display=:$(head -1 "$work/display" 2>/dev/null)
fi
kill -0 "$xvfb" 2>/dev/null && [ "$display" != ":" ] || fail "Xvfb did not start (display $display)"
# Every node of its own master on the loopback, by a name that always
# resolves (a machine's host name need not).
export DISPLAY=$display ROS_MASTER_URI=http://127.0.0.1:$port ROS_LOG_DIR=$work/ros_log
unset ROS_IP
export ROS_HOSTNAME=localhost
setsid roslaunch -p "$port" coil_winding_sim winding_cell.launch stop_at_end:=true "$@" \
  > "$work/launch.log" 2>&1 &
launch=$!
# The job's end on cell_status, then time for rviz to draw it.
done_seen=false
while [ $SECONDS -lt $deadline ]; do
  if timeout -k 2 5 rostopic echo -n 1 /cell_status/job_done 2>/dev/null | grep -q True; then
    done_seen=true
    break
  fi
  kill -0 "$launch" 2>/dev/null || fail "the launch ended before the job did"
  sleep 0.5
done
$done_seen || fail "no job_done on /cell_status within ${CWS_SCREENSHOT_DEADLINE:-150} s"
sleep "${CWS_SCREENSHOT_SETTLE:-6}"
timeout -k 2 30 import -window root "$out" || fail "import could not take the picture"
echo "rviz_screenshot: $out"
