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
  # The reason last too: a log that keeps only its end still says it.
  echo "rviz_screenshot: $*" >&2
  echo "--- the launch's last lines:" >&2
  tail -30 "$work/launch.log" >&2 || true
  echo "--- Xvfb:" >&2
  tail -5 "$work/xvfb.log" >&2 || true
  echo "--- the launch's processes:" >&2
  pgrep -a -f "roslaunch|rosmaster|rviz|winding_cell_node" >&2 || true
  echo "rviz_screenshot: $*" >&2
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
{ kill -0 "$xvfb" 2>/dev/null && [ "$display" != ":" ]; } || fail "Xvfb did not start (display $display)"
# Every node of its own master on the loopback, by address: no name has
# to resolve (a machine's host name need not).
export DISPLAY=$display ROS_MASTER_URI=http://127.0.0.1:$port ROS_LOG_DIR=$work/ros_log
unset ROS_HOSTNAME
export ROS_IP=127.0.0.1
# The node's console lines reach launch.log as they are written.
export ROSCONSOLE_STDOUT_LINE_BUFFERED=1
setsid roslaunch -p "$port" coil_winding_sim winding_cell.launch stop_at_end:=true "$@" \
  > "$work/launch.log" 2>&1 &
launch=$!
# The job's end, from the node's own console line in the launch's output:
# no subscriber has to start and connect (a Python tool can take seconds
# to start on a loaded machine, which once kept a bounded wait from ever
# seeing the message).
while ! grep -q "job done: " "$work/launch.log" 2>/dev/null; do
  kill -0 "$launch" 2>/dev/null || fail "the launch ended before the job did"
  [ $SECONDS -lt $deadline ] || fail "no 'job done' from the node within ${CWS_SCREENSHOT_DEADLINE:-150} s"
  sleep 0.5
done
# Then pictures until rviz has drawn the scene (more distinct colours than
# its empty window's 1,155), each taken after a pause; the last is kept.
min_colours=${CWS_SCREENSHOT_MIN_COLOURS:-2000}
colours=0
while :; do
  sleep "${CWS_SCREENSHOT_SETTLE:-6}"
  kill -0 "$launch" 2>/dev/null || fail "the launch ended before rviz drew the job"
  timeout -k 2 30 import -window root "$work/shot.png" || fail "import could not take the picture"
  colours=$(identify -format %k "$work/shot.png" 2>/dev/null || echo 0)
  [ "$colours" -gt "$min_colours" ] && break
  if [ $SECONDS -ge $deadline ]; then
    cp "$work/shot.png" "$out"
    fail "rviz drew little within ${CWS_SCREENSHOT_DEADLINE:-150} s: $colours colours in $out"
  fi
done
cp "$work/shot.png" "$out"
echo "rviz_screenshot: $out"
