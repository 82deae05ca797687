#!/bin/bash
# The rviz screenshot of docs/ros.md ("The TF tree"): the ROS bridge's TF tree and grid as rviz draws them with
# fixed frame `map`, on a synthetic corridor drive. Not a test and not part of the build or of CI: rviz, Xvfb
# and the Python ROS client are only needed here.
#
#   scripts/ros_rviz_screenshot.sh [OUT.png]          (default docs/img/ros-rviz.png)
#
# What runs, all on this machine, each started here and stopped by its pid at the end (SIGINT, SIGKILL after 10 s):
#   - a ROS master (rosmaster --core) on a free port, with ROS_HOME/ROS_LOG_DIR in a scratch directory;
#   - a synthetic drive: `slambooster synth --scene corridor --stress drive --seed 0` (FRAMES frames, 160x120,
#     the corridor driven straight at 1.05-1.45 m/s): depth and the base's wheel odometry (odometry.txt);
#   - a fake robot (scripts/ros_fake_robot.py): the drive's odometry on /odom and as odom -> base_link on /tf,
#     the mount base_link -> camera_depth_optical_frame (1.2 m up) on /tf_static, and the depth on
#     /camera/depth/image, at the recorded pace times SPEED (the layout of test_ros_tf_tree);
#   - the bridge (build/ros/slambooster_ros) with ~odom_topic /odom and ~push_socket: it hands the depth and the
#     odometry to the daemon and publishes map -> odom, ~odometry and ~map (the grid, in slambooster_grid);
#   - the daemon (build/daemon/slamboosterd) with the push source, source.odometry=socket (the odometry comes
#     from the bridge, as on a robot) and a navigation grid whose up the robot's odometry says ("up": "none");
#   - Xvfb (1024x768) and rviz with docs/ros-rviz.rviz (fixed frame map).
# It waits until the daemon has processed the whole drive and the bridge's grid has content, lets rviz draw,
# grabs the screen (xwd), converts it to PNG (ImageMagick) and shrinks it (pngquant, optipng when present).
#
# Debian 12 packages it needs beyond scripts/install_deps.sh (and a build with the ROS component):
#   apt-get install --no-install-recommends rviz xvfb x11-apps imagemagick python3-rospy python3-nav-msgs \
#     python3-sensor-msgs python3-tf2-msgs python3-pil        (optional: pngquant optipng)
# Environment: BUILD (build), FRAMES (240), SPEED (0.5), DISPLAY_NUMBER (97), KEEP=1 keeps the scratch directory.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${BUILD:-$ROOT/build}
OUT=${1:-$ROOT/docs/img/ros-rviz.png}
FRAMES=${FRAMES:-240}
SPEED=${SPEED:-0.5}
DISPLAY_NUMBER=${DISPLAY_NUMBER:-97}
PY=/usr/bin/python3  # Debian's python3-rospy is for the system interpreter

for tool in "$BUILD/tools/slambooster/slambooster" "$BUILD/daemon/slamboosterd" "$BUILD/ros/slambooster_ros"; do
  [ -x "$tool" ] || { echo "ros_rviz_screenshot: $tool missing: build slambooster slamboosterd slambooster_ros in $BUILD (BUILD=...)" >&2; exit 2; }
done
for tool in rosmaster rviz Xvfb xwd convert; do
  command -v "$tool" >/dev/null || { echo "ros_rviz_screenshot: $tool not found: apt-get install rviz xvfb x11-apps imagemagick (see the top of $0)" >&2; exit 2; }
done
$PY -c 'import rospy, nav_msgs.msg, sensor_msgs.msg, tf2_msgs.msg, PIL' 2>/dev/null ||
  { echo "ros_rviz_screenshot: $PY cannot import rospy/nav_msgs/sensor_msgs/tf2_msgs/PIL: apt-get install python3-rospy python3-nav-msgs python3-sensor-msgs python3-tf2-msgs python3-pil" >&2; exit 2; }

