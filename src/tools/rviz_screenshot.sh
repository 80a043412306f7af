#!/bin/bash
# A screenshot of the cell in rviz, as a user sees it: the cell launched
# with the given arguments (a job that ends, held at its end) on a ROS
# master of its own, rviz on a virtual screen (Xvfb), the picture taken
# once the job is done and rviz has drawn it.
#
# usage: src/tools/rviz_screenshot.sh OUT.png [roslaunch arguments of winding_cell.launch...]
# e.g.   src/tools/rviz_screenshot.sh docs/rviz_winding_cell.png real_time_factor:=0
# Needs the workspace built and sourced, Xvfb and ImageMagick's import.
set -eu
out=$1
shift
port=${CWS_SCREENSHOT_PORT:-11391}
display=${CWS_SCREENSHOT_DISPLAY:-:91}
work=$(mktemp -d)
cleanup() {
  kill -INT "${launch:-}" 2>/dev/null || true
  sleep 2
  kill "${launch:-}" "${xvfb:-}" 2>/dev/null || true
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
Xvfb "$display" -screen 0 1200x800x24 -nolisten tcp > "$work/xvfb.log" 2>&1 &
xvfb=$!
export DISPLAY=$display ROS_MASTER_URI=http://127.0.0.1:$port ROS_LOG_DIR=$work/ros_log
sleep 1
roslaunch -p "$port" coil_winding_sim winding_cell.launch stop_at_end:=true "$@" \
  > "$work/launch.log" 2>&1 &
launch=$!
# The job's end on cell_status, then time for rviz to draw it.
for _ in $(seq 600); do
  if rostopic echo -n 1 /cell_status/job_done 2>/dev/null | grep -q True; then break; fi
  if ! kill -0 "$launch" 2>/dev/null; then
    echo "rviz_screenshot: the launch ended before the job did:" >&2
    tail -20 "$work/launch.log" >&2
    exit 1
  fi
  sleep 0.5
done
sleep "${CWS_SCREENSHOT_SETTLE:-6}"
import -window root "$out"
echo "rviz_screenshot: $out"
