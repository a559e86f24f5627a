#!/usr/bin/env bash
# The robots of the replay page as they look (tests/viewer/robots.test.mjs): bare
# URDF runs of the iiwa, the UR5 and the Panda (particle form; the iiwa and the
# UR5 as rigid bodies too, --rigid), short; then an interrupted run, whose
# folder must hold a replay.html that loads.
#
#   tests/viewer/run_robots_test.sh ROBOPHI_BINARY ARTIFACT_DIR
#
# Exit 77 (skipped) when Chromium, node, viewer/node_modules/playwright-core or the
# robots (ROBOPHI_ROBOTS_DIR, and robots-wild beside it) are missing, unless CI is set.
set -euo pipefail

robophi=${1:?usage: run_robots_test.sh ROBOPHI_BINARY ARTIFACT_DIR}
artifacts=${2:?usage: run_robots_test.sh ROBOPHI_BINARY ARTIFACT_DIR}
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
chromium=${ROBOPHI_CHROMIUM:-/usr/bin/chromium}
robots=${ROBOPHI_ROBOTS_DIR:-$repo/../shared/robots}
wild="$robots/../robots-wild"
ur5="$wild/example-robot-data/robots/ur_description/urdf/ur5_robot.urdf"

missing=()
[ -x "$chromium" ] || missing+=("$chromium (apt-get install chromium)")
command -v node >/dev/null || missing+=("node")
[ -d "$repo/viewer/node_modules/playwright-core" ] ||
  missing+=("viewer/node_modules/playwright-core (npm ci --prefix viewer)")
[ -f "$robots/kuka_iiwa/model.urdf" ] || missing+=("$robots/kuka_iiwa/model.urdf (ROBOPHI_ROBOTS_DIR)")
[ -f "$ur5" ] || missing+=("$ur5")
if [ ${#missing[@]} -gt 0 ]; then
  if [ "${CI:-}" = "true" ] || [ "${CI:-}" = "1" ]; then
    echo "viewer robots test: missing ${missing[*]}" >&2
    exit 1
  fi
  echo "viewer robots test: skipped, missing ${missing[*]}"
  exit 77
fi

# The runs go to a folder of this test's own: ctest runs the viewer tests side by
# side, and run_reference_test.sh runs an iiwa and a UR5 (other scenes) too.
runs="$artifacts/robot_runs"
mkdir -p "$runs"
export ROBOPHI_CHROMIUM="$chromium"
run() {  # run NAME URDF [options...]
  local name=$1 urdf=$2
  shift 2
  rm -rf "${runs:?}/$name"
  "$robophi" run "$urdf" --duration 0.1 --out "$runs/$name" --quiet "$@" > /dev/null
}
run iiwa "$robots/kuka_iiwa/model.urdf"
run iiwa_rigid "$robots/kuka_iiwa/model.urdf" --rigid
run ur5 "$ur5" --package-path "$wild"
run ur5_rigid "$ur5" --package-path "$wild" --rigid
run panda "$robots/franka_panda/panda.urdf" --package-path "$robots/franka_panda"
node "$here/robots.test.mjs" "$artifacts/robots" "$runs/iiwa:q" "$runs/iiwa_rigid" \
  "$runs/ur5:q" "$runs/ur5_rigid" "$runs/panda:q"

# An interrupted run: SIGINT once it has written frames; its folder gets the page
# (the run is long enough that no machine finishes it first).
stopped="$artifacts/interrupted"
rm -rf "$stopped" "$stopped.log"
"$robophi" run "$robots/kuka_iiwa/model.urdf" --duration 1000 --out "$stopped" > "$stopped.log" 2>&1 &
pid=$!
# (It writes into its staging folder, .interrupted.partial, until it ends.)
rows() { cat "$artifacts/.interrupted.partial/energy.csv" 2>/dev/null | wc -l; }
until [ "$(rows)" -ge 2 ]; do
  if ! kill -0 "$pid" 2>/dev/null; then break; fi
  sleep 0.2
done
kill -INT "$pid" 2>/dev/null || true
status=0
wait "$pid" || status=$?
[ "$status" -eq 130 ] || { echo "interrupted run: exit $status, expected 130" >&2; cat "$stopped.log" >&2; exit 1; }
grep -q '"status": *"interrupted"' "$stopped/summary.json"
test -s "$stopped/replay.html"
node "$here/replay.test.mjs" "$stopped" "$artifacts/interrupted.png"
