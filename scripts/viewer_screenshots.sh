#!/usr/bin/env bash
# Remakes the replay screenshots of docs/viewer.md: runs scenes/arm_obstacle.json,
# scenes/vehicle_hills.json and scenes/hand_grasp.json into OUT (default
# out/screenshots) and shoots each replay page in headless Chromium
# (tests/viewer/screenshot.mjs) into docs/<scene>-replay.png.
#
#   scripts/viewer_screenshots.sh [BUILD_DIR] [OUT]
#
# Needs a built robophi, node, /usr/bin/chromium and viewer/node_modules (npm ci
# --prefix viewer). hand_grasp is run for its first 4 s (the grasp is closed and
# the kick given by then; the whole scene is 50 s).
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$repo/build}
out=${2:-$repo/out/screenshots}
robophi=$build/robophi
mkdir -p "$out"

shoot() {  # scene, time to show ("last" or seconds), extra run options...
  local scene=$1 when=$2
  shift 2
  local name
  name=$(basename "$scene" .json)
  "$robophi" run "$repo/scenes/$scene" --out "$out/$name" --quiet "$@"
  node "$repo/tests/viewer/screenshot.mjs" "$out/$name" "$repo/docs/$name-replay.png" "$when"
}

shoot arm_obstacle.json last
shoot vehicle_hills.json 6
shoot hand_grasp.json last --duration 4
