#!/usr/bin/env bash
# Install dependencies, build, and run the main job.
#
#   scripts/run.sh [args...]
#
# When launch/sim.launch exists: roslaunch cga_rigid_sim sim.launch args...
#   (e.g. scripts/run.sh scene:=thin_rod); without args: the default scene (tennis racket,
#   spinning) with gravity:="[0, 0, 0]". Prints where to look (topics, tf, rviz).
# Otherwise: the demo executable tumble_demo args...
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
root=$(pwd)

# One build/test at a time in this checkout.
# shellcheck source=scripts/build_lock.sh
source scripts/build_lock.sh
take_build_lock run.sh

bash scripts/install_deps.sh
bash scripts/build.sh -DCGA_RIGID_SIM_BUILD_PEER_BENCHMARKS=OFF
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
  # Without arguments: the default scene (the tennis racket, spinning about its intermediate
  # axis) in free space, so it flips in place instead of falling out of view.
  if [[ $# -eq 0 ]]; then
    set -- gravity:="[0, 0, 0]"
  fi
  hints() {
    cat <<EOF

run.sh: the simulator runs (roslaunch cga_rigid_sim sim.launch $*). In another terminal:
  source $devel/setup.bash
  rostopic echo /simulator/momentum/bodies[1]             # the scene's total momentum, 100 Hz
  rostopic echo /simulator/body_states                    # poses, twists, motor coefficients
  rosrun tf2_tools view_frames.py                         # the tf tree -> frames.pdf
  rosrun tf2_tools echo.py world racket_head              # a link; Noetic: tf2_ros tf2_echo
  rosrun rviz rviz -d \$(rospack find cga_rigid_sim)/rviz/cga_rigid_sim.rviz  # scene, momentum
  rosservice call /simulator/pause                        # also: unpause, step 100, reset
  roslaunch cga_rigid_sim record.launch bag:=run.bag      # record a bag
  scripts/plot_bag.py run.bag run.png                     # its energy, |L|, |P| and drift
With rviz from the start: bash scripts/run.sh gravity:="[0, 0, 0]" rviz:=true
Other scenes: bash scripts/run.sh scene:=thin_rod (symmetric_top, dumbbell, projectile,
t_handle, many_bodies); every sim.launch argument works. doc/node.md: the node's reference.
Articulated robots: scene:=double_pendulum, scene:=arm7, scene:=satellite gravity:="[0, 0, 0]";
  rostopic echo /joint_states; doc/node.md: "Articulated robots".
EOF
  }
  hints
  # Again once the node's start-up output has scrolled by.
  (sleep 5 && hints) &
  exec roslaunch cga_rigid_sim sim.launch "$@"
fi
exec "$devel/lib/cga_rigid_sim/tumble_demo" "$@"
