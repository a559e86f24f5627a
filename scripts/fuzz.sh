#!/usr/bin/env bash
# Fuzzes the scene loader (fuzz/fuzz_scene.cpp) or the URDF importer with
# meshes (fuzz/fuzz_urdf.cpp; fuzz/README.md) with libFuzzer: builds the target
# with Debian's clang into build-fuzz/ (only the libraries, a unity build, and
# the target: coverage, ASan, UBSan), then runs it on its seed corpus.
#
#   scripts/fuzz.sh                  the scene loader, the long run: 1 000 000 executions
#   scripts/fuzz.sh -runs=20000      a short run (scripts/check.sh)
#   scripts/fuzz.sh urdf -max_total_time=1500    the URDF importer
#   ROBOPHI_FUZZ_SANITIZERS= ROBOPHI_FUZZ_BUILD=build-fuzz-fast scripts/fuzz.sh urdf
#                                    coverage only, no ASan/UBSan: the million-run builds
#
# Extra arguments go to libFuzzer. New inputs that reach new code are kept in
# build-fuzz/corpus (build-fuzz/corpus-urdf) (not in the repository); a crash,
# leak, timeout or out-of-memory writes build-fuzz/artifacts/<kind>-<hash> and
# exits non-zero: reproduce with build-fuzz/fuzz/robophi_fuzz_scene
# build-fuzz/artifacts/<file> (robophi_fuzz_urdf: in build-fuzz/urdf-work, with
# ROBOPHI_FUZZ_URDF_DIR set to it).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${ROBOPHI_FUZZ_BUILD:-$root/build-fuzz}"

if [ ! -f "$build/build.ninja" ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++ \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_UNITY_BUILD=ON -DROBOPHI_FUZZ=ON \
    -DROBOPHI_BUILD_APP=OFF -DROBOPHI_BUILD_TESTS=OFF -DROBOPHI_CHECK_LAYERS=OFF \
    -DROBOPHI_FUZZ_SANITIZERS="${ROBOPHI_FUZZ_SANITIZERS-address,undefined}" >/dev/null
fi
target=scene
if [ "${1:-}" = scene ] || [ "${1:-}" = urdf ]; then
  target="$1"
  shift
fi
cmake --build "$build" --target "robophi_fuzz_$target" -j "${ROBOPHI_FUZZ_JOBS:-$(nproc)}"

mkdir -p "$build/corpus" "$build/corpus-urdf" "$build/artifacts"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}" UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}"
# Leaks inside the system's assimp are its own (fuzz/lsan.supp says which).
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$root/fuzz/lsan.supp}"
if [ "$target" = scene ]; then
  # Defaults: a million runs, 30 s per input is a hang (a scene at the size budget
  # takes a few seconds under ASan), 2 GB is out of memory;
  # arguments given later win. Heightfield seeds name their PGM files relative to
  # tests/scene/broken, so the run starts there.
  cd "$root/tests/scene/broken"
  exec "$build/fuzz/robophi_fuzz_scene" -runs=1000000 -timeout=30 -rss_limit_mb=2048 \
    -max_len=65536 -dict="$root/fuzz/scene.dict" -artifact_prefix="$build/artifacts/" \
    -print_final_stats=1 "$@" \
    "$build/corpus" "$root/fuzz/seeds" "$root/scenes" "$root/tests/scene/broken"
fi

# The URDF importer runs in a work folder that holds the shared robots' meshes
# where their URDFs name them (ROBOPHI_ROBOTS_DIR, default ../shared/robots):
# meshes/ (the iiwa's and the Husky's), pkg/meshes (the Panda's package://meshes),
# the grippers' STL files; the robots' URDFs are seeds beside fuzz/urdf_seeds
# (with meshes of their own) and tests/urdf/broken. A hang is 30 s, as for the
# scene loader (a shared robot with its real meshes takes 12 s instrumented here).
robots="${ROBOPHI_ROBOTS_DIR:-$root/../shared/robots}"
[ -d "$robots" ] || robots="$root/../../shared/robots"
work="$build/urdf-work"
mkdir -p "$work/meshes" "$work/pkg" "$build/urdf-seeds"
if [ -d "$robots" ]; then
  for mesh in "$robots"/kuka_iiwa/meshes/* "$robots"/husky/meshes/*; do
    ln -sfn "$mesh" "$work/meshes/$(basename "$mesh")"
  done
  ln -sfn "$robots/franka_panda/meshes" "$work/pkg/meshes"
  for mesh in "$robots"/pr2_gripper/*.stl; do ln -sfn "$mesh" "$work/$(basename "$mesh")"; done
  cp "$robots"/*/*.urdf "$build/urdf-seeds/"
else
  echo "fuzz.sh: no shared robots at $robots: the URDF seeds are fuzz/urdf_seeds only" >&2
fi
cd "$work"
ROBOPHI_FUZZ_URDF_DIR="$work" exec "$build/fuzz/robophi_fuzz_urdf" -runs=1000000 -timeout=30 \
  -rss_limit_mb=2048 -max_len=65536 -artifact_prefix="$build/artifacts/" -print_final_stats=1 \
  "$@" "$build/corpus-urdf" "$root/fuzz/urdf_seeds" "$build/urdf-seeds" "$root/tests/urdf/broken"
