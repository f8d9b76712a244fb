#!/usr/bin/env bash
# Soak test of the simulator node (not part of scripts/test.sh): the many_bodies scene (100
# boxes) at real time for 5 minutes, recorded with rosbag at 100 Hz, under a flood of input
# messages — valid, invalid and over the bounds mixed (scripts/soak_flood.py) — while
# scripts/soak_probe.py samples the node's resident memory every second and calls its
# ~get_body_state every 2 s. Then scripts/soak_check.py checks: every tf, momentum and
# body-state tick is in the bag, ~rejected_inputs equals the refusable messages sent, the memory
# is flat after the first 30 s, the service answered every time. Prints a summary; exits 1 if a
# check failed, 2 if it could not run.
#
#   bash scripts/soak.sh                    # 5 minutes at 10 000 messages/s
#   bash scripts/soak.sh --minutes 1 --rate 2000 --keep
#
# Needs a build (scripts/build.sh). Runs its own ROS master on a free port, so it does not
# disturb another one. --keep keeps the bag and logs (in a /tmp/cga_soak.* folder, printed).
set -u
cd "$(dirname "$0")/.."
minutes=5
rate=10000
keep=0
while [ $# -gt 0 ]; do
  case "$1" in
    --minutes) minutes="$2"; shift 2 ;;
    --rate) rate="$2"; shift 2 ;;
    --keep) keep=1; shift ;;
    -h|--help) sed -n '2,16p' "$0"; exit 0 ;;
    *) echo "soak.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
seconds=$(/usr/bin/python3 -c "print(int(round(float('$minutes') * 60)))") || exit 2
[ "$seconds" -ge 40 ] || { echo "soak.sh: --minutes must give at least 40 s (30 s warm-up)" >&2; exit 2; }

[ -f build/ws/devel/setup.bash ] || { echo "soak.sh: no build; run scripts/build.sh first" >&2; exit 2; }
export PATH=/usr/bin:$PATH
set +u  # ROS's setup scripts read unset variables
# shellcheck disable=SC1091
source build/ws/devel/setup.bash
set -u
export ROS_PACKAGE_PATH="$PWD/build/ws/src:${ROS_PACKAGE_PATH:-}"
out=$(mktemp -d /tmp/cga_soak.XXXXXX)
export ROS_HOME="$out/ros"
port=$(/usr/bin/python3 -c "import socket; s = socket.socket(); s.bind(('', 0)); print(s.getsockname()[1])")
export ROS_MASTER_URI="http://localhost:$port"
py=/usr/bin/python3

pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -INT "$p" 2>/dev/null; done
  sleep 2
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
  [ "$keep" = 1 ] || rm -rf "$out"
}
trap cleanup EXIT
wait_for() {  # wait_for <what> <seconds> <command…>
  local what="$1" limit="$2"; shift 2
  for _ in $(seq 1 $((limit * 10))); do "$@" >/dev/null 2>&1 && return 0; sleep 0.1; done
  echo "soak.sh: timed out waiting for $what (logs in $out)" >&2; keep=1; exit 2
}

echo "soak: $minutes min at $rate messages/s; master $ROS_MASTER_URI; logs in $out"
roscore -p "$port" >"$out/roscore.log" 2>&1 &
pids+=($!)
wait_for "the master" 30 rosparam list
roslaunch cga_rigid_sim many_bodies.launch real_time_factor:=1.0 >"$out/simulator.log" 2>&1 &
sim_launch=$!
pids+=($sim_launch)
wait_for "the simulator" 60 rosservice info /simulator/get_body_state

# The outputs at 100 Hz; not the input topics (record.launch records those too: at 10 000
# messages/s they would make the bag gigabytes without telling anything the counts do not).
record=$(catkin_find --first-only rosbag record 2>/dev/null || echo /usr/lib/rosbag/record)
"$record" -O "$out/soak.bag" __name:=soak_record /tf /simulator/momentum \
  /simulator/body_states /simulator/rejected_inputs >"$out/record.log" 2>&1 &
record_pid=$!
pids+=($record_pid)
wait_for "rosbag record" 30 sh -c "rostopic info /simulator/body_states | grep -q soak_record"
sleep 1

$py scripts/soak_probe.py --out "$out/probe.json" >"$out/probe.log" 2>&1 &
probe_pid=$!
pids+=($probe_pid)
sleep 1
echo "soak: flooding for $seconds s …"
$py scripts/soak_flood.py --rate "$rate" --seconds "$seconds" >"$out/flood.json" 2>"$out/flood.log"
flood_status=$?
sleep 3  # the last wrenches are refused when due; the count is latched
rejected=$(rostopic echo -n 1 /simulator/rejected_inputs/data 2>/dev/null | head -1)

kill -INT "$probe_pid"; wait "$probe_pid"
kill -INT "$record_pid"; wait "$record_pid"
kill -INT "$sim_launch"; wait "$sim_launch"
if [ "$flood_status" != 0 ] || [ -z "$rejected" ] || [ ! -f "$out/soak.bag" ]; then
  echo "soak.sh: the run did not complete (flood status $flood_status, rejected '$rejected'; logs in $out)" >&2
  keep=1
  exit 2
fi
grep -h "cannot keep" "$out/simulator.log" | sed 's/\x1b\[[0-9;]*m//g' | tail -3
$py scripts/soak_check.py --bag "$out/soak.bag" --flood "$out/flood.json" \
  --probe "$out/probe.json" --rejected "$rejected"
status=$?
[ "$status" = 0 ] || keep=1
[ "$keep" = 1 ] && echo "soak: bag and logs kept in $out"
exit $status
