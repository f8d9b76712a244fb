#!/usr/bin/env bash
# Builds and runs the whole peer-engine sweep.
#
#   bench/peers/run_peers.sh            # build/peers, results in bench/out
#   bench/peers/run_peers.sh --contacts # the contact benchmark instead (peer_contacts_<engine>,
#                                       # bench/out/contacts_<engine>.csv, doc/benchmarks-contacts.md)
#   bench/peers/run_peers.sh --articulated  # the articulated benchmark (peer_articulated_<engine>,
#                                       # bench/out/articulated_<engine>.csv, doc/benchmarks-articulated.md)
#
# Environment: PEER_BUILD_DIR (default <repo>/build/peers), PEER_OUT_DIR
# (default <repo>/bench/out), PEER_JOBS (default 2: two runners at a time,
# one per core; 1 gives cleaner timings but takes about twice as long),
# PEER_ENGINES (default "simbody mujoco bullet dart ode"; only those built
# are run). Extra arguments are passed to every runner (e.g. --cases thin_rod).
#
# Writes <out>/peers_<engine>.csv, <out>/peers_<engine>.log,
# <out>/reference_<case>.csv (cached truth) and <out>/peers_versions.txt
# (package versions, engine-reported versions, machine, load averages).
#
# Budget: ~5 min of CPU time in all (Simbody ~2.7 min, the other four engines
# ~2.5 min together), i.e. ~3 min of wall time on 2 idle cores (Simbody in one
# lane, the other four engines in the other). On a busy machine the wall
# time grows accordingly (12 min at load average 6-18 on 2 cores).
set -euo pipefail

contacts=false
articulated=false
if [[ "${1:-}" == "--contacts" ]]; then
  contacts=true
  shift
elif [[ "${1:-}" == "--articulated" ]]; then
  articulated=true
  shift
fi

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
build="${PEER_BUILD_DIR:-$root/build/peers}"
out="${PEER_OUT_DIR:-$root/bench/out}"
jobs="${PEER_JOBS:-2}"
engines="${PEER_ENGINES:-simbody mujoco bullet dart ode}"

cmake -S "$here" -B "$build" >/dev/null
mkdir -p "$out"

