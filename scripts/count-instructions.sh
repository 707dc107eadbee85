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
  # The tree's own layout (folders moved under issue 28): every include
  # directory and library of the model, the SoC software, the world and the
  # board that exists in it.
  inc=(-I"$PWD/testbenches/support" -I"$tree/rtl_model/include" -I"$b/generated/include"
       -isystem /usr/include/eigen3)
  for dir in "$tree"/soc_software/include "$tree"/soc_software/*/include \
             "$tree"/host_tools/{,sim/}{world,board}/include; do
    [ -d "$dir" ] && inc+=(-I"$dir")
  done
  libs=(-Wl,--start-group)
  for lib in "$b"/host_tools/{,sim/}{board,world}/libodoloc_*.a "$b"/soc_software/libodoloc_sw*.a \
             "$b"/rtl_model/libodoloc_rtl.a; do
    [ -f "$lib" ] && libs+=("$lib")
  done
  libs+=(-Wl,--end-group -lfmt)
  for driver in four_eppm chip fast_forward fast_forward_moving; do
    g++ -O3 -DNDEBUG -std=c++20 "${inc[@]}" "testbenches/bench/counts/$driver.cpp" \
        -o "$out/$driver" "${libs[@]}"
    valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file="$out/cg" \
             "$out/$driver" >/dev/null 2>&1
    printf '%-14s %-40s %s\n' "$driver" "$(git -C "$tree" rev-parse --short HEAD)" \
           "$(awk '/^summary:/ {print $2}' "$out/cg")"
  done
done
