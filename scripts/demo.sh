#!/usr/bin/env bash
# The main job on the bundled default scene: installs what is missing, builds, and computes the
# swept volume of the bundled bracket (data/meshes/bracket.off) along the bundled growing screw
# (data/motions/screw_scale.json, a polySAM of two spans). Writes out/envelope.ply and
# out/report.json (JSON: volume, counts, check, timings) and prints a summary line. Extra
# arguments go to `steady sweep` (e.g. --tolerance 2e-3).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh" --target steady >/dev/null
cd "$root"
mkdir -p out
exec "${BUILD_DIR:-$root/build}/cli/steady" sweep data/meshes/bracket.off --motion data/motions/screw_scale.json \
  -o out/envelope.ply --report out/report.json "$@"
