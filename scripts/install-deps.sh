#!/usr/bin/env bash
# Installs what robophi needs on Debian 12, from Debian's packages only (clang
# and its runtime libraries are for the fuzz target, scripts/fuzz.sh).
# Safe to run again: apt-get skips what is already there.
set -euo pipefail

# Installs the Debian packages among "$@" that are not installed yet.
install_missing() {
  local missing=() p
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" ||
      missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "robophi: installing ${missing[*]}"
  local sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
    "${missing[@]}"
}

install_missing \
  build-essential cmake ninja-build pkg-config \
  nlohmann-json3-dev libcli11-dev libfmt-dev libeigen3-dev \
  libgtest-dev libgmock-dev libbenchmark-dev libomp-dev \
  python3 python3-numpy python3-pytest python3-jsonschema \
  clang libclang-rt-dev

# Robots and meshes (docs/robots.md): the URDF reader's XML with line numbers
# (tinyxml2), collision meshes (assimp: STL, OBJ, ...), and the forward
# kinematics the tests check the importer against (orocos-kdl, kdl-parser,
# urdfdom); the Python package (pybind11, python3-dev).
install_missing \
  libtinyxml2-dev libassimp-dev libtinyobjloader-dev \
  liburdfdom-dev liborocos-kdl-dev libkdl-parser-dev \
  pybind11-dev python3-dev

# MJCF import through MuJoCo's own compiler (docs/robots.md "MJCF"; optional: without
# it, robophi builds and says that MJCF needs libmujoco-dev).
install_missing libmujoco-dev

# robophi sweep across processes (docs/sweep.md): Open MPI.
install_missing openmpi-bin libopenmpi-dev

# The PILE benchmark's yardstick (bench/bullet_pile.cpp, docs/performance.md):
# Bullet, whose Debian package carries a double-precision build.
install_missing libbullet-dev

# The live view (docs/viewer.md "Live view": robophi run --live, world.view()): its
# HTTP and WebSocket server is Boost.Beast over Boost.Asio, header-only (optional:
# without it, robophi builds and --live says that it needs libboost-dev).
install_missing libboost-dev

# The replay viewer (docs/viewer.md): Chromium runs its browser test, and npm
# brings three.js and playwright-core into viewer/node_modules. node and npm may
# already come from elsewhere (e.g. NodeSource); apt installs them only if not.
viewer_packages=(chromium)
command -v node >/dev/null 2>&1 || viewer_packages+=(nodejs)
command -v npm >/dev/null 2>&1 || viewer_packages+=(npm)
install_missing "${viewer_packages[@]}"

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [ ! -d "$repo_root/viewer/node_modules/three" ] ||
   [ ! -d "$repo_root/viewer/node_modules/playwright-core" ]; then
  echo "robophi: npm ci --prefix viewer"
  npm ci --prefix "$repo_root/viewer" --no-audit --no-fund
fi
