"""fit_collection and measure_collection: the model fitted to every scan of a collection (as `sscape
fit` fits one) and each fitted body measured (as `sscape measure` measures a shape), one Dask task
per scan."""
from __future__ import annotations

import csv
import ctypes
import hashlib
import json
import os
from typing import Dict, Optional

from .. import library_version
from .._native import lib
from ..body import measurement_names
from ..errors import check
from . import _worker
from ._cluster import check_cluster_settings, client_for, manifest_path, run_into_manifest, run_tasks
from .scans import as_scans

_SI = {0: "m", 1: "m2", 2: "m3", 3: "kg"}


def _digest(*paths: Optional[str]) -> str:
    """What a fit was made from: the bytes of its files (a changed scan is fitted again)."""
    h = hashlib.sha256()
    for p in paths:
        h.update(b"\0" if p is None else open(p, "rb").read())
    return h.hexdigest()[:32]


def _kept_fits(out_dir: str, jobs):
    """The jobs still to run, and the fits kept: made before from the same files and settings (the
    manifest says so) whose files are still there."""
    try:
        with open(manifest_path(out_dir)) as f:
            old = json.load(f).get("scans", {})
    except (OSError, ValueError):
        old = {}
    todo, kept = [], {}
    for job in jobs:
        before = old.get(job["name"], {})
        if job["key"] is not None and before.get("status") in ("fitted", "reused") and before.get("key") == job["key"] and \
                os.path.exists(job["body"]) and os.path.exists(job["params"]):
            kept[job["name"]] = dict(before, status="reused", error=None)
        else:
            todo.append(job)
    return todo, kept


def fit_collection(scans, model: Optional[str] = None, out_dir: str = "fits", client=None, *, units: Optional[str] = None,
                   hands: bool = False, components: int = 0, iterations: int = 0, body_format: str = "obj",
                   scheduler: Optional[str] = None, workers: Optional[int] = None, threads_per_task: int = 1,
                   progress: bool = True, task_timeout: Optional[float] = None) -> Dict[str, dict]:
    """Fits the model (shape and pose) to every scan: out_dir/NAME.obj (or .ply, .glb: body_format),
    the fitted body, and NAME.json, its parameters (shape, per-joint rotations, translation, the
    report), as `sscape fit --points SCAN [--landmarks NAME.lnd] -o NAME.obj --params NAME.json`
    writes them; a fit that does not explain its scan (or ends in an impossible pose) fails with its
    reason and writes nothing. Scans, model, units and the cluster as register_collection's; hands:
    use hand landmarks; components: shape components fitted (0: all); iterations: the solver's limit
    (0: its default); task_timeout: seconds after which a fit is stopped and recorded as failed
    (None: no limit). out_dir/pipeline/manifest.json: each scan's status ("fitted" or "failed"), error and
    report. Running again keeps the fits made from the same scan and landmark files, model and
    settings (status "reused")."""
    if body_format not in ("obj", "ply", "glb"):
        raise ValueError(f"body_format must be obj, ply or glb, not {body_format!r}")
    check_cluster_settings(workers, threads_per_task, task_timeout)
    scan_list = as_scans(scans)
    os.makedirs(out_dir, exist_ok=True)
    model_path = os.path.abspath(model) if model else None
    settings = json.dumps([units, hands, components, iterations, body_format, library_version(),
                           _digest(model_path) if model_path else "built-in"])
    jobs = []
    for s in scan_list:
        try:
            key = _digest(s.path, s.landmarks) + settings
        except OSError:
            key = None  # unreadable: the task reports why
        jobs.append({"name": s.name, "scan": os.path.abspath(s.path), "landmarks": s.landmarks and os.path.abspath(s.landmarks),
                     "model": model_path, "units": units, "hands": hands, "shape_count": components, "max_iterations": iterations,
                     "threads": threads_per_task, "key": key, "timeout": task_timeout,
                     "body": os.path.abspath(os.path.join(out_dir, f"{s.name}.{body_format}")),
                     "params": os.path.abspath(os.path.join(out_dir, f"{s.name}.json"))})
    todo, kept = _kept_fits(out_dir, jobs)
    header = {"command": "fit", "model": model_path or "built-in", "units": units}
    with client_for(client, scheduler, workers) as c:
        return run_into_manifest(c, _worker.fit_job, todo, out_dir, header, "fit", progress, kept)


def measure_collection(fits_dir: str, model: Optional[str] = None, out_csv: Optional[str] = None, client=None, *,
                       scheduler: Optional[str] = None, workers: Optional[int] = None, progress: bool = True) -> Dict[str, dict]:
    """Measures the body of every fit in fits_dir (the NAME.json parameters fit_collection or `sscape
    fit --params` wrote) with the model they were fitted with, as
    `sscape measure --shape ...` does; writes out_csv (default fits_dir/measurements.csv): a row per
    scan, `scan,NAME_UNIT,...` in SI units, failed ones left out (they are in the returned dict with
    their error). Returns each scan's result by name."""
    names = sorted(f[:-5] for f in os.listdir(fits_dir) if f.endswith(".json") and not f.startswith("."))
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
    # A scan's name is its file's, which need not be UTF-8: written as the same bytes.
    with open(tmp, "w", newline="", encoding="utf-8", errors="surrogateescape") as f:
        w = csv.writer(f)
        w.writerow(["scan"] + [f"{n}_{u}" for n, u in zip(columns, units)])
        for name in names:
            r = results.get(name)
            if r and r["status"] == "measured":
                w.writerow([name] + [repr(r["measurements"][n]) for n in columns])
    os.replace(tmp, out_csv)
    return dict(sorted(results.items()))
