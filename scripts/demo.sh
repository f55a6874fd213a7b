#!/usr/bin/env bash
# The main job on the bundled default scene: installs what is missing, builds, and prints the
# regular pattern of the SAM between the two bundled poses (data/poses/).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh" --target steady >/dev/null
exec "${BUILD_DIR:-$root/build}/cli/steady" demo --data "$root/data" "$@"
