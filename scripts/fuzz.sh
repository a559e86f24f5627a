#!/usr/bin/env bash
# Fuzzes the scene loader (fuzz/fuzz_scene.cpp, fuzz/README.md) with libFuzzer:
# builds the target with Debian's clang into build-fuzz/ (only the libraries and
# the target: coverage, ASan, UBSan), then runs it on the seed corpus.
#
#   scripts/fuzz.sh                  the long run: 1 000 000 executions
#   scripts/fuzz.sh -runs=20000      a short run (scripts/check.sh)
#   scripts/fuzz.sh -max_total_time=3600
#
# Extra arguments go to libFuzzer. New inputs that reach new code are kept in
# build-fuzz/corpus (not in the repository); a crash, leak, timeout or
# out-of-memory writes build-fuzz/artifacts/<kind>-<hash> and exits non-zero:
# reproduce with build-fuzz/fuzz/robophi_fuzz_scene build-fuzz/artifacts/<file>.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${ROBOPHI_FUZZ_BUILD:-$root/build-fuzz}"

if [ ! -f "$build/build.ninja" ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++ \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DROBOPHI_FUZZ=ON -DROBOPHI_BUILD_APP=OFF \
    -DROBOPHI_BUILD_TESTS=OFF -DROBOPHI_CHECK_LAYERS=OFF >/dev/null
fi
cmake --build "$build" --target robophi_fuzz_scene -j "${ROBOPHI_FUZZ_JOBS:-$(nproc)}"

mkdir -p "$build/corpus" "$build/artifacts"
# Defaults: a million runs, 30 s per input is a hang (a scene at the size budget
# takes a few seconds under ASan), 2 GB is out of memory;
# arguments given later win. Heightfield seeds name their PGM files relative to
# tests/scene/broken, so the run starts there.
cd "$root/tests/scene/broken"
ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}" UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}" \
  "$build/fuzz/robophi_fuzz_scene" -runs=1000000 -timeout=30 -rss_limit_mb=2048 -max_len=65536 \
  -dict="$root/fuzz/scene.dict" -artifact_prefix="$build/artifacts/" -print_final_stats=1 "$@" \
  "$build/corpus" "$root/fuzz/seeds" "$root/scenes" "$root/tests/scene/broken"
