#!/usr/bin/env bash
# Installs the Debian 12 packages steady needs, only those that are missing. With --fuzz, also
# those of scripts/fuzz.sh (Clang and its libFuzzer and sanitizer runtimes).
set -euo pipefail

packages=(
  g++ cmake make
  libeigen3-dev      # core
  libboost-dev       # 50-digit test oracles (boost::multiprecision)
  libgtest-dev       # tests
  libbenchmark-dev   # bench/
  libcli11-dev nlohmann-json3-dev  # cli/, io/ (motion files)
  libopenmesh-dev    # io/ (mesh files)
  libembree-dev libtbb-dev  # collide/ (broad phase); sweep/ (parallel re-triangulation)
  libcgal-dev libgmp-dev libmpfr-dev  # sweep/: CGAL 5.5 (exact kernel: GMP, MPFR)
  libcgal-demo       # bench/: CGAL's sample meshes (data.tar.gz)
  libfcl-dev         # bench/: FCL 0.7, the contact peer
  libopenvdb-dev libboost-iostreams-dev  # bench/: OpenVDB 10, the sweep peer (its FindOpenVDB needs Boost.Iostreams)
)
if [ "${1:-}" = "--fuzz" ]; then
  packages+=(clang libclang-rt-14-dev)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "steady: installing missing Debian packages: ${missing[*]}" >&2
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then
    sudo_cmd=(sudo)
  else
    echo "steady: not root and no sudo; install these packages first: ${missing[*]}" >&2
    exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
