#!/usr/bin/env bash
# Runs one libFuzzer target of tests/fuzz (ear, motion, mesh or sweep) for SECONDS (default 600), in
# its own build (BUILD_DIR, default build-fuzz/: Clang, AddressSanitizer, UBSan, libFuzzer).
# The working corpus starts from tests/fuzz/corpus/TARGET and grows in
# $BUILD_DIR/corpus/TARGET; inputs that fail are written to $BUILD_DIR/findings/TARGET/.
# To keep a finding as a regression input, copy it into tests/fuzz/corpus/TARGET/ once fixed:
# the test suite replays that folder (ctest -R fuzz_replay).
#
# Usage: scripts/fuzz.sh TARGET [SECONDS] [libFuzzer options, e.g. -jobs=2 -workers=2]
# Needs clang and libclang-rt-14-dev (scripts/install-deps.sh --fuzz installs them).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
target=${1:?usage: scripts/fuzz.sh ear|motion|mesh|sweep [SECONDS] [libFuzzer options]}
shift
seconds=600
if [[ ${1:-} =~ ^[0-9]+$ ]]; then seconds=$1; shift; fi
case $target in ear | motion | mesh | sweep) ;; *) echo "unknown fuzz target '$target' (ear, motion, mesh or sweep)" >&2; exit 2 ;; esac
build=${BUILD_DIR:-$root/build-fuzz}
"$root/scripts/install-deps.sh" --fuzz
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSTEADY_FUZZ=ON \
  -DSTEADY_BUILD_TESTS=OFF -DSTEADY_BUILD_BENCH=OFF -DSTEADY_BUILD_CLI=OFF >/dev/null
cmake --build "$build" -j "${JOBS:-$(nproc)}" --target "steady_fuzz_$target"
mkdir -p "$build/corpus/$target" "$build/findings/$target"
# (-rss_limit_mb: an input that makes the library take more than 2 GB is a finding too;
#  -timeout: so is one that takes more than 60 s (inputs take 10 to 40 times
#  longer here than in Release))
export LSAN_OPTIONS="suppressions=$root/tests/fuzz/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
exec "$build/tests/fuzz/steady_fuzz_$target" "$build/corpus/$target" "$root/tests/fuzz/corpus/$target" \
  -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=60 -max_len=4096 \
  -artifact_prefix="$build/findings/$target/" -print_final_stats=1 "$@"
