#!/usr/bin/env bash
# Install the Debian packages cga_rigid_sim needs to build, run and test.
#
#   scripts/install_deps.sh [--peers]
#
# Debian 12 (and Ubuntu releases with ROS 1 in their archive): ROS 1 from the distribution's
# packages (under /usr). Ubuntu 20.04: ROS Noetic packages (ros-noetic-*, under /opt/ros/noetic;
# the packages.ros.org apt source must already be configured).
# --peers also installs the peer engines and gnuplot used by bench/ (those available only).
# Does nothing (fast) when everything is installed already. Uses sudo when not root.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

peers=false
for arg in "$@"; do
  case "$arg" in
    --peers) peers=true ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    *) echo "install_deps.sh: unknown argument '$arg'" >&2; exit 2 ;;
  esac
done

export PATH="/usr/bin:$PATH"

# Common to both platforms.
packages=(build-essential cmake pkg-config python3 python3-catkin-pkg python3-yaml
          libeigen3-dev libboost-dev liburdfdom-dev libtinyxml2-dev libgtest-dev googletest
          libqhull-dev  # convex hulls of collision meshes (src/scene/convex_hull.cc)
          libassimp-dev  # collision meshes in Collada and the other formats robot packages ship
          libccd-dev  # MPR for two collision hulls (src/contact/contact_convex_pairs.cc; FCL's too)
          # seeing a run (doc/node.md "Seeing the simulation"): plots from a bag, rviz under a virtual
          # X server with mesa's software GL, and a screenshot of it
          python3-matplotlib python3-pil xvfb xauth libgl1-mesa-dri imagemagick
          # the Python module (pybind11) and the fit on Dask (doc/python.md, doc/fitting.md)
          pybind11-dev python3-pybind11 python3-setuptools python3-numpy python3-scipy python3-pytest
          python3-distributed python3-dask)

candidate_of() {  # prints the apt candidate version of $1, or nothing
  apt-cache policy "$1" 2>/dev/null | awk '/Candidate:/ {print $2}' | grep -v '^(none)$' || true
}

os_id=$(. /etc/os-release 2>/dev/null && echo "${ID:-}:${VERSION_ID:-}" || true)
if [[ -d /opt/ros/noetic || $os_id == ubuntu:20.04 ]] ||
   [[ $os_id == ubuntu:* && -n "$(candidate_of ros-noetic-roscpp)" ]]; then
  platform=noetic
  packages+=(
    ros-noetic-catkin ros-noetic-roscpp ros-noetic-rospy ros-noetic-tf2 ros-noetic-tf2-ros
    ros-noetic-tf2-msgs ros-noetic-tf2-geometry-msgs ros-noetic-geometry-msgs
    ros-noetic-std-msgs ros-noetic-std-srvs ros-noetic-rosgraph-msgs
    ros-noetic-message-generation ros-noetic-message-runtime ros-noetic-rosbag
    ros-noetic-rostopic ros-noetic-rosservice ros-noetic-roslaunch ros-noetic-rostest
    ros-noetic-rosunit ros-noetic-rosbash
    ros-noetic-sensor-msgs ros-noetic-trajectory-msgs ros-noetic-robot-state-publisher
    ros-noetic-nav-msgs
    ros-noetic-visualization-msgs ros-noetic-rviz
    ros-noetic-fcl)  # FCL ≥ 0.6 (Ubuntu 20.04's libfcl-dev is 0.5, another API)
