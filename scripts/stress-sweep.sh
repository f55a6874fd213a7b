#!/usr/bin/env bash
# The seeded stress campaign of the sweep (tests/sweep/stress_sweep.cpp): cases FIRST .. END-1 of
# its table (default 0 .. 1799; the seeded table goes on beyond), each in its own process with a
# time limit, so that a crash or a hang loses that case only, JOBS at a time. Appends every
# case's lines to LOG, then prints the counts of this run and the cases that did not pass.
#
# Usage: scripts/stress-sweep.sh [FIRST [END]] [steady_sweep_stress options: --dense,
#        --all-vertices, --repro-dir DIR, --smooth (the second table: smooth keyframe motions),
#        --shears (the third table: polySAMs of straight shears)]
# Environment: BUILD_DIR (default build/), JOBS (cases at a time, default nproc), LIMIT (seconds
# per case, default 300), LOG (default $BUILD_DIR/stress-sweep.log).
# A CRASH is a case whose process ended otherwise than by PASS, VOID, SKIP (exit 0) or FAIL,
# THROW (exit 1): a signal, the time limit (rc 124) or an unreadable input (rc 2).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build}
first=0 end=1800
if [[ ${1:-} =~ ^[0-9]+$ ]]; then first=$1; shift; fi
if [[ ${1:-} =~ ^[0-9]+$ ]]; then end=$1; shift; fi
export bin=$build/tests/sweep/steady_sweep_stress log=${LOG:-$build/stress-sweep.log} limit=${LIMIT:-300}

if ! out=$(BUILD_DIR=$build "$root/scripts/build.sh" --target steady_sweep_stress 2>&1); then
  echo "$out" >&2
  exit 1
fi
"$bin" --first "$first" --list "$@" >/dev/null  # (a bad option: its usage message, once)
touch "$log"
before=$(wc -l <"$log")

run_case() {
  local i=$1 rc=0
  shift
  timeout "$limit" "$bin" --first "$i" --log "$log" "$@" >/dev/null 2>&1 || rc=$?
  if ((rc > 1)); then
    echo "CRASH $("$bin" --first "$i" --list "$@" | cut -d' ' -f2) case=$i rc=$rc" >>"$log"
  fi
}
export -f run_case
SECONDS=0
seq "$first" $((end - 1)) | xargs -P "${JOBS:-$(nproc)}" -I{} bash -c 'run_case "$@"' _ {} "$@"

tail -n +$((before + 1)) "$log" | awk -v wall=$SECONDS -v logfile="$log" '
  /^(PASS|VOID|FAIL|THROW|SKIP|CRASH) / { n[$1]++ }
  /^(FAIL|THROW|CRASH) / {
    match($0, /case=[0-9]+/); i = substr($0, RSTART + 5, RLENGTH - 5)
    bnd = match($0, /bnd<=[0-9.]+eps \([0-9]+\/[0-9]+/) ? substr($0, RSTART, RLENGTH) ")" : ""
    more = match($0, /selfint [1-9][0-9]*|rc=[0-9]+/) ? substr($0, RSTART, RLENGTH) : ""
    bad[i] = sprintf("  %5d %-5s %-38s %s %s", i, $1, $2, bnd, more)
  }
  END {
    printf "%d cases in %d s (%s): PASS %d, VOID %d, FAIL %d, THROW %d, CRASH %d, SKIP %d\n", \
      n["PASS"] + n["VOID"] + n["FAIL"] + n["THROW"] + n["CRASH"] + n["SKIP"], wall, logfile, \
      n["PASS"], n["VOID"], n["FAIL"], n["THROW"], n["CRASH"], n["SKIP"]
    for (i in bad) print bad[i] | "sort -n"
  }'
