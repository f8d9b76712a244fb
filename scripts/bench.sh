#!/usr/bin/env bash
# Regenerate every benchmark result, doc/benchmarks.md and its diagrams (doc/img/).
#
#   scripts/bench.sh [--no-install] [--no-build] [--no-peers] [--no-node] [--quick] [--cpu-time]
#
# Steps: install the peer engines and gnuplot (scripts/install_deps.sh --peers), build with the
# benchmarks (scripts/build.sh -DCGA_RIGID_SIM_BUILD_BENCHMARKS=ON), run the peers
# (bench/peers/run_peers.sh), our work-precision sweep, the scaling sweep and the node
# throughput, then bench/report.py.
# The parts run one after another (the peers' driver itself runs two runners at a time, one
# per core). Raw results go to bench/out/ (git-ignored). Budget: 15 minutes on 2 cores (the
# measured time is printed at the end and recorded in doc/benchmarks.md). The ns figures are
# only meaningful on an otherwise idle machine; on a busy one, --cpu-time makes the report use
# the thread-CPU times every runner also records. --quick runs a reduced sweep (three steps, one
# repetition) to check the pipeline.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
root=$(pwd)

install=true build=true peers=true node=true quick=false clock=wall
for arg in "$@"; do
  case "$arg" in
    --no-install) install=false ;;
    --no-build) build=false ;;
    --no-peers) peers=false ;;
    --no-node) node=false ;;
    --quick) quick=true ;;
    --cpu-time) clock=cpu ;;
    -h|--help) sed -n '2,14p' "$0"; exit 0 ;;
    *) echo "bench.sh: unknown argument '$arg'" >&2; exit 2 ;;
  esac
done

export PATH="/usr/bin:$PATH"
out="${BENCH_OUT:-$root/bench/out}"  # BENCH_OUT: another results directory
bin="$root/build/ws/devel/lib/cga_rigid_sim"
start=$(date +%s)
stamp() { echo "bench.sh: [$(( $(date +%s) - start )) s] $*"; }

# Our step grid is the peers' default (bench/peers/peer_common.cc: 10 steps, 0.1 ms ... 0.1 s;
# the Simbody runner skips h < 1 ms for time). --quick uses three steps for both.
ours_args=() peer_args=() node_args=()
# Scaling on one and two threads, every state read every step and every 10 steps (the node at
# 100 Hz): coasting bodies cost nothing between reads.
scaling_args=(--threads 1,2 --read-every 1,10)
if $quick; then
  ours_args=(--hs 1e-3,1e-2,1e-1 --reps 1 --min-timed-steps 20000)
  peer_args=(--hs 1e-3,1e-2,1e-1 --reps 1 --timing-steps 2000)
  scaling_args=(--ns 1,100,10000 --reps 1 --body-steps 200000 --threads 1,2 --read-every 1,10)
  node_args=(--ns 1,1000 --window 3 --warmup 1)
fi

if $install; then
  stamp "installing dependencies (peers, gnuplot)"
  bash scripts/install_deps.sh --peers || echo "bench.sh: install_deps.sh failed; using what is installed" >&2
fi
if $build; then
  stamp "building (Release, benchmarks on)"
  bash scripts/build.sh -DCGA_RIGID_SIM_BUILD_BENCHMARKS=ON -DCGA_RIGID_SIM_BUILD_PEER_BENCHMARKS=ON
fi
for exe in bench_work_precision bench_scaling; do
  [[ -x "$bin/$exe" ]] || { echo "bench.sh: $bin/$exe missing: build first" >&2; exit 1; }
done

mkdir -p "$out"
# Results of the parts that run now are removed first (a failed part leaves no stale data).
rm -f "$out"/ours.csv "$out"/scaling.csv "$out"/environment.txt
if $peers; then rm -f "$out"/peers_*.csv "$out"/peers_versions.txt; fi
if $node; then rm -f "$out"/node_throughput.csv; fi

# The machine, recorded before the runs (report.py prints it).
{
  echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "git_describe: $(git describe --always --dirty --tags 2>/dev/null || echo unknown)"
  echo "cpu: $(lscpu | sed -n 's/^Model name:[[:space:]]*//p' | head -1)"
  echo "cores: $(nproc) (lscpu: $(lscpu | sed -n 's/^CPU(s):[[:space:]]*//p' | head -1) CPUs)"
  echo "compiler: $(c++ --version | head -1)"
  echo "os: $(. /etc/os-release 2>/dev/null && echo "${PRETTY_NAME:-?}"), kernel $(uname -r)"
  echo "loadavg: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "clock_ghz: $("$bin/bench_work_precision" --fma-clock 2>/dev/null || echo 0)"
} > "$out/environment.txt"

# Peers: the peer engineer's driver (builds the runners in build/peers, fills the reference
# cache, runs two runners at a time, writes peers_<engine>.csv and peers_versions.txt).
if $peers; then
  stamp "peers (bench/peers/run_peers.sh)"
  if [[ -f bench/peers/run_peers.sh ]]; then
    PEER_OUT_DIR="$out" bash bench/peers/run_peers.sh "${peer_args[@]}" > "$out/run_peers.log" 2>&1 ||
      echo "bench.sh: run_peers.sh failed (see bench/out/run_peers.log)" >&2
    tail -3 "$out/run_peers.log"
  else  # no driver: the runners of this build, one after another
    shopt -s nullglob
    for runner in "$bin"/peer_*; do
      engine=${runner##*/peer_}
      "$runner" --version >> "$out/peers_versions.txt" 2>/dev/null || true
      "$runner" --out "$out" "${peer_args[@]}" 2> "$out/peers_$engine.log" ||
        echo "bench.sh: peer_$engine failed (see bench/out/peers_$engine.log)" >&2
    done
    shopt -u nullglob
  fi
fi

stamp "ours: work-precision"
"$bin/bench_work_precision" --out "$out" "${ours_args[@]}" 2> "$out/ours.log"
tail -1 "$out/ours.log"

stamp "scaling"
"$bin/bench_scaling" --out "$out" "${scaling_args[@]}" 2> "$out/scaling.log"
tail -1 "$out/scaling.log"

if $node; then
  stamp "node throughput"
  /usr/bin/python3 bench/node_throughput.py --out "$out" --node "$bin/simulator" "${node_args[@]}" ||
    echo "bench.sh: node_throughput.py failed" >&2
fi

elapsed=$(( $(date +%s) - start ))
load_end=$(cut -d' ' -f1-3 /proc/loadavg)
echo "bench_duration: $((elapsed / 60)) min $((elapsed % 60)) s (scripts/bench.sh $*; load average" \
  "at the end $load_end)" >> "$out/environment.txt"
stamp "report"
/usr/bin/python3 bench/report.py --out "$out" --clock "$clock"
stamp "done: doc/benchmarks.md, doc/img/*.png (raw results in bench/out/)"
