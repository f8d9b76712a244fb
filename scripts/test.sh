#!/usr/bin/env bash
# Install dependencies, build with tests, run every gtest and rostest, summarize.
#
#   scripts/test.sh [extra cmake args, e.g. -DCGA_RIGID_SIM_ASAN=ON]
#
# Each registered test target (gtest binary test_<layer>, rostest test/ros/<name>.test) runs
# with a time limit (CGA_RIGID_SIM_TEST_TIMEOUT seconds, default 600); then each fuzz target of
# fuzz/ runs for CGA_RIGID_SIM_FUZZ_SECONDS (default 30; scripts/fuzz.sh, doc/fuzzing.md), and
# test_scene_asan (built with them) runs.
# JUnit results go to build/ws/build/test_results/; the last line printed is "N passed,
# N failed" (test cases). Exit status is non-zero if a test failed, crashed, timed out or
# produced no result, or if no test ran at all.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
root=$(pwd)

# One build/test at a time in this checkout.
# shellcheck source=scripts/build_lock.sh
source scripts/build_lock.sh
take_build_lock test.sh

bash scripts/install_deps.sh
# Benchmarks are not tests (scripts/bench.sh builds and runs them; scripts/run.sh's build has
# them): skip them here.
bash scripts/build.sh --tests -DCGA_RIGID_SIM_BUILD_BENCHMARKS=OFF -DCGA_RIGID_SIM_BUILD_PEER_BENCHMARKS=OFF "$@"

# Environment: Debian python first, the workspace's devel space, a private ROS home, and a
# master URI that can only be local (rostest starts its own master on a free port).
export PATH="/usr/bin:$PATH"
set +u
if [[ -f /opt/ros/noetic/setup.bash ]]; then
  # shellcheck disable=SC1091
  source /opt/ros/noetic/setup.bash
fi
# shellcheck disable=SC1091
source "$root/build/ws/devel/setup.bash"
set -u
export ROS_PACKAGE_PATH="$root/build/ws/src${ROS_PACKAGE_PATH:+:$ROS_PACKAGE_PATH}"
export ROS_MASTER_URI=http://localhost:11311
export ROS_HOSTNAME=localhost
unset ROS_IP ROS_NAMESPACE
export ROS_HOME="$root/build/ros_home"
export ROS_LOG_DIR="$ROS_HOME/log"
mkdir -p "$ROS_LOG_DIR"

build_dir="$root/build/ws/build"
results="$build_dir/test_results"
rm -rf "$results"
mkdir -p "$results/cga_rigid_sim"

timeout_s="${CGA_RIGID_SIM_TEST_TIMEOUT:-600}"

# The test targets catkin registered for this package, e.g.
# run_tests_cga_rigid_sim_gtest_test_cga, run_tests_cga_rigid_sim_rostest_test_ros_x.test, and
# run_tests_cga_rigid_sim_pytest_python (test/python/, pytest's JUnit XML)
mapfile -t targets < <(make -C "$build_dir" --no-print-directory help |
  sed -n 's/^\.\.\. \(run_tests_cga_rigid_sim_\(gtest\|rostest\|pytest\)_..*\)$/\1/p' | sort)

write_failure() {  # $1 = target, $2 = reason; a JUnit file the summary counts as one failure
  local file="$results/cga_rigid_sim/FAILED-$1.xml"
  cat >"$file" <<EOF
<?xml version="1.0" encoding="UTF-8"?>
<testsuite name="$1" tests="1" failures="1" errors="0">
  <testcase classname="$1" name="test_ran"><failure message="$2"/></testcase>
</testsuite>
EOF
}

# The fuzz build (clang with the sanitizers, the longest single job of the run) goes beside the
# tests, which mostly wait on their nodes and masters: started now, waited for before the fuzz
# runs below. CGA_RIGID_SIM_FUZZ_SECONDS=0 skips it.
fuzz_seconds="${CGA_RIGID_SIM_FUZZ_SECONDS:-30}"
fuzz_build_pid=""
if [[ $fuzz_seconds != 0 ]]; then
  mkdir -p "$root/build"
  # Short runs: a build quick to make (-O0) that still names file:line in a report; deep runs
  # are scripts/fuzz.sh's own, at -O2 (doc/fuzzing.md#build-time).
  export CGA_RIGID_SIM_FUZZ_OPT="${CGA_RIGID_SIM_FUZZ_OPT:--O0 -gline-tables-only}"
  bash scripts/fuzz.sh --build-only >"$root/build/fuzz_build.log" 2>&1 &
  fuzz_build_pid=$!
  echo "test.sh: fuzz build started beside the tests (log: build/fuzz_build.log)"
fi

start=$(date +%s)
for target in "${targets[@]}"; do
  echo "test.sh: ---- $target"
  rc=0
  timeout --kill-after=30 "$timeout_s" \
    make -C "$build_dir" --no-print-directory "$target" || rc=$?
  if [[ $rc -eq 124 || $rc -eq 137 ]]; then
    echo "test.sh: $target timed out after $timeout_s s"
    write_failure "$target" "timed out after $timeout_s s"
  elif [[ $rc -ne 0 ]]; then
    write_failure "$target" "make $target exited with status $rc"
  fi
done
end=$(date +%s)
echo "test.sh: ${#targets[@]} test targets ran in $((end - start)) s"

# The fuzz targets (doc/fuzzing.md), a short run each: one test case per target, passed when
# the run found no crash, leak or sanitizer report; and test_scene_asan, the scene layer's
# bad-input tests on the core the fuzz build instruments (AddressSanitizer, LeakSanitizer,
# UBSan). CGA_RIGID_SIM_FUZZ_SECONDS=0 skips both.
if [[ $fuzz_seconds != 0 ]]; then
  rc=0
  wait "$fuzz_build_pid" || rc=$?
  echo "test.sh: fuzz build done (status $rc; a failure is reported by the run below)"
  echo "test.sh: ---- fuzz targets, $fuzz_seconds s each, and test_scene_asan"
  rc=0
  bash scripts/fuzz.sh --seconds "$fuzz_seconds" --parallel 2 --junit "$results/cga_rigid_sim" || rc=$?
  if [[ $rc -ne 0 ]] && ! compgen -G "$results/cga_rigid_sim/fuzz-*.xml" >/dev/null; then
    write_failure fuzz "scripts/fuzz.sh exited with status $rc"
  fi
  asan_test="$root/build/fuzz/test_scene_asan"
  if [[ -x $asan_test ]]; then
    rc=0
    (cd "$root" && timeout --kill-after=30 "$timeout_s" "$asan_test" \
      --gtest_output="xml:$results/cga_rigid_sim/gtest-test_scene_asan.xml") || rc=$?
    if [[ $rc -ne 0 ]] && [[ ! -s $results/cga_rigid_sim/gtest-test_scene_asan.xml ]]; then
      write_failure test_scene_asan "test_scene_asan exited with status $rc"
    fi
  else
    write_failure test_scene_asan "build/fuzz/test_scene_asan was not built"
  fi
fi

exec /usr/bin/python3 "$root/scripts/summarize_tests.py" "$results"
