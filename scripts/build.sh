#!/usr/bin/env bash
# Build cga_rigid_sim with catkin_make in the workspace build/ws (git-ignored).
#
#   scripts/build.sh [--tests] [extra cmake args, e.g. -DCGA_RIGID_SIM_ASAN=ON]
#
# build/ws/src/cga_rigid_sim mirrors the repository root (one symlink per top-level entry,
# without build/ and .git). Results:
#   build/ws/devel/lib/cga_rigid_sim/<executable>   node, apps, gtest binaries (test_<layer>)
#   build/ws/devel/setup.bash                       source it to use rosrun/roslaunch
# --tests also builds the test targets (gtest binaries). Options are reset to their defaults
# unless given again: the build always matches the arguments of this call.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
root=$(pwd)

tests=false
cmake_args=()
for arg in "$@"; do
  case "$arg" in
    --tests) tests=true ;;
    -h|--help) sed -n '2,11p' "$0"; exit 0 ;;
    -D*|-G*) cmake_args+=("$arg") ;;
    *) echo "build.sh: unknown argument '$arg' (cmake args start with -D)" >&2; exit 2 ;;
  esac
done

# One build/test at a time in this checkout.
# shellcheck source=scripts/build_lock.sh
source scripts/build_lock.sh
take_build_lock build.sh

# Debian's python (with catkin_pkg) first; ROS Noetic environment when present.
export PATH="/usr/bin:$PATH"
if [[ -f /opt/ros/noetic/setup.bash ]]; then
  set +u
  # shellcheck disable=SC1091
  source /opt/ros/noetic/setup.bash
  set -u
fi

# The package directory of the workspace mirrors the repository root with one symlink per
# top-level entry, leaving out build/ and .git: a symlink to the root itself would put the
# workspace inside the package, and ROS tools that walk a package following symlinks (roslaunch
# and rostest looking up a launch file or a node) would loop through it.
ws="$root/build/ws"
pkg="$ws/src/cga_rigid_sim"
if [[ -L "$pkg" ]]; then
  rm -f "$pkg"
fi
mkdir -p "$pkg"
shopt -s nullglob dotglob
for entry in "$pkg"/*; do  # drop links to entries that are gone
  if [[ -L "$entry" && ! -e "$entry" ]]; then
    rm -f "$entry"
  fi
done
for entry in "$root"/*; do
  name=$(basename "$entry")
  case "$name" in
    build|.git) continue ;;
  esac
  if [[ "$(readlink "$pkg/$name" 2>/dev/null || true)" != "../../../../$name" ]]; then
    rm -rf "${pkg:?}/$name"
    ln -s "../../../../$name" "$pkg/$name"
  fi
done
shopt -u nullglob dotglob

jobs="${CGA_RIGID_SIM_JOBS:-2}"
targets=(all)
if $tests; then
  targets+=(tests)
fi

start=$(date +%s)
# Every option of the project (and the extra compiler flags) at its default, then this call's
# arguments over them (the compiler flags: $CXXFLAGS, as CMake takes it on a first configure):
# CMake keeps an option in its cache from one configure to the next, so a
# -DCGA_RIGID_SIM_NATIVE=ON or -DCMAKE_CXX_FLAGS=... given once would otherwise stay in every
# later build, test.sh's and run.sh's included.
catkin_make -C "$ws" \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 \
  -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_FLAGS="${CXXFLAGS:-}" \
  -DCGA_RIGID_SIM_ASAN=OFF \
  -DCGA_RIGID_SIM_NATIVE=OFF \
  -DCGA_RIGID_SIM_BUILD_BENCHMARKS=ON \
  -DCGA_RIGID_SIM_BUILD_PEER_BENCHMARKS=ON \
  "${cmake_args[@]}" \
  -j"$jobs" "${targets[@]}"
end=$(date +%s)
echo "build.sh: build took $((end - start)) s"
