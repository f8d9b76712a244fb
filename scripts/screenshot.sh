#!/usr/bin/env bash
# Render a scene in rviz on a virtual X server (Xvfb, mesa's software GL) and save a screenshot.
#
#   scripts/screenshot.sh <scene> <out.png> [--at SECONDS] [--focus X,Y,Z] [--distance M]
#                         [--yaw RAD] [--pitch RAD] [--size WxH] [launch args...]
#
# Starts its own master (a free port) and `roslaunch cga_rigid_sim <scene>.launch rviz:=true`
# (or sim.launch scene:=<scene> when there is no such file) paused, with the package's rviz
# configuration (rviz/cga_rigid_sim.rviz) seen from the given view: orbit about --focus
# (default 0,0,0.8) at --distance (default 3.5 m), --yaw and --pitch as rviz's orbit view. Once
# rviz has subscribed to the node's markers it steps the simulation to --at seconds (default 0)
# with ~step (exactly round(at/dt) steps, dt from the launch args, default 0.001), gives rviz a
# few seconds to draw, grabs the screen (ImageMagick `import`; rviz fills it: --fullscreen, no
# panels) and writes it to <out.png> (--size, default 1000x600; a 128-colour PNG). Further arguments go to roslaunch, e.g. gravity:="[0, 0, 0]".
# Needs the workspace built (scripts/build.sh) and xvfb, rviz, imagemagick
# (scripts/install_deps.sh). Exit status 1 with a message if any part fails.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)

usage() { sed -n '2,17p' "$0"; }
if [[ $# -lt 2 ]]; then usage >&2; exit 2; fi
scene=$1 out=$2
shift 2
at=0 focus=0,0,0.8 distance=3.5 yaw=5.6 pitch=0.45 size=1000x600 dt=0.001
launch_args=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --at) at=$2; shift 2 ;;
    --focus) focus=$2; shift 2 ;;
    --distance) distance=$2; shift 2 ;;
    --yaw) yaw=$2; shift 2 ;;
    --pitch) pitch=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    dt:=*) dt=${1#dt:=}; launch_args+=("$1"); shift ;;
    *:=*) launch_args+=("$1"); shift ;;
    *) echo "screenshot.sh: unknown argument '$1'" >&2; usage >&2; exit 2 ;;
  esac
done
fail() { echo "screenshot.sh: $*" >&2; exit 1; }
[[ $size =~ ^([0-9]+)x([0-9]+)$ ]] || fail "--size: expected WxH, got '$size'"
width=${BASH_REMATCH[1]} height=${BASH_REMATCH[2]}
steps=$(/usr/bin/python3 -c "import sys; a, d = float(sys.argv[1]), float(sys.argv[2]); \
assert a >= 0 and d > 0; print(round(a / d))" "$at" "$dt") ||
  fail "--at must be a number >= 0 and dt > 0 (got --at '$at', dt '$dt')"

export PATH="/usr/bin:$PATH"
command -v xvfb-run >/dev/null || fail "xvfb-run not found: install xvfb (scripts/install_deps.sh)"
command -v import >/dev/null || fail "import not found: install imagemagick (scripts/install_deps.sh)"
[[ -f $root/build/ws/devel/setup.bash ]] || fail "no workspace: run scripts/build.sh first"
set +u
[[ -f /opt/ros/noetic/setup.bash ]] && source /opt/ros/noetic/setup.bash
source "$root/build/ws/devel/setup.bash"
set -u
export ROS_PACKAGE_PATH="$root/build/ws/src${ROS_PACKAGE_PATH:+:$ROS_PACKAGE_PATH}"
command -v rviz >/dev/null || fail "rviz not found: install rviz (scripts/install_deps.sh)"

launch_file=$root/launch/$scene.launch
[[ -f $launch_file ]] || launch_file=$root/launch/sim.launch
[[ $launch_file == */sim.launch ]] && launch_args=("scene:=$scene" "${launch_args[@]}")
[[ -f $root/urdf/$scene.urdf || $launch_file != */sim.launch ]] ||
  fail "no scene '$scene' (launch/$scene.launch or urdf/$scene.urdf)"

