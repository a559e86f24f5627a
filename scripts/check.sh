#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test: the normal build, then
# once more under AddressSanitizer + UndefinedBehaviorSanitizer, then a short
# run of each fuzz target (the scene loader, the URDF importer).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install-deps.sh"
jobs="$(nproc)"

"$root/scripts/build.sh" "$root/build"
ctest --test-dir "$root/build" --output-on-failure -j "$jobs"

# The sanitizer build: -O1 with line tables (half the compile time of -O2 -g,
# asserts on), only what the tests run; without MPI (Open MPI's own allocations
# would read as leaks: the MPI sweep is tested by the normal build).
ROBOPHI_TARGETS="robophi robophi_tests" "$root/scripts/build.sh" "$root/build-asan" \
  -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" -DROBOPHI_SANITIZE=ON \
  -DROBOPHI_MPI=OFF
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir "$root/build-asan" --output-on-failure -j "$jobs" -LE "slow|package|viewer|bench"

# The fuzz targets (fuzz/README.md): a short libFuzzer run of each, their own
# clang build of the libraries and the targets only (scripts/fuzz.sh for the long run).
ROBOPHI_FUZZ_JOBS="$jobs" "$root/scripts/fuzz.sh" -runs=20000 -max_total_time=60
ROBOPHI_FUZZ_JOBS="$jobs" "$root/scripts/fuzz.sh" urdf -runs=20000 -max_total_time=60
