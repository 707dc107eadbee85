#!/usr/bin/env python3
"""test_plot_scaling: scripts/plot-scaling.py on a short real odoloc_bench run.

    test_plot_scaling.py ODOLOC_BENCH PLOT_SCALING_PY

Runs the Scaling benchmarks briefly into JSON, draws the picture, and checks
the PNG (signature, size), the printed table (every point of every series,
fast-forward far ahead of the cycle step with nothing moving), a report with
a series missing (exit 1, named) and a bad command line (exit 2).
"""
import json
import pathlib
import struct
import subprocess
import sys
import tempfile

EXPECTED_X = {
    "BM_Scaling_Encoders": [0, 1, 2, 3, 4],
    "BM_Scaling_EdgeRate": [1000, 10000, 100000, 1000000],
    "BM_Scaling_TofChannels": [0, 1, 2, 4, 8],
}


def fail(message):
    print(f"FAIL: {message}")
    sys.exit(1)


def main():
    bench, script = sys.argv[1], sys.argv[2]
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        report = tmp / "bench.json"
        subprocess.run([bench, "--benchmark_filter=Scaling", "--benchmark_min_time=0.001",
                        f"--benchmark_out={report}", "--benchmark_out_format=json"],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        png = tmp / "scaling.png"
        run = subprocess.run([sys.executable, script, str(report), str(png)],
                             capture_output=True, text=True)
        if run.returncode != 0:
            fail(f"plot-scaling exited {run.returncode}: {run.stderr}")
        data = png.read_bytes()
        if data[:8] != b"\x89PNG\r\n\x1a\n":
            fail("not a PNG")
        width, height = struct.unpack(">II", data[16:24])
        if (width, height) != (1500, 500):
            fail(f"PNG is {width}x{height}, expected 1500x500")

        rows = [line.split("\t") for line in run.stdout.splitlines()[1:]]
        table = {(r[0], r[1], int(r[2])): float(r[3]) for r in rows}
        for family, xs in EXPECTED_X.items():
            for mode in ("fast-forward", "cycle step"):
                got = sorted(x for (f, m, x) in table if f == family and m == mode)
                if got != xs:
                    fail(f"{family} {mode}: points {got}, expected {xs}")
        if any(rate <= 0 for rate in table.values()):
            fail("a rate is not positive")
        still_ff = table[("BM_Scaling_Encoders", "fast-forward", 0)]
        still_step = table[("BM_Scaling_Encoders", "cycle step", 0)]
        if still_ff < 10 * still_step:
            fail(f"with nothing moving fast-forward ({still_ff:.3g}/s) should be far ahead of "
                 f"the cycle step ({still_step:.3g}/s)")

        partial = json.loads(report.read_text())
        partial["benchmarks"] = [b for b in partial["benchmarks"]
                                 if not b["name"].startswith("BM_Scaling_TofChannels")]
        partial_path = tmp / "partial.json"
        partial_path.write_text(json.dumps(partial))
        run = subprocess.run([sys.executable, script, str(partial_path), str(tmp / "p.png")],
                             capture_output=True, text=True)
        if run.returncode != 1 or "BM_Scaling_TofChannels (fast-forward)" not in run.stderr:
            fail(f"a missing series: exit {run.returncode}, {run.stderr!r}")
        if (tmp / "p.png").exists():
            fail("a picture was drawn from a report with a series missing")

        run = subprocess.run([sys.executable, script], capture_output=True, text=True)
        if run.returncode != 2 or "plot-scaling.py BENCH.json OUT.png" not in run.stderr:
            fail(f"usage: exit {run.returncode}, {run.stderr!r}")
    print("PASS")


if __name__ == "__main__":
    main()
