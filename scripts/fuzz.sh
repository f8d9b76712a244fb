#!/usr/bin/env bash
# Build the libFuzzer targets (fuzz/, doc/fuzzing.md) with clang and run each one.
#
#   scripts/fuzz.sh [--seconds N | --runs N] [--target NAME]... [--junit DIR] [--build-only]
#
# --seconds N   run each target for N seconds (default 60; libFuzzer -max_total_time)
# --runs N      run each target for N executions instead (-runs; the long run is --runs 1000000)
# --target NAME only this target (urdf, mesh, initial_state, world_inputs; repeatable)
# --junit DIR   also write one JUnit file per target into DIR (fuzz-<target>.xml, one test case:
#               it passes when the run ended without a crash, leak, timeout or sanitizer report)
# --build-only  build, do not run
# --parallel N  run N targets at a time (default 1; scripts/test.sh uses 2, one per core)
# Builds into build/fuzz (no ROS needed: the core and the targets, instrumented with
# -fsanitize=fuzzer-no-link,address,undefined). Seeds come from the test data (URDFs of urdf/,
# test/ros/, test/scene/bad_urdf/; meshes; config/*.yaml as flow text) and fuzz/corpus/<target>/;
# the inputs libFuzzer finds stay in build/fuzz/corpus/<target>/ for the next run. A finding is
# written to build/fuzz/artifacts/<target>/ (crash-…, leak-…, timeout-…); the run's log is
# build/fuzz/logs/<target>-<N>s.log or -<N>runs.log, and one summary line per target is printed
# at the end.
# Exit status non-zero if a target failed or could not be built.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
root=$(pwd)
export PATH="/usr/bin:$PATH"

seconds=60
runs=""
targets=()
junit=""
build_only=false
parallel=1
while [[ $# -gt 0 ]]; do
  case "$1" in
    --seconds) seconds="$2"; runs=""; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --target) targets+=("$2"); shift 2 ;;
    --junit) junit="$2"; shift 2 ;;
    --build-only) build_only=true; shift ;;
    --parallel) parallel="$2"; shift 2 ;;
    -h|--help) sed -n '2,21p' "$0"; exit 0 ;;
    *) echo "fuzz.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