else
  platform=debian
  packages+=(
    catkin ros-base-dev libroscpp-dev libtf2-dev libtf2-ros-dev libtf2-msgs-dev
    libtf2-geometry-msgs-dev libgeometry-msgs-dev libstd-msgs-dev libstd-srvs-dev
    libros-rosgraph-msgs-dev ros-message-generation ros-message-runtime ros-std-msgs
    ros-geometry-msgs librosbag-dev rosbash
    python3-rospy python3-roslaunch python3-rostest python3-rosunit python3-rosbag
    python3-rostopic python3-rosservice python3-std-msgs python3-geometry-msgs python3-std-srvs
    python3-rosgraph-msgs python3-tf2-msgs python3-tf2-ros
    libsensor-msgs-dev python3-sensor-msgs ros-sensor-msgs
    libnav-msgs-dev python3-nav-msgs ros-nav-msgs  # ground-truth odometry (doc/sensors.md)
    # controllers' commands and states (doc/node.md#controllers); Python for the rostests
    libtrajectory-msgs-dev python3-trajectory-msgs ros-trajectory-msgs
    ros-robot-state-publisher  # test/ros/robot_state_publisher.test
    libvisualization-msgs-dev python3-visualization-msgs rviz  # rviz.test reads ~markers in Python
    libfcl-dev  # FCL 0.7: collision detection for contacts
    dart-doc)  # published robot descriptions the loader's tests read (test/scene/urdf/published_robots_test.cc)
fi

# The fuzz targets (scripts/fuzz.sh): clang with libFuzzer and the ASan/UBSan/LSan runtimes. The
# runtimes are a package of their own since LLVM 14 (libclang-rt-<N>-dev); Ubuntu 20.04's clang-10
# has them in libclang-common-10-dev.
codename=$(. /etc/os-release 2>/dev/null && echo "${VERSION_CODENAME:-}" || true)
case "$codename" in
  focal) packages+=(clang-10 libclang-common-10-dev) ;;
  bookworm) packages+=(clang libclang-rt-14-dev) ;;
  *) packages+=(clang libclang-rt-dev) ;;
esac

peer_packages=(libmujoco-dev libode-dev libbullet-dev libdart-dev libsimbody-dev gnuplot-nox)

# One `dpkg -s` for all packages; a package counts as present when its status is installed.
installed=" $(dpkg -s "${packages[@]}" "${peer_packages[@]}" 2>/dev/null |
  awk '/^Package:/ {p = $2} /^Status: install ok installed/ {printf "%s ", p}' || true) "
is_installed() {
  [[ "$installed" == *" $1 "* ]]
}

missing=()
for p in "${packages[@]}"; do
  is_installed "$p" || missing+=("$p")
done
missing_peers=()
if $peers; then
  for p in "${peer_packages[@]}"; do
    if [[ $p == gnuplot-nox ]] && command -v gnuplot >/dev/null; then continue; fi
    is_installed "$p" || missing_peers+=("$p")
  done
fi

if [[ ${#missing[@]} -eq 0 && ${#missing_peers[@]} -eq 0 ]]; then
  echo "install_deps.sh: all dependencies present ($platform)"
  exit 0
fi

if [[ $(id -u) -eq 0 ]]; then
  as_root=()
elif command -v sudo >/dev/null; then
  as_root=(sudo)
else
  echo "install_deps.sh: need root or sudo to install: ${missing[*]} ${missing_peers[*]}" >&2
  exit 1
fi
apt_get() {
  "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get "$@"
}

echo "install_deps.sh: installing for $platform: ${missing[*]} ${missing_peers[*]}"
apt_get update -q

if [[ $platform == noetic && ! -d /opt/ros/noetic && -z "$(candidate_of ros-noetic-roscpp)" ]]; then
  echo "install_deps.sh: ros-noetic-* packages are not available: add the packages.ros.org apt source" >&2
  exit 1
fi

# Peers: install only what the archive has, say what is skipped.
for p in "${missing_peers[@]}"; do
  if [[ -n "$(candidate_of "$p")" ]]; then
    missing+=("$p")
  else
    echo "install_deps.sh: note: peer package $p is not available here, skipped"
  fi
done

if [[ ${#missing[@]} -gt 0 ]]; then
  apt_get install -y -q --no-install-recommends "${missing[@]}"
fi
echo "install_deps.sh: done"
