#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test: the normal build, then
# once more under AddressSanitizer + UndefinedBehaviorSanitizer, then a short
# run of each fuzz target (the scene loader, the URDF importer). Each phase
# prints its wall time and its CPU time (user + system, of all its processes).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
jobs="$(nproc)"

phase() {
  local TIMEFORMAT="check.sh: $1: %R s wall, %U s user + %S s system"
  shift
  time "$@"
}

phase "dependencies" "$root/scripts/install-deps.sh"

phase "build" "$root/scripts/build.sh" "$root/build"
phase "tests" ctest --test-dir "$root/build" --output-on-failure -j "$jobs"

# The sanitizer build: -O1 with line tables (half the compile time of -O2 -g,
# asserts on), only what the tests run; without MPI (Open MPI's own allocations
# would read as leaks: the MPI sweep is tested by the normal build); a unity
# build (CMAKE_UNITY_BUILD: a target's files compiled eight to a file, their
# headers parsed once a batch; the tests are one in every build). Its tests run
# in a few processes, gtest's shards (tests/CMakeLists.txt).
phase "sanitizer build" env ROBOPHI_TARGETS="robophi robophi_tests" \
  "$root/scripts/build.sh" "$root/build-asan" -DCMAKE_BUILD_TYPE=Debug \
  -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" -DROBOPHI_SANITIZE=ON -DROBOPHI_MPI=OFF -DCMAKE_UNITY_BUILD=ON
phase "sanitizer tests" env ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir "$root/build-asan" --output-on-failure -j "$jobs" -LE "slow|package|viewer|bench"

# The fuzz targets (fuzz/README.md): a short libFuzzer run of each, their own
# clang build of the libraries and the targets only (scripts/fuzz.sh for the long run).
export ROBOPHI_FUZZ_JOBS="$jobs"
phase "fuzz scene (build, run)" "$root/scripts/fuzz.sh" -runs=20000 -max_total_time=60
phase "fuzz urdf (build, run)" "$root/scripts/fuzz.sh" urdf -runs=20000 -max_total_time=60
