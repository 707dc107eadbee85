#!/usr/bin/env bash
# Wall-clock medians of the model's speed benchmarks for this tree against a
# second worktree with its own build/default (docs/performance.md, "One
# source per block"): RUNS interleaved runs (default 5), each benchmark
# alone, pinned to CPU 0, base and new alternating.
#   scripts/compare-benchmarks.sh OTHER_WORKTREE [RUNS]
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 1 ] || { echo "usage: $0 OTHER_WORKTREE [RUNS]" >&2; exit 2; }
base=$(cd "$1" && pwd)
runs=${2:-5}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
filters=(BM_FourEppm_CycleStep BM_OdolocChip_CycleStep BM_OdolocChip_FastForward_EncodersStill
         'BM_Scaling_Encoders/encoders:4/cycle_step:0' 'BM_Scaling_TofChannels/channels:8/cycle_step:0')
for ((r = 0; r < runs; ++r)); do
  for f in "${filters[@]}"; do
    for tree in "$base" "$PWD"; do
      tag=$([ "$tree" = "$base" ] && echo base || echo new)
      taskset -c 0 "$tree/build/default/testbenches/odoloc_bench" --benchmark_filter="^$f\$" \
        --benchmark_min_time=0.5 --benchmark_format=json 2>/dev/null >"$out/$tag.$r.$(echo "$f" | tr '/:' '__').json"
    done
  done
done
python3 - "$out" "$(git -C "$base" rev-parse --short HEAD)" "$(git rev-parse --short HEAD)" <<'PY'
import json, pathlib, statistics, sys
out, base, new = pathlib.Path(sys.argv[1]), sys.argv[2], sys.argv[3]
times = {}
for p in sorted(out.glob("*.json")):
    tag = p.name.split(".")[0]
    for b in json.loads(p.read_text())["benchmarks"]:
        times.setdefault(b["name"], {}).setdefault(tag, []).append(b["real_time"])
print(f"{'benchmark (median real time)':58} {base:>12} {new:>12}  ratio")
for name, t in times.items():
    mb, mn = statistics.median(t["base"]), statistics.median(t["new"])
    print(f"{name:58} {mb:12.0f} {mn:12.0f}  {mn / mb:.3f}")
PY