if $contacts; then
  # Contact cases: MuJoCo (the slowest on pile1000) in one lane, the others in
  # the second lane (PEER_JOBS=1: one after another). Extra arguments go to
  # every runner (e.g. --cases bounce --hs 1e-3).
  cmake --build "$build" -j2 --target peer_contact_benchmarks >/dev/null
  engines="${PEER_ENGINES:-mujoco bullet ode}"
  crunners=()
  for e in $engines; do
    if [[ -x "$build/peer_contacts_$e" ]]; then crunners+=("$e"); else echo "peer_contacts_$e not built: skipped"; fi
  done
  if [[ ${#crunners[@]} -eq 0 ]]; then echo "no contact runner built"; exit 1; fi
  t0=$(date +%s)
  load_start="$(cut -d' ' -f1-3 /proc/loadavg)"
  run_contacts() {
    local e="$1"
    shift
    "$build/peer_contacts_$e" --out "$out" "$@" 2>"$out/contacts_$e.log" || echo "peer_contacts_$e failed (see $out/contacts_$e.log)"
  }
  if [[ "$jobs" -ge 2 && ${#crunners[@]} -ge 2 ]]; then
    ( run_contacts "${crunners[0]}" "$@" ) &
    lane1=$!
    for e in "${crunners[@]:1}"; do run_contacts "$e" "$@"; done
    wait "$lane1"
  else
    for e in "${crunners[@]}"; do run_contacts "$e" "$@"; done
  fi
  {
    echo "# contact peer run $(date -u +%Y-%m-%dT%H:%M:%SZ), wall $(( $(date +%s) - t0 )) s, PEER_JOBS=$jobs"
    for e in "${crunners[@]}"; do "$build/peer_contacts_$e" --version; done
    echo "# load average (1/5/15 min) at start: $load_start, at end: $(cut -d' ' -f1-3 /proc/loadavg)"
  } >"$out/contacts_versions.txt"
  cat "$out/contacts_versions.txt"
  exit 0
fi

if $articulated; then
  # Articulated cases: Simbody (the slowest) in one lane, the others in the second lane
  # (PEER_JOBS=1: one after another). The truth is computed once first (--prepare, ~30 s), so
  # that the lanes do not race to fill its cache. Extra arguments go to every runner (e.g.
  # --cases arm7 --hs 1e-3).
  cmake --build "$build" -j2 --target peer_articulated_benchmarks >/dev/null
  engines="${PEER_ENGINES:-simbody mujoco bullet dart ode}"
  arunners=()
  for e in $engines; do
    if [[ -x "$build/peer_articulated_$e" ]]; then arunners+=("$e"); else echo "peer_articulated_$e not built: skipped"; fi
  done
  if [[ ${#arunners[@]} -eq 0 ]]; then echo "no articulated runner built"; exit 1; fi
  t0=$(date +%s)
  load_start="$(cut -d' ' -f1-3 /proc/loadavg)"
  "$build/peer_articulated_${arunners[0]}" --out "$out" --prepare "$@"
  run_articulated() {
    local e="$1"
    shift
    "$build/peer_articulated_$e" --out "$out" "$@" 2>"$out/articulated_$e.log" || echo "peer_articulated_$e failed (see $out/articulated_$e.log)"
  }
  if [[ "$jobs" -ge 2 && ${#arunners[@]} -ge 2 ]]; then
    ( run_articulated "${arunners[0]}" "$@" ) &
    lane1=$!
    for e in "${arunners[@]:1}"; do run_articulated "$e" "$@"; done
    wait "$lane1"
  else
    for e in "${arunners[@]}"; do run_articulated "$e" "$@"; done
  fi
  {
    echo "# articulated peer run $(date -u +%Y-%m-%dT%H:%M:%SZ), wall $(( $(date +%s) - t0 )) s, PEER_JOBS=$jobs"
    dpkg-query -W -f='${Package} ${Version}\n' libmujoco-dev libode-dev libbullet-dev libdart-dev libsimbody-dev 2>/dev/null || true
    for e in "${arunners[@]}"; do "$build/peer_articulated_$e" --version; done
    echo "# compiler: $(${CXX:-c++} --version | head -n1)"
    echo "# cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores"
    echo "# load average (1/5/15 min) at start: $load_start, at end: $(cut -d' ' -f1-3 /proc/loadavg)"
  } >"$out/articulated_versions.txt"
  cat "$out/articulated_versions.txt"
  exit 0
fi

cmake --build "$build" -j2 >/dev/null

runners=()
for e in $engines; do
  if [[ -x "$build/peer_$e" ]]; then runners+=("$e"); else echo "peer_$e not built (engine not found): skipped"; fi
done
if [[ ${#runners[@]} -eq 0 ]]; then echo "no peer runner built"; exit 1; fi

t0=$(date +%s)
load_start="$(cut -d' ' -f1-3 /proc/loadavg)"

# Fill the reference cache once, so parallel runners do not race to compute it.
"$build/peer_${runners[0]}" --out "$out" --prepare "$@"

run_one() {  # engine [runner args...]
  local e="$1"
  shift
  "$build/peer_$e" --out "$out" "$@" 2>"$out/peers_$e.log" || echo "peer_$e failed (see $out/peers_$e.log)"
}

if [[ "$jobs" -ge 2 && ${#runners[@]} -ge 2 ]]; then
  # Lane 1: the first engine (Simbody, the slowest); lane 2: all others.
  ( run_one "${runners[0]}" "${@}" ) &
  lane1=$!
  for e in "${runners[@]:1}"; do run_one "$e" "${@}"; done
  wait "$lane1"
else
  for e in "${runners[@]}"; do run_one "$e" "${@}"; done
fi

t1=$(date +%s)
{
  echo "# peer benchmark run $(date -u +%Y-%m-%dT%H:%M:%SZ), wall ${0##*/}: $((t1 - t0)) s, PEER_JOBS=$jobs"
  echo "# Debian packages (dpkg-query -W):"
  dpkg-query -W -f='${Package} ${Version}\n' libmujoco-dev libode-dev libbullet-dev libdart-dev libsimbody-dev 2>/dev/null || true
  echo "# engine-reported versions:"
  for e in "${runners[@]}"; do "$build/peer_$e" --version; done
  echo "# compiler: $(${CXX:-c++} --version | head -n1)"
  echo "# cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores"
  echo "# load average (1/5/15 min) at start: $load_start, at end: $(cut -d' ' -f1-3 /proc/loadavg)"
} >"$out/peers_versions.txt"
cat "$out/peers_versions.txt"
