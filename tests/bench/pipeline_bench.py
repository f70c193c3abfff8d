#!/usr/bin/python3
"""The Dask pipeline's throughput and overhead: scans per minute registered by the serial command
line (`sscape register` per scan), by sscape.pipeline.register_collection on a LocalCluster of 1
and of 2 worker processes, and the cost per task: the pipeline against the bare command line at
the same thread count, and an empty task's round trip through the scheduler.

usage: SSCAPE_LIBRARY=build/sdk/libsscape_offline.so PYTHONPATH=bindings/python \\
       tests/bench/pipeline_bench.py --cli build/bin/sscape [--scans 16] [--points 30000] [--work DIR]
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cli", required=True, help="the sscape command line")
    parser.add_argument("--scans", type=int, default=16)
    parser.add_argument("--points", type=int, default=30000)
    parser.add_argument("--work", help="working folder (default: a temporary one, removed)")
    a = parser.parse_args()
    import distributed
    from sscape import pipeline
    from sscape.pipeline import _worker

    work = a.work or tempfile.mkdtemp(prefix="sscape-pipeline-bench-")
    scans = os.path.join(work, "scans")
    shutil.rmtree(scans, ignore_errors=True)
    os.makedirs(scans)
    for seed in range(1, a.scans + 1):
        subprocess.run([a.cli, "simulate", "-o", os.path.join(scans, f"p{seed:03d}"), "--seed", str(seed), "--points", str(a.points),
                        "--pose-amount", "0.2"], check=True, capture_output=True)
        os.unlink(os.path.join(scans, f"p{seed:03d}_truth.obj"))
    names = sorted(f[:-9] for f in os.listdir(scans) if f.endswith("_scan.ply"))
    cores = os.cpu_count()
    print(f"{a.scans} simulated scans of {a.points} points with landmarks; {cores} cores")

    serial = os.path.join(work, "serial")
    os.makedirs(serial, exist_ok=True)
    t0 = time.perf_counter()
    for n in names:
        subprocess.run([a.cli, "register", os.path.join(scans, f"{n}_scan.ply"), "--landmarks", os.path.join(scans, f"{n}.lnd"),
                        "-o", os.path.join(serial, f"{n}_scan.ply"), "--report", os.path.join(serial, f"{n}_scan.json")],
                       check=True, capture_output=True)
    cli_seconds = time.perf_counter() - t0
    rows = [("sscape register, one process per scan", cores, cli_seconds, None)]

    def pipeline_run(workers, threads):
        out = os.path.join(work, f"pipeline_{workers}x{threads}")
        shutil.rmtree(out, ignore_errors=True)
        t_start = time.perf_counter()
        with distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
                distributed.Client(cluster) as client:
            client.run(lambda: None)  # the workers are up
            started = time.perf_counter() - t_start
            t = time.perf_counter()
            result = pipeline.register_collection(scans, out_dir=out, client=client, threads_per_task=threads, progress=False)
            seconds = time.perf_counter() - t
            assert all(r["status"] == "registered" for r in result.values()), result
            t = time.perf_counter()  # an empty task's round trip through the scheduler
            client.gather(client.map(_worker.no_op, range(500), pure=False))
            empty = time.perf_counter() - t
        return seconds, started, empty

    for workers, threads in ((1, cores), (1, 1), (2, 1)):
        seconds, started, empty = pipeline_run(workers, threads)
        rows.append((f"pipeline, {workers} worker process{'es' if workers > 1 else ''} x {threads} library thread{'s' if threads > 1 else ''}",
                     threads, seconds, started))
        rows.append((f"  (500 empty tasks, {workers} worker{'s' if workers > 1 else ''})", 0, empty, None))

    print(f"{'run':52s} {'seconds':>8s} {'s/scan':>7s} {'scans/min':>9s} {'cluster start s':>15s}")
    for label, _threads, seconds, started in rows:
        if label.startswith("  (500"):
            print(f"{label:52s} {seconds:8.2f}   per task {1e3 * seconds / 500:.1f} ms")
            continue
        print(f"{label:52s} {seconds:8.1f} {seconds / a.scans:7.2f} {60 * a.scans / seconds:9.1f} {'' if started is None else f'{started:15.1f}'}")
    same_threads = next(s for label, t, s, _ in rows if label.startswith("pipeline, 1 worker process x") and t == cores)
    print(f"overhead per task against the bare command line at {cores} threads: {1e3 * (same_threads - cli_seconds) / a.scans:+.0f} ms "
          "(the command line also loads the model for every scan)")
    if not a.work:
        shutil.rmtree(work)


if __name__ == "__main__":
    sys.exit(main())
