#!/usr/bin/env bash
# Installs what is missing, builds, and runs the default scene into out/default.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
"$root/build/robophi" run "$root/scenes/default.json" --out "$root/out/default"