WORK=$(mktemp -d /tmp/ros_rviz_screenshot.XXXXXX)
PIDS=()
stop_all() {  # in reverse order of start, each by its own pid: SIGINT, then SIGKILL after 10 s
  local i pid
  for ((i = ${#PIDS[@]} - 1; i >= 0; i--)); do
    pid=${PIDS[i]}
    kill -INT "$pid" 2>/dev/null || continue
    for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
  done
  if [ "${KEEP:-0}" = 1 ]; then echo "ros_rviz_screenshot: logs kept in $WORK"; else rm -rf "$WORK"; fi
}
trap stop_all EXIT
fail() { echo "ros_rviz_screenshot: $*; logs in $WORK" >&2; KEEP=1; exit 1; }
wait_until() {  # wait_until SECONDS WHAT COMMAND...
  local seconds=$1 what=$2; shift 2
  for _ in $(seq $((seconds * 5))); do "$@" >/dev/null 2>&1 && return 0; sleep 0.2; done
  fail "$what not within $seconds s"
}

PORT=$($PY -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
export ROS_MASTER_URI=http://127.0.0.1:$PORT/ ROS_HOME=$WORK ROS_LOG_DIR=$WORK ROS_IP=127.0.0.1
rosmaster --core -p "$PORT" -w 3 >"$WORK/rosmaster.log" 2>&1 &
PIDS+=($!)
wait_until 15 "the ROS master" $PY -c 'import rosgraph, sys; sys.exit(0 if rosgraph.Master("/probe").is_online() else 1)'

"$BUILD/tools/slambooster/slambooster" synth --scene corridor --stress drive --seed 0 --frames "$FRAMES" \
  --width 160 --height 120 --fx 120.3 --fy 120 --threads 1 --overwrite --out "$WORK/drive" >"$WORK/synth.log" 2>&1 ||
  fail "slambooster synth failed"
# The volume where the drive's calibration.json hints it (as the ROS tests do), 128^3.
$PY - "$WORK" <<'EOF'
import json, sys
work = sys.argv[1]
c = json.load(open(work + "/drive/calibration.json"))
json.dump({"volume_resolution": 128, "knobs": "csr=1,ir=1", "volume_size_m": c["volume_size_m"],
           "initial_position": c["volume_initial_position"]}, open(work + "/pipeline.json", "w"))
# Up from the robot's odometry; 0.1 m cells, no finer than the volume's 9 cm voxels (finer ones leave stripes).
json.dump({"up": "none", "resolution_m": 0.1}, open(work + "/navmap.json", "w"))
EOF
DEPTH_SCALE=$($PY -c "import json; print(json.load(open('$WORK/drive/calibration.json'))['depth_scale'])")

"$BUILD/ros/slambooster_ros" __name:=slambooster _socket:="$WORK/sb.sock" _reconnect_s:=0.1 \
  _push_socket:="$WORK/push.sock" _depth_topic:=/camera/depth/image _push_depth_scale:="$DEPTH_SCALE" \
  _odom_topic:=/odom _odom_camera_frame:=camera_depth_optical_frame _map_period_s:=1 _cloud_period_s:=0 \
  >"$WORK/bridge.log" 2>&1 &
PIDS+=($!)
"$BUILD/daemon/slamboosterd" --input "$WORK/push.sock" --out "$WORK/out" --socket "$WORK/sb.sock" \
  --pacing recorded --at-end stop --controller fixed --set source.type=push --set source.odometry=socket \
  --set slam.threads=1 --set "slam.pipeline_config=$WORK/pipeline.json" --set "output.navmap=$WORK/navmap.json" \
  --set output.navmap_period_s=1 --set output.rotation.mode=never >"$WORK/daemon.log" 2>&1 &
PIDS+=($!)
$PY "$ROOT/scripts/ros_fake_robot.py" --sequence "$WORK/drive" --speed "$SPEED" --lead-s 0.5 \
  --wait-socket "$WORK/sb.sock" --done-file "$WORK/robot.done" >"$WORK/fake_robot.log" 2>&1 &
PIDS+=($!)

Xvfb ":$DISPLAY_NUMBER" -screen 0 1024x768x24 -nolisten tcp >"$WORK/xvfb.log" 2>&1 &
PIDS+=($!)
wait_until 15 "Xvfb on :$DISPLAY_NUMBER" xwd -root -display ":$DISPLAY_NUMBER" -silent
DISPLAY=:$DISPLAY_NUMBER LIBGL_ALWAYS_SOFTWARE=1 rviz -d "$ROOT/docs/ros-rviz.rviz" >"$WORK/rviz.log" 2>&1 &
PIDS+=($!)

# The whole drive published and processed, then a grid with occupied and free cells.
DRIVE_S=$($PY -c "print(int(($FRAMES / 30.0) / $SPEED) + 120)")
wait_until "$DRIVE_S" "the fake robot's last frame" test -e "$WORK/robot.done"
sleep 3  # the last frames' poses
$PY - >"$WORK/grid.log" 2>&1 <<'EOF' || fail "no grid with occupied cells on /slambooster/map"
import rospy, sys, time
from nav_msgs.msg import OccupancyGrid
rospy.init_node("grid_probe", anonymous=True, disable_signals=True)
deadline = time.time() + 30
while time.time() < deadline:
    g = rospy.wait_for_message("/slambooster/map", OccupancyGrid, timeout=30)
    occupied = sum(1 for v in g.data if v > 50)
    free = sum(1 for v in g.data if v == 0)
    print(f"grid {g.info.width}x{g.info.height} at {g.info.resolution} m: {occupied} occupied, {free} free")
    if occupied > 100 and free > 100:
        sys.exit(0)
    time.sleep(1)
sys.exit(1)
EOF
cat "$WORK/grid.log"
sleep 8  # rviz draws the latest grid and frames

mkdir -p "$(dirname "$OUT")"
xwd -root -display ":$DISPLAY_NUMBER" -silent >"$WORK/screen.xwd"
convert "xwd:$WORK/screen.xwd" "png:$WORK/screen.png"
if command -v pngquant >/dev/null; then
  pngquant --force --quality 60-90 --output "$WORK/screen-q.png" "$WORK/screen.png" && mv "$WORK/screen-q.png" "$WORK/screen.png"
fi
if command -v optipng >/dev/null; then optipng -quiet -o5 "$WORK/screen.png"; fi
cp "$WORK/screen.png" "$OUT"
echo "ros_rviz_screenshot: wrote $OUT ($(stat -c %s "$OUT") bytes)"
grep -h "map -> odom\|odometry from" "$WORK/bridge.log" | head -3 || true
