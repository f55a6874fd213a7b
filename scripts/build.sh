#!/usr/bin/env bash
# Configures and builds steady in Release (BUILD_DIR, default build/). Extra arguments are
# passed to `cmake --build` (e.g. --target steady).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build}
jobs=${JOBS:-$(nproc)}
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release ${CMAKE_ARGS:-} >/dev/null
cmake --build "$build" -j "$jobs" "$@"
