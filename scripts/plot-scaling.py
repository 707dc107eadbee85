#!/usr/bin/env python3
"""Draws how the model's speed grows with work, from odoloc_bench's JSON.

    plot-scaling.py BENCH.json OUT.png

BENCH.json: `odoloc_bench --benchmark_filter=Scaling --benchmark_out=BENCH.json
--benchmark_out_format=json` (Google Benchmark's JSON). Draws three panels,
fabric clocks per second (fast-forward: effective) against the encoders
moving, one encoder's edge rate and the comparator channels pulsing, each
fast-forwarded and cycle-stepped, with the 50 MHz fabric as the real-time
line (docs/performance.md). Prints the plotted table on standard output.
Exits 1, naming what is missing, when a series has no point; 2 on usage.
"""
import json
import pathlib
import subprocess
import sys
import tempfile

# benchmark name -> (argument on the x axis, x label, log x)
PANELS = {
    "BM_Scaling_Encoders": ("encoders", "encoders moving (100 k edges/s each)", False),
    "BM_Scaling_EdgeRate": ("edges_per_s", "edges per second on one encoder", True),
    "BM_Scaling_TofChannels": ("channels", "comparator channels pulsing (1 kHz)", False),
}
MODES = {0: "fast-forward", 1: "cycle step"}
FABRIC_CLOCK_HZ = 50e6


def parse_name(name):
    """'BM_X/a:1/b:2' -> ('BM_X', {'a': 1, 'b': 2}); ignores aggregates."""
    family, *args = name.split("/")
    values = {}
    for arg in args:
        key, _, value = arg.partition(":")
        if value.lstrip("-").isdigit():
            values[key] = int(value)
    return family, values


def series(report):
    """{(family, cycle_step): [(x, clocks per second), ...]} sorted by x."""
    points = {}
    for bench in report.get("benchmarks", []):
        if bench.get("run_type", "iteration") != "iteration" or "items_per_second" not in bench:
            continue
        family, args = parse_name(bench["name"])
        if family not in PANELS or "cycle_step" not in args:
            continue
        x = args.get(PANELS[family][0])
        if x is None:
            continue
        points.setdefault((family, args["cycle_step"]), []).append(
            (x, float(bench["items_per_second"])))
    return {key: sorted(values) for key, values in points.items()}


def gnuplot_script(points, data_dir, output):
    lines = [
        "set terminal pngcairo size 1500,500 font ',10'",
        f"set output '{output}'",
        "set multiplot layout 1,3 title 'odoloc chip model: fabric clocks per second "
        "(fast-forward: effective)'",
        "set logscale y",
        "set format y '%.0s%c'",
        "set ylabel 'clocks/s'",
        "set grid",
        "set key left center box opaque",
    ]
    for family, (_, label, log_x) in PANELS.items():
        lines.append("set logscale x; set xtics auto" if log_x else "unset logscale x; set xtics 1")
        lines.append(f"set xlabel '{label}'")
        plots = [f"'{data_dir / f'{family}_{mode}.dat'}' using 1:2 with linespoints "
                 f"title '{title}'" for mode, title in MODES.items()]
        plots.append(f"{FABRIC_CLOCK_HZ} with lines dashtype 2 title 'real time (50 MHz)'")
        lines.append("plot " + ", ".join(plots))
    lines.append("unset multiplot")
    return "\n".join(lines) + "\n"


def main(argv):
    if len(argv) != 3:
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    report = json.loads(pathlib.Path(argv[1]).read_text())
    points = series(report)
    missing = [f"{family} ({MODES[mode]})" for family in PANELS for mode in MODES
               if not points.get((family, mode))]
    if missing:
        print(f"plot-scaling: {argv[1]} has no point for " + ", ".join(missing)
              + " (run odoloc_bench --benchmark_filter=Scaling)", file=sys.stderr)
        return 1
    with tempfile.TemporaryDirectory() as tmp:
        data_dir = pathlib.Path(tmp)
        print("benchmark\tmode\tx\tclocks_per_s")
        for (family, mode), values in sorted(points.items()):
            with open(data_dir / f"{family}_{mode}.dat", "w") as data:
                for x, rate in values:
                    data.write(f"{x} {rate}\n")
                    print(f"{family}\t{MODES[mode]}\t{x}\t{rate:.6g}")
        subprocess.run(["gnuplot"], input=gnuplot_script(points, data_dir, argv[2]), text=True,
                       check=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