work=$(mktemp -d /tmp/cga_rigid_sim_screenshot.XXXXXX)
cleanup() {
  rm -rf "$work"
}
trap cleanup EXIT

# The view: the shipped configuration with this camera, the side panels hidden, the window the
# size of the screen.
IFS=, read -r fx fy fz <<<"$focus"
/usr/bin/python3 - "$root/rviz/cga_rigid_sim.rviz" "$work/view.rviz" "$fx" "$fy" "$fz" \
  "$distance" "$yaw" "$pitch" "$width" "$height" <<'EOF' || fail "bad view arguments"
import sys, yaml
src, dst = sys.argv[1], sys.argv[2]
fx, fy, fz, distance, yaw, pitch = map(float, sys.argv[3:9])
width, height = int(sys.argv[9]), int(sys.argv[10])
config = yaml.safe_load(open(src))
view = config['Visualization Manager']['Views']['Current']
view['Focal Point'] = {'X': fx, 'Y': fy, 'Z': fz}
view['Distance'], view['Yaw'], view['Pitch'] = distance, yaw, pitch
config['Panels'] = []
config['Window Geometry'] = {'Height': height, 'Width': width, 'X': 0, 'Y': 0,
                             'Hide Left Dock': True, 'Hide Right Dock': True}
yaml.safe_dump(config, open(dst, 'w'))
EOF

# A private master on a free port, a private ROS home.
port=$(/usr/bin/python3 -c "import socket; s = socket.socket(); s.bind(('localhost', 0)); \
print(s.getsockname()[1])")
export ROS_MASTER_URI=http://localhost:$port ROS_HOSTNAME=localhost ROS_HOME=$work/ros
unset ROS_IP ROS_NAMESPACE

# Everything that needs the display runs inside xvfb-run (a free display number, -a).
cat >"$work/inside.sh" <<'EOF'
set -euo pipefail
roslaunch --port "$PORT" "$LAUNCH_FILE" rviz:=true rviz_config:="$WORK/view.rviz" \
  rviz_args:=--fullscreen paused:=true \
  "$@" >"$WORK/launch.log" 2>&1 &
launch_pid=$!
trap 'kill -INT $launch_pid 2>/dev/null; wait $launch_pid 2>/dev/null || true' EXIT
# rviz is up when it subscribes to the markers (at most 180 s: software GL on a busy machine).
for _ in $(seq 1 360); do
  if rostopic info /simulator/markers 2>/dev/null | grep -q '/rviz'; then break; fi
  kill -0 $launch_pid 2>/dev/null || { cat "$WORK/launch.log" >&2; exit 1; }
  sleep 0.5
done
rostopic info /simulator/markers 2>/dev/null | grep -q '/rviz' ||
  { echo "rviz did not subscribe to /simulator/markers within 180 s" >&2; tail -20 "$WORK/launch.log" >&2; exit 1; }
# The node may still be starting (rviz subscribes to a topic before it has a publisher).
timeout 60 rosservice call --wait /simulator/step "$STEPS" >/dev/null ||
  { echo "~step failed" >&2; tail -20 "$WORK/launch.log" >&2; exit 1; }
# rviz draws at 30 Hz in software: give it time to take the last tf and markers.
sleep 4
import -window root "$WORK/screen.png"
EOF
PORT=$port LAUNCH_FILE=$launch_file WORK=$work STEPS=$steps \
  xvfb-run -a -s "-screen 0 ${width}x${height}x24" bash "$work/inside.sh" "${launch_args[@]}" ||
  fail "rendering failed (roslaunch log above)"
[[ -s $work/screen.png ]] || fail "no screenshot taken"
mkdir -p "$(dirname "$out")"
# 8-bit palette PNG: the flat rviz colours compress well (README images stay small).
convert "$work/screen.png" -colors 128 "PNG8:$out" || fail "cannot write $out"
echo "screenshot.sh: wrote $out ($(du -k "$out" | cut -f1) kB; $scene at t = $at s, $steps steps)"
