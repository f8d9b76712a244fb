# Sourced by build.sh, run.sh and test.sh: one build/test at a time in this checkout.
# take_build_lock NAME takes build/.lock on file descriptor 9 (waiting, with a message, if another
# script holds it) and marks it held for child scripts, which then do not wait on themselves.
take_build_lock() {
  mkdir -p build
  if [[ -z "${CGA_RIGID_SIM_LOCK_HELD:-}" ]] && command -v flock >/dev/null; then
    exec 9>build/.lock
    flock -n 9 || { echo "$1: waiting for another build/test in this checkout"; flock 9; }
    export CGA_RIGID_SIM_LOCK_HELD=1
  fi
}
