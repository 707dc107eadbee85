#!/usr/bin/env bash
# Instructions of the per-clock and fast-forward drivers (testbenches/bench/
# counts/) under valgrind's cachegrind, for this tree and, when given, a
# second worktree with its own build/default (docs/performance.md, "One
# source per block"): deterministic, where this VM's wall clock varies by
# 20 % between runs.   scripts/count-instructions.sh [OTHER_WORKTREE]
set -euo pipefail
cd "$(dirname "$0")/.."
trees=("$PWD")
[ $# -ge 1 ] && trees=("$(cd "$1" && pwd)" "$PWD")
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for tree in "${trees[@]}"; do
  b=$tree/build/default
  inc=(-I"$PWD/testbenches/support" -I"$tree/rtl_model/include" -I"$b/generated/include"
       -I"$tree/host_tools/world/include" -I"$tree/host_tools/board/include"
       -I"$tree/soc_software/include" -isystem /usr/include/eigen3)
  libs=("$b/host_tools/board/libodoloc_board.a" "$b/soc_software/libodoloc_sw.a"
        "$b/host_tools/world/libodoloc_world.a" "$b/rtl_model/libodoloc_rtl.a" -lfmt)
  for driver in four_eppm chip fast_forward; do
    g++ -O3 -DNDEBUG -std=c++20 "${inc[@]}" "testbenches/bench/counts/$driver.cpp" \
        -o "$out/$driver" "${libs[@]}"
    valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file="$out/cg" \
             "$out/$driver" >/dev/null 2>&1
    printf '%-14s %-40s %s\n' "$driver" "$(git -C "$tree" rev-parse --short HEAD)" \
           "$(awk '/^summary:/ {print $2}' "$out/cg")"
  done
done
