#!/usr/bin/env bash
# Sweeps small bodies along motions that keep a plane or a line fixed (README, Swept volumes,
# "Planar motions"), through the CLI of an existing build, and prints one line per sweep:
# mesh, motion, relative tolerance, exit status, time and the envelope's check. Exit status 0
# when every envelope passed its check (the CLI's status 0), 1 otherwise.
#   - the bundled box and bracket turning 10 to 270 degrees about z while moving (2, 0.5), at
#     1e-2, 3e-3 and 1e-3 (48 sweeps);
#   - the box, the L prism (tests/sweep/fixtures) and the tetrahedron turning 30 and 100 degrees
#     about x or y while moving, at 1e-2 and 3e-3 (24);
#   - the box, L prism, bracket and tetrahedron along a general affine span keeping z (8);
#   - the tetrahedron along tests/sweep/fixtures/tetra_shear_keeps_z.json at 2e-2 to 1e-3 (4).
# Usage: scripts/planar-scan.sh [BUILD_DIR (default build)]; motions go to a temporary folder.
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
steady=${1:-$root/build}/cli/steady
[ -x "$steady" ] || { echo "planar-scan: no $steady; build first (scripts/build.sh)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failed=0
run() {  # mesh motion tolerance
  local out rc
  out=$(timeout 600 "$steady" sweep "$1" --motion "$2" -o "$work/envelope.off" --tolerance "$3" --threads 1 2>&1)
  rc=$?
  [ $rc -eq 0 ] || failed=1
  echo "$(basename "$1") $(basename "$2") $3 status $rc: $(echo "$out" | grep -o 'in [0-9.]* s[^;]*; check: [^;]*' | head -1)"
}
pose() {  # translation axis degrees -> a motion file from the identity
  echo "{\"keyframes\": [{\"t\": 0, \"pose\": [[1,0,0,0],[0,1,0,0],[0,0,1,0]]}, {\"t\": 1, \"pose\": {\"translation\": [$1], \"axis\": [$2], \"angle_deg\": $3}}]}"
}
box=$root/data/meshes/box.off bracket=$root/data/meshes/bracket.off tetra=$root/data/meshes/tetrahedron.off
prism=$root/tests/sweep/fixtures/l_prism.off
for deg in 10 30 45 60 90 135 180 270; do
  pose "2, 0.5, 0" "0, 0, 1" $deg > "$work/z$deg.json"
  for t in 1e-2 3e-3 1e-3; do for m in "$box" "$bracket"; do run "$m" "$work/z$deg.json" $t; done; done
done
for deg in 30 100; do
  pose "0, 1, 0.7" "1, 0, 0" $deg > "$work/x$deg.json"
  pose "1.5, 0, 0.5" "0, 1, 0" $deg > "$work/y$deg.json"
  for f in x y; do for m in "$box" "$prism" "$tetra"; do for t in 1e-2 3e-3; do run "$m" "$work/$f$deg.json" $t; done; done; done
done
echo '{"keyframes": [{"t": 0, "pose": [[1,0,0,0],[0,1,0,0],[0,0,1,0]]}, {"t": 1, "pose": [[1.2, 0.7, 0, 1.5], [-0.3, 0.9, 0, 0.5], [0, 0, 1, 0]]}]}' > "$work/shear_z.json"
for m in "$box" "$prism" "$bracket" "$tetra"; do for t in 1e-2 3e-3; do run "$m" "$work/shear_z.json" $t; done; done
for t in 2e-2 1e-2 3e-3 1e-3; do run "$tetra" "$root/tests/sweep/fixtures/tetra_shear_keeps_z.json" $t; done
exit $failed
