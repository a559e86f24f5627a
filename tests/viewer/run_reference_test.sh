#!/usr/bin/env bash
# The robots' replays against reference images (tests/viewer/reference.test.mjs):
# the Panda pick (scenes/panda_pick.json, its first 1.5 s: the arm descends), the
# Husky drive (scenes/husky_drive.json, 1.5 s), the iiwa and the UR5 on their
# servos (tests/viewer/scenes/iiwa_swing.json, ur5_swing.json, 1 s), each at t = 0
# and at its end against tests/viewer/reference/<name>-t0.png, -end.png.
#
#   tests/viewer/run_reference_test.sh ROBOPHI_BINARY ARTIFACT_DIR
#
# ROBOPHI_RECORD_REFERENCE=1 re-records the images into tests/viewer/reference/
# (look at them before committing). Exit 77 (skipped) when Chromium, node,
# viewer/node_modules/playwright-core or the robots (ROBOPHI_ROBOTS_DIR, and
# robots-wild beside it) are missing, unless CI is set.
set -euo pipefail

robophi=${1:?usage: run_reference_test.sh ROBOPHI_BINARY ARTIFACT_DIR}
artifacts=${2:?usage: run_reference_test.sh ROBOPHI_BINARY ARTIFACT_DIR}
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
chromium=${ROBOPHI_CHROMIUM:-/usr/bin/chromium}
export ROBOPHI_ROBOTS_DIR=${ROBOPHI_ROBOTS_DIR:-$repo/../shared/robots}
robots=$ROBOPHI_ROBOTS_DIR
ur5="$robots/../robots-wild/example-robot-data/robots/ur_description/urdf/ur5_robot.urdf"

missing=()
[ -x "$chromium" ] || missing+=("$chromium (apt-get install chromium)")
command -v node >/dev/null || missing+=("node")
[ -d "$repo/viewer/node_modules/playwright-core" ] ||
  missing+=("viewer/node_modules/playwright-core (npm ci --prefix viewer)")
for f in kuka_iiwa/model.urdf franka_panda/panda.urdf husky/husky.urdf; do
  [ -f "$robots/$f" ] || missing+=("$robots/$f (ROBOPHI_ROBOTS_DIR)")
done
[ -f "$ur5" ] || missing+=("$ur5")
# (scenes/husky_drive.json names its URDF relative to itself: ../../shared/robots.)
[ -f "$repo/../shared/robots/husky/husky.urdf" ] || missing+=("$repo/../shared/robots/husky/husky.urdf")
if [ ${#missing[@]} -gt 0 ]; then
  if [ "${CI:-}" = "true" ] || [ "${CI:-}" = "1" ]; then
    echo "viewer reference test: missing ${missing[*]}" >&2
    exit 1
  fi
  echo "viewer reference test: skipped, missing ${missing[*]}"
  exit 77
fi

# The runs go to a folder of this test's own: ctest runs the viewer tests side by
# side, and run_robots_test.sh runs an iiwa and a UR5 of its own too.
runs="$artifacts/reference_runs"
mkdir -p "$runs"
export ROBOPHI_CHROMIUM="$chromium"
run() {  # run NAME SCENE [options...]
  local name=$1 scene=$2
  shift 2
  rm -rf "${runs:?}/$name"
  "$robophi" run "$scene" --out "$runs/$name" --quiet "$@" > "$runs/$name.log" 2>&1 ||
    { echo "robophi run $scene failed:" >&2; cat "$runs/$name.log" >&2; exit 1; }
}
run panda_pick "$repo/scenes/panda_pick.json" --duration 1.5
run husky_drive "$repo/scenes/husky_drive.json" --duration 1.5
run iiwa "$here/scenes/iiwa_swing.json"
run ur5 "$here/scenes/ur5_swing.json"
node "$here/reference.test.mjs" "$artifacts/reference" "$here/reference" \
  "panda_pick=$runs/panda_pick" "husky_drive=$runs/husky_drive" \
  "iiwa=$runs/iiwa" "ur5=$runs/ur5"
