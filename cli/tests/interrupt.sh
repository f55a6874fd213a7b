#!/bin/bash
# Test of `steady sweep` stopped by a signal (cli.sweep.interrupted_*): starts a sweep that
# takes several seconds (the bundled bracket along keys.json at tolerance 1e-4: about 7 s on
# two cores), sends the signal after half a second, and expects the exit status, the message on
# standard error and an empty output directory: no envelope, no report, no temporary file.
# usage: interrupt.sh STEADY DATA_DIR SIGNAL STATUS
set -u
steady=$1 data=$2 sig=$3 want=$4
dir=$(mktemp -d)
err=$(mktemp)
trap 'rm -rf "$dir" "$err"' EXIT
cd "$dir" || exit 1
"$steady" sweep "$data/meshes/bracket.off" --motion "$data/motions/keys.json" --tolerance 1e-4 \
  -o out.ply --report report.json 2>"$err" &
pid=$!
sleep 0.5
kill -s "$sig" "$pid"
wait "$pid"
status=$?
fail=0
if [ "$status" -ne "$want" ]; then
  echo "exit status $status, expected $want$([ "$status" -eq 0 ] && echo ': the sweep ended before the signal, pick a longer one')"
  fail=1
fi
if ! grep -q "steady: error \[interrupted\]: the sweep was interrupted by SIG$sig in its .* stage; nothing was written" "$err"; then
  echo "standard error does not say so:"
  cat "$err"
  fail=1
fi
left=$(ls -A "$dir")
if [ -n "$left" ]; then
  echo "files left behind: $left"
  fail=1
fi
[ "$fail" -eq 0 ] && echo "interrupted by SIG$sig: status $status, nothing written"
exit "$fail"
