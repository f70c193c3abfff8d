#!/usr/bin/python3
"""Synthesis against the plain yardstick (issue 51), in one run: builds ../shared/perf/baseline_synth.cpp
(Eigen, float32, -march=native, one thread), then runs it and sscape_bench alternately, ROUNDS rounds,
and prints the medians and the ratios with their targets. This machine's speed drifts: compare the
ratios, never the absolute times across runs.

usage: tests/bench/yardstick.py [--build build] [--rounds 3] [--perf ../shared/perf]
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys

root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--build", default=os.path.join(root, "build"), help="the Release build folder (sscape_bench)")
parser.add_argument("--rounds", type=int, default=3)
parser.add_argument("--perf", default=os.path.join(root, "..", "shared", "perf"), help="the folder of baseline_synth.cpp")
parser.add_argument("--min-time", default="0.3", help="sscape_bench's --benchmark_min_time")
args = parser.parse_args()

source = os.path.join(args.perf, "baseline_synth.cpp")
bench = os.path.join(args.build, "tests", "bench", "sscape_bench")
if not os.path.isfile(source):
    print(f"SKIPPED: {source} not found (the yardstick is in ../shared/perf)")
    sys.exit(77)
if not os.access(bench, os.X_OK):
    sys.exit(f"{bench} not found: build the benchmarks first (./setup.sh test)")
baseline = os.path.join(args.build, "yardstick", "baseline_synth")
os.makedirs(os.path.dirname(baseline), exist_ok=True)
if not os.path.exists(baseline) or os.path.getmtime(baseline) < os.path.getmtime(source):
    subprocess.run(["g++", "-O3", "-march=native", "-I/usr/include/eigen3", source, "-o", baseline], check=True)

# sscape's side: the default model (arg 1), one body; batches of 256 bodies on 1 and 2 workers; loads.
names = {"pose": "BM_PoseOnly/1", "shape_pose": "BM_ShapeAndPose/1", "batch1": "BM_Batch/1/real_time",
         "batch2": "BM_Batch/2/real_time", "load_builtin": "BM_LoadDefaultModel", "load_file": "BM_LoadDefaultFile"}
pattern = "^(BM_PoseOnly/1|BM_ShapeAndPose/1|BM_Batch/[12]/real_time|BM_LoadDefaultModel|BM_LoadDefaultFile)$"
results = {key: [] for key in ["y_pose", "y_shape_pose", *names]}
for r in range(args.rounds):
    out = subprocess.run([baseline], capture_output=True, text=True, check=True).stdout
    m = re.search(r"pose-only ([\d.]+) us\s+shape\+pose ([\d.]+) us", out)
    results["y_pose"].append(float(m.group(1)))
    results["y_shape_pose"].append(float(m.group(2)))
    out = subprocess.run([bench, f"--benchmark_filter={pattern}", f"--benchmark_min_time={args.min_time}", "--benchmark_format=json"],
                         capture_output=True, text=True, check=True).stdout
    by_name = {b["name"]: b for b in json.loads(out)["benchmarks"]}
    scale = {"ns": 1e-3, "us": 1.0, "ms": 1e3}
    for key, name in names.items():
        b = by_name[name]
        results[key].append(b["items_per_second"] if key.startswith("batch") else b["real_time"] * scale[b["time_unit"]])
    print(f"round {r + 1}: yardstick pose {results['y_pose'][-1]:.1f} us, shape+pose {results['y_shape_pose'][-1]:.1f} us; "
          f"sscape pose {results['pose'][-1]:.1f} us, shape+pose {results['shape_pose'][-1]:.1f} us, "
          f"batch {results['batch1'][-1]:.0f} / {results['batch2'][-1]:.0f} bodies/s, "
          f"load built-in {results['load_builtin'][-1] / 1e3:.1f} ms, file {results['load_file'][-1] / 1e3:.1f} ms; "
          f"ratios {results['pose'][-1] / results['y_pose'][-1]:.2f}, {results['shape_pose'][-1] / results['y_shape_pose'][-1]:.2f}", flush=True)

med = {k: statistics.median(v) for k, v in results.items()}
# Each ratio is the median of the rounds' own ratios: the two sides of a round ran next to each
# other, so a round that the machine ran slowly as a whole still gives a fair ratio.
def ratio(num, den):
    return statistics.median(a / b for a, b in zip(results[num], results[den]))


rows = [
    ("pose only (default model)", f"{med['y_pose']:.1f} us", f"{med['pose']:.1f} us", ratio("pose", "y_pose"), "<= 0.30"),
    ("shape (50) + pose", f"{med['y_shape_pose']:.1f} us", f"{med['shape_pose']:.1f} us", ratio("shape_pose", "y_shape_pose"), "<= 0.50"),
]
print(f"\n{'medians of ' + str(args.rounds) + ' rounds':<28} {'yardstick':>11} {'sscape':>11} {'ratio':>7}  target (ratio: median of the rounds' ratios)")
for name, y, s, r, target in rows:
    print(f"{name:<28} {y:>11} {s:>11} {r:>7.2f}  {target}")
print(f"{'batch of 256, 1 / 2 workers':<28} {med['batch1']:>9.0f}/s {med['batch2']:>9.0f}/s {ratio('batch2', 'batch1'):>7.2f}  >= 1.90 (2 workers / 1)")
print(f"{'load: built-in / its file':<28} {med['load_builtin'] / 1e3:>8.1f} ms {med['load_file'] / 1e3:>8.1f} ms "
      f"{ratio('load_builtin', 'load_file'):>7.2f}  <= 1.00 (built-in / file), <= 10 ms")
