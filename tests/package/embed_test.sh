#!/usr/bin/env bash
# The installed package (issue 10): installs the build tree into a fresh prefix,
# checks that nothing of the build leaks into it (flags, private dependencies,
# private headers), builds examples/embed against it with find_package and with
# pkg-config, and runs both.
#   embed_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build="$1"
source="$2"
work="$build/package-test"
rm -rf "$work"
cmake --install "$build" --prefix "$work/prefix" > "$work.install.log"
prefix="$work/prefix"

# The exported targets carry no compile flag, no sanitizer, no private header-only
# dependency (fmt is linked, as Debian's libfmt, and found by robophiConfig.cmake).
targets=$(find "$prefix" -name 'robophiTargets*.cmake')
[ -n "$targets" ] || { echo "no robophiTargets.cmake installed"; exit 1; }
if grep -nE 'ffp-contract|fsanitize|Werror|OpenMP|fmt::fmt-header-only|nlohmann|Eigen3|CLI11|GTest' $targets; then
  echo "the exported targets leak a build flag or a private dependency"; exit 1
fi
# Installed headers include only robophi's own headers and the standard library.
if grep -rnE '#include *[<"](nlohmann|fmt|Eigen|CLI|gtest|collision/|forces/|integrate/|model/|core/|scene/|build/)' \
     "$prefix/include/robophi"; then
  echo "an installed header includes a private or third-party header"; exit 1
fi
for lib in core build scene; do
  find "$prefix" -name "librobophi_$lib.a" | grep -q . || { echo "librobophi_$lib.a missing"; exit 1; }
done

generator=()
command -v ninja > /dev/null && generator=(-G Ninja)
cmake -S "$source/examples/embed" -B "$work/embed" "${generator[@]}" \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" > "$work/embed.configure.log"
cmake --build "$work/embed" --parallel 2 > "$work/embed.build.log"
# The hand grasp: contacts and (passive) joint values; the servo arm: targets.
"$work/embed/embed" "$source/scenes/hand_grasp.json" 1.0 | tee "$work/hand.txt"
grep -qE 'most contacts [1-9]' "$work/hand.txt" || { echo "no contact in the hand grasp"; exit 1; }
"$work/embed/embed" "$source/scenes/revolute_arm.json" 1.0 | tee "$work/arm.txt"
grep -qE 'ok: [1-9][0-9]* driven joints followed' "$work/arm.txt" || { echo "no joint driven"; exit 1; }

pc_dir=$(dirname "$(find "$prefix" -name robophi.pc)")
flags=$(PKG_CONFIG_PATH="$pc_dir" pkg-config --cflags --libs robophi)
c++ -O2 "$source/examples/embed/main.cpp" $flags -o "$work/embed-pkg-config"
"$work/embed-pkg-config" "$source/scenes/revolute_arm.json" 0.5
# As a subproject (add_subdirectory): the three libraries, and no tests, CLI or npm step.
cmake -S "$source/examples/embed" -B "$work/subproject" "${generator[@]}" \
  -DROBOPHI_SOURCE_DIR="$source" > "$work/subproject.configure.log"
rules="$work/subproject/build.ninja"
[ -f "$rules" ] || rules="$work/subproject/Makefile"
for wanted in robophi_core robophi_build robophi_scene embed; do
  grep -q "$wanted" "$rules" || { echo "subproject: no target $wanted"; exit 1; }
done
if grep -qE 'robophi_tests|robophi_replay_assets|robophi_app|CLI11|gtest' "$rules"; then
  echo "subproject: robophi's tests, CLI or viewer step came along"; exit 1
fi
echo "package: installed, found by find_package and pkg-config, embed ran; subproject clean"
