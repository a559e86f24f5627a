#!/usr/bin/env bash
# Remakes the replay screenshots of docs/viewer.md: runs scenes/arm_obstacle.json,
# scenes/vehicle_hills.json and scenes/hand_grasp.json into OUT (default
# out/screenshots) and shoots each replay page in headless Chromium
# (tests/viewer/screenshot.mjs) into docs/<scene>-replay.png.
#
#   scripts/viewer_screenshots.sh [BUILD_DIR] [OUT]
#
# Needs a built robophi, node, /usr/bin/chromium and viewer/node_modules (npm ci
# --prefix viewer). Each page is shown at a chosen time and, for the vehicle,
# from a chosen view (tests/viewer/screenshot.mjs VIEW) so that the terrain
# and the goal ahead are both in the picture.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$repo/build}
out=${2:-$repo/out/screenshots}
robophi=$build/robophi
mkdir -p "$out"

shoot() {  # scene, time to show ("last" or seconds), view JSON or ""
  local scene=$1 when=$2 view=$3
  local name
  name=$(basename "$scene" .json)
  "$robophi" run "$repo/scenes/$scene" --out "$out/$name" --quiet
  node "$repo/tests/viewer/screenshot.mjs" "$out/$name" "$repo/docs/$name-replay.png" "$when" "$view"
}

# After the escape's first virtual obstacle (t = 1.03 s), the arm sliding off it.
shoot arm_obstacle.json 1.6 ""
# On the second row of hills, the goal 2 m ahead.
shoot vehicle_hills.json 6.5 '{"target": [1.9, 0, 0], "distance": 3.2, "elevation": 0.55}'
# The ball held, after the sideways kick at 1.5 s.
shoot hand_grasp.json 3 ""
