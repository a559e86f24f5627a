#!/usr/bin/env bash
# The live view in a real browser (tests/viewer/live.test.mjs): robophi run --live
# on scenes/pendulum.json, driven by headless Chromium through the page: frames per
# second, pause and resume, a mouse drag and its work in summary.json, and the
# state hash of a live run without drag against the plain run's.
#
#   tests/viewer/run_live_test.sh ROBOPHI_BINARY ARTIFACT_DIR
#
# Exit 77 (skipped) when Chromium, node or viewer/node_modules/playwright-core is
# missing, or robophi was built without the live view (no Boost.Beast), unless CI
# is set: then any of them missing is a failure.
set -euo pipefail

robophi=${1:?usage: run_live_test.sh ROBOPHI_BINARY ARTIFACT_DIR}
artifacts=${2:?usage: run_live_test.sh ROBOPHI_BINARY ARTIFACT_DIR}
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
chromium=${ROBOPHI_CHROMIUM:-/usr/bin/chromium}

missing=()
[ -x "$chromium" ] || missing+=("$chromium (apt-get install chromium)")
command -v node >/dev/null || missing+=("node")
[ -d "$repo/viewer/node_modules/playwright-core" ] ||
  missing+=("viewer/node_modules/playwright-core (npm ci --prefix viewer)")
# Without Boost.Beast, --live says that it is not built (and runs nothing).
if "$robophi" run "$repo/scenes/pendulum.json" --live --live-port 0 --live-wait 0 \
     --duration 0.01 --out "$artifacts/live_probe" --quiet 2>&1 >/dev/null |
   grep -q "live view is not built"; then
  missing+=("the live view (robophi built without Boost.Beast: libboost-dev)")
fi
if [ ${#missing[@]} -gt 0 ]; then
  if [ "${CI:-}" = "true" ] || [ "${CI:-}" = "1" ]; then
    echo "live view test: missing ${missing[*]}" >&2
    exit 1
  fi
  echo "live view test: skipped, missing ${missing[*]}"
  exit 77
fi

mkdir -p "$artifacts"
export ROBOPHI_CHROMIUM="$chromium"
node "$here/live.test.mjs" "$robophi" "$artifacts"
