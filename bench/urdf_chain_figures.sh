#!/usr/bin/env bash
# Import time and peak memory of URDF chains (bench/urdf_chain.py), both importers:
#   bench/urdf_chain_figures.sh ROBOPHI_BINARY OUT_FILE
# Each row: links, joint type, importer, exit code, wall s, user s, peak RSS MB.
set -u
robophi="$1"; out="$2"
root="$(cd "$(dirname "$0")/.." && pwd)"
dir="$(mktemp -d)"
printf "%-6s %-9s %-10s %4s %8s %8s %8s\n" links joint importer exit wall_s user_s rss_MB > "$out"
for n in 1000 5000 20000; do
  for joint in revolute fixed; do
    python3 "$root/bench/urdf_chain.py" "$n" "$joint" > "$dir/chain$n$joint.urdf"
    for importer in --rigid --particles; do
      /usr/bin/time -f "%e %U %M" -o "$dir/time" timeout 600 "$robophi" validate \
        "$importer" "$dir/chain$n$joint.urdf" > "$dir/out" 2>&1
      code=$?
      read -r wall user rss < <(tail -1 "$dir/time")
      printf "%-6s %-9s %-10s %4s %8s %8s %8d\n" "$n" "$joint" "${importer#--}" "$code" "$wall" \
        "$user" "$((rss / 1024))" >> "$out"
      [ "$code" = 0 ] || sed -n 1,3p "$dir/out" | cut -c1-300 | sed 's/^/    /' >> "$out"
    done
  done
done
rm -rf "$dir"