all_targets=(urdf mesh initial_state world_inputs)
[[ ${#targets[@]} -gt 0 ]] || targets=("${all_targets[@]}")
for t in "${targets[@]}"; do
  [[ " ${all_targets[*]} " == *" $t "* ]] || { echo "fuzz.sh: unknown target '$t' (${all_targets[*]})" >&2; exit 2; }
done

# clang++ with libFuzzer: Debian 12's clang (14) or Ubuntu 20.04's clang-10 (scripts/install_deps.sh).
cxx=""
for c in clang++ clang++-14 clang++-10; do
  if command -v "$c" >/dev/null; then cxx=$(command -v "$c"); break; fi
done
[[ -n $cxx ]] || { echo "fuzz.sh: clang++ not found: run scripts/install_deps.sh" >&2; exit 1; }

out="$root/build/fuzz"
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
jobs=$(nproc 2>/dev/null || echo 2)
mkdir -p "$out"
# CGA_RIGID_SIM_FUZZ_OPT: the build's optimisation and debug flags (default "-O2 -g"; the test
# command's short runs use "-O0 -gline-tables-only", quicker to build).
cmake -S "$root/fuzz" -B "$out" -DCMAKE_CXX_COMPILER="$cxx" "${launcher[@]}" \
  -DFUZZ_OPT="${CGA_RIGID_SIM_FUZZ_OPT:--O2 -g}" >"$out/cmake.log" 2>&1 ||
  { cat "$out/cmake.log" >&2; echo "fuzz.sh: cmake failed" >&2; exit 1; }
build_failed=false
cmake --build "$out" -- -j"$jobs" || build_failed=true

write_junit() {  # $1 target, $2 "" (pass) or failure message, $3 details, $4 seconds
  [[ -n $junit ]] || return 0
  mkdir -p "$junit"
  local failure=""
  if [[ -n $2 ]]; then
    failure="<failure message=\"$(xml_escape "$2")\">$(xml_escape "$3")</failure>"
  fi
  cat >"$junit/fuzz-$1.xml" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<testsuite name="fuzz_$1" tests="1" failures="$([[ -n $2 ]] && echo 1 || echo 0)" errors="0" time="$4">
  <testcase classname="fuzz" name="fuzz_$1" time="$4">$failure</testcase>
</testsuite>
XML
}
xml_escape() {
  sed -e 's/&/\&amp;/g' -e 's/</\&lt;/g' -e 's/>/\&gt;/g' -e 's/"/\&quot;/g' <<<"$1" |
    tr -cd '\11\12\15\40-\176'
}

if $build_failed; then
  for t in "${targets[@]}"; do write_junit "$t" "fuzz targets did not build" "" 0; done
  echo "fuzz.sh: build failed" >&2
  exit 1
fi
$build_only && exit 0

# Seeds: the test data, assembled afresh on every run.
seed_urdf() {
  cp "$root"/urdf/*.urdf "$root"/test/ros/*.urdf "$root"/test/scene/bad_urdf/*.urdf "$1"/
}
seed_mesh() {  # first byte: 0 = STL, 1 = OBJ (fuzz/fuzz_mesh.cc)
  local m
  for m in "$root"/fuzz/meshes/*.* "$root"/test/scene/bad_urdf/meshes/*.*; do
    case "$m" in
      *.stl) { printf '\0'; cat "$m"; } >"$1/$(basename "$m")" ;;
      *.obj) { printf '\1'; cat "$m"; } >"$1/$(basename "$m")" ;;
    esac
  done
}
seed_initial_state() {  # config/<scene>.yaml → "<scene>\n" + the dictionary as JSON (flow text)
  local y
  for y in "$root"/config/*.yaml; do
    /usr/bin/python3 -c 'import json, sys, yaml
d = yaml.safe_load(open(sys.argv[1]))
sys.stdout.write(sys.argv[2] + "\n" + json.dumps(d.get("initial_state", {})) + "\n")' \
      "$y" "$(basename "$y" .yaml)" >"$1/$(basename "$y" .yaml)"
  done
}
seed_world_inputs() { :; }

# One target's run: its log, its JUnit file, its summary line (in logs/<target>.summary).
# Exit status 1 when the run failed.
run_target() {
  local t=$1 bin seeds corpus artifacts log args limit start end elapsed execs cov line rc report artifact
  bin="$out/fuzz_$t"
  seeds="$out/seeds/$t"
  corpus="$out/corpus/$t"
  artifacts="$out/artifacts/$t"
  if [[ -n $runs ]]; then log="$out/logs/$t-${runs}runs.log"; else log="$out/logs/$t-${seconds}s.log"; fi
  rm -rf "$seeds"
  mkdir -p "$seeds" "$corpus" "$artifacts" "$out/logs"
  "seed_$t" "$seeds"
  args=(-artifact_prefix="$artifacts/" -print_final_stats=1 -timeout=20 -rss_limit_mb=2560)
  if [[ -f $root/fuzz/$t.dict ]]; then args+=(-dict="$root/fuzz/$t.dict"); fi
  if [[ -n $runs ]]; then limit=-runs="$runs"; else limit=-max_total_time="$seconds"; fi
  args+=("$limit")
  echo "fuzz.sh: ---- fuzz_$t $limit"
  start=$(date +%s.%N)
  rc=0
  # Our reproducers and seeds are read from fuzz/corpus/<target> (not written to).
  "$bin" "${args[@]}" "$corpus" "$seeds" "$root/fuzz/corpus/$t" >"$log" 2>&1 || rc=$?
  end=$(date +%s.%N)
  elapsed=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.0f", b - a }')
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  cov=$(grep -oE 'cov: [0-9]+ ft: [0-9]+ corp: [0-9]+' "$log" | tail -1)
  line="fuzz_$t: ${execs:-?} executions in ${elapsed} s, ${cov:-no coverage line}, exit $rc"
  if [[ $rc -eq 0 ]]; then
    write_junit "$t" "" "" "$elapsed"
  else
    report=$(grep -m1 -E 'ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error|fuzz check failed|SUMMARY' "$log" || true)
    artifact=$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$log" | tail -1)
    line+=" — ${report:-failed} ${artifact:+(reproducer: $artifact)}"
    write_junit "$t" "fuzz_$t: ${report:-exit status $rc}" "$(tail -n 60 "$log")" "$elapsed"
  fi
  echo "fuzz.sh: $line"
  echo "$line" >"$out/logs/$t.summary"
  [[ $rc -eq 0 ]]
}

# The targets, `parallel` at a time (each libFuzzer run is one process on one core).
status=0
pids=()
for t in "${targets[@]}"; do
  run_target "$t" &
  pids+=($!)
  if [[ ${#pids[@]} -ge $parallel ]]; then
    wait "${pids[0]}" || status=1
    pids=("${pids[@]:1}")
  fi
done
for pid in "${pids[@]}"; do wait "$pid" || status=1; done
summary=()
for t in "${targets[@]}"; do summary+=("$(cat "$out/logs/$t.summary" 2>/dev/null || echo "fuzz_$t: no result")"); done
echo "fuzz.sh: summary"
printf '  %s\n' "${summary[@]}"
exit $status
