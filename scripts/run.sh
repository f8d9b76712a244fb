#!/usr/bin/env bash
# Install dependencies, build, and run the main job.
#
#   scripts/run.sh [args...]
#
# When launch/sim.launch exists: roslaunch cga_rigid_sim sim.launch args...
#   (e.g. scripts/run.sh scene:=thin_rod)
# Otherwise: the demo executable tumble_demo args...
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
root=$(pwd)

# One build/test at a time in this checkout.
mkdir -p build
if [[ -z "${CGA_RIGID_SIM_LOCK_HELD:-}" ]] && command -v flock >/dev/null; then
  exec 9>build/.lock
  flock -n 9 || { echo "run.sh: waiting for another build/test in this checkout"; flock 9; }
  export CGA_RIGID_SIM_LOCK_HELD=1
fi

bash scripts/install_deps.sh
bash scripts/build.sh
exec 9>&-  # release the lock: the job may run for a long time

export PATH="/usr/bin:$PATH"
devel="$root/build/ws/devel"
set +u
if [[ -f /opt/ros/noetic/setup.bash ]]; then
  # shellcheck disable=SC1091
  source /opt/ros/noetic/setup.bash
fi
# shellcheck disable=SC1091
source "$devel/setup.bash"
set -u
export ROS_PACKAGE_PATH="$root/build/ws/src${ROS_PACKAGE_PATH:+:$ROS_PACKAGE_PATH}"

if [[ -f launch/sim.launch ]]; then
  exec roslaunch cga_rigid_sim sim.launch "$@"
fi
exec "$devel/lib/cga_rigid_sim/tumble_demo" "$@"
