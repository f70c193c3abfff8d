"""fit_collection and measure_collection: the model fitted to every scan of a collection (as `sscape
fit` fits one) and each fitted body measured (as `sscape measure` measures a shape), one Dask task
per scan."""
from __future__ import annotations

import csv
import ctypes
import os
import time
from typing import Dict, Optional

from .._native import lib
from ..body import measurement_names
from ..errors import check
from . import _worker
from ._cluster import client_for, remove_stale_temporaries, run_tasks, write_json_atomically
from .scans import as_scans

_SI = {0: "m", 1: "m2", 2: "m3", 3: "kg"}


def _collect(out_dir: str, command: str, model: Optional[str], jobs, function, client, scheduler, workers, progress, extra) -> Dict[str, dict]:
    remove_stale_temporaries(out_dir)
    manifest = {"command": command, "model": model or "built-in", **extra, "started": time.time(), "finished": None, "scans": {}}
    path = os.path.join(out_dir, "manifest.json")

    def record(result: dict) -> None:
        manifest["scans"][result["name"]] = result
        write_json_atomically(path, manifest)

    with client_for(client, scheduler, workers) as c:
        run_tasks(c, function, jobs, record, command, progress)
    manifest["finished"] = time.time()
    manifest["scans"] = dict(sorted(manifest["scans"].items()))
    write_json_atomically(path, manifest)
    return manifest["scans"]


def fit_collection(scans, model: Optional[str] = None, out_dir: str = "fits", client=None, *, units: Optional[str] = None,
                   hands: bool = False, components: int = 0, iterations: int = 0, body_format: str = "obj",
                   scheduler: Optional[str] = None, workers: Optional[int] = None, threads_per_task: int = 1,
                   progress: bool = True) -> Dict[str, dict]:
    """Fits the model (shape and pose) to every scan: out_dir/NAME.obj (or .ply, .glb: body_format),
    the fitted body, and NAME.json, its parameters (shape, per-joint rotations, translation, the
    report), as `sscape fit --points SCAN [--landmarks NAME.lnd] -o NAME.obj --params NAME.json`
    writes them; a fit that does not explain its scan (or ends in an impossible pose) fails with its
    reason and writes nothing. Scans, model, units and the cluster as register_collection's; hands:
    use hand landmarks; components: shape components fitted (0: all); iterations: the solver's limit
    (0: its default). out_dir/manifest.json: each scan's status ("fitted" or "failed"), error and
    report. Every run fits every scan again (a fit takes about a second)."""
    if body_format not in ("obj", "ply", "glb"):
        raise ValueError(f"body_format must be obj, ply or glb, not {body_format!r}")
    scan_list = as_scans(scans)
    os.makedirs(out_dir, exist_ok=True)
    model_path = os.path.abspath(model) if model else None
    jobs = [{"name": s.name, "scan": os.path.abspath(s.path), "landmarks": s.landmarks and os.path.abspath(s.landmarks), "model": model_path,
             "units": units, "hands": hands, "shape_count": components, "max_iterations": iterations, "threads": threads_per_task,
             "body": os.path.abspath(os.path.join(out_dir, f"{s.name}.{body_format}")),
             "params": os.path.abspath(os.path.join(out_dir, f"{s.name}.json"))} for s in scan_list]
    return _collect(out_dir, "fit", model_path, jobs, _worker.fit_job, client, scheduler, workers, progress, {"units": units})


def measure_collection(fits_dir: str, model: Optional[str] = None, out_csv: Optional[str] = None, client=None, *,
                       scheduler: Optional[str] = None, workers: Optional[int] = None, progress: bool = True) -> Dict[str, dict]:
    """Measures the body of every fit in fits_dir (the NAME.json parameters fit_collection or `sscape
    fit --params` wrote; the manifest.json is not one) with the model they were fitted with, as
    `sscape measure --shape ...` does; writes out_csv (default fits_dir/measurements.csv): a row per
    scan, `scan,NAME_UNIT,...` in SI units, failed ones left out (they are in the returned dict with
    their error). Returns each scan's result by name."""
    names = sorted(f[:-5] for f in os.listdir(fits_dir) if f.endswith(".json") and f != "manifest.json" and not f.startswith("."))
    model_path = os.path.abspath(model) if model else None
    jobs = [{"name": n, "params": os.path.abspath(os.path.join(fits_dir, n + ".json")), "model": model_path} for n in names]
    results: Dict[str, dict] = {}
    with client_for(client, scheduler, workers) as c:
        run_tasks(c, _worker.measure_job, jobs, lambda r: results.__setitem__(r["name"], r), "measure", progress)
    columns = measurement_names()
    units = []
    for m in range(len(columns)):
        unit = ctypes.c_int32()
        check(lib.ssc_measurement_get_info(m, None, ctypes.byref(unit), None))
        units.append(_SI[unit.value])
    out_csv = out_csv or os.path.join(fits_dir, "measurements.csv")
    tmp = out_csv + ".partial"
    with open(tmp, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["scan"] + [f"{n}_{u}" for n, u in zip(columns, units)])
        for name in names:
            r = results.get(name)
            if r and r["status"] == "measured":
                w.writerow([name] + [repr(r["measurements"][n]) for n in columns])
    os.replace(tmp, out_csv)
    return dict(sorted(results.items()))
