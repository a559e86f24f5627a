#!/usr/bin/env bash
# The replay page in a real browser: copies the fixture run folder, writes its
# replay.html with `robophi export html`, and drives it in headless Chromium
# (tests/viewer/replay.test.mjs); then the same for a real run of
# scenes/arm_obstacle.json.
#
#   tests/viewer/run_viewer_test.sh ROBOPHI_BINARY ARTIFACT_DIR
#
# Exit 77 (skipped) when Chromium, node or viewer/node_modules/playwright-core is
# missing, unless CI is set: then a missing tool is a failure.
set -euo pipefail

robophi=${1:?usage: run_viewer_test.sh ROBOPHI_BINARY ARTIFACT_DIR}
artifacts=${2:?usage: run_viewer_test.sh ROBOPHI_BINARY ARTIFACT_DIR}
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
chromium=${ROBOPHI_CHROMIUM:-/usr/bin/chromium}

missing=()
[ -x "$chromium" ] || missing+=("$chromium (apt-get install chromium)")
command -v node >/dev/null || missing+=("node")
[ -d "$repo/viewer/node_modules/playwright-core" ] ||
  missing+=("viewer/node_modules/playwright-core (npm ci --prefix viewer)")
if [ ${#missing[@]} -gt 0 ]; then
  if [ "${CI:-}" = "true" ] || [ "${CI:-}" = "1" ]; then
    echo "viewer test: missing ${missing[*]}" >&2
    exit 1
  fi
  echo "viewer test: skipped, missing ${missing[*]}"
  exit 77
fi

mkdir -p "$artifacts"
run="$artifacts/fixture_run"
rm -rf "$run"
mkdir -p "$run"
cp "$here"/fixture/*.json "$here"/fixture/*.csv "$run"/

"$robophi" export html "$run"
"$robophi" export vtk "$run"
test -s "$run/vtk/run.pvd"

export ROBOPHI_CHROMIUM="$chromium"
node "$here/replay.test.mjs" "$run" "$artifacts/replay.png"

# A real run end to end: robophi run writes world.json and the page, which must
# draw the obstacle, its security distance, the virtual obstacle of the escape
# and the goal (scenes/arm_obstacle.json: 0.1 s of wall time).
arm="$artifacts/arm_obstacle_run"
rm -rf "$arm"
"$robophi" run "$repo/scenes/arm_obstacle.json" --out "$arm" --quiet > /dev/null
node "$here/replay.test.mjs" "$arm" "$artifacts/arm_obstacle.png"
