"""register_collection: every scan of a collection registered to the model's template, one Dask
task per scan, as `sscape register` registers each (the same library call, the same files)."""
from __future__ import annotations

import os
from typing import Dict, Optional

from . import _worker
from ._cluster import check_cluster_settings, client_for, run_into_manifest
from .scans import as_scans

def register_collection(scans, model: Optional[str] = None, out_dir: str = "registrations", client=None, *,
                        units: Optional[str] = None, up: Optional[str] = None, pictures: bool = False, scheduler: Optional[str] = None,
                        workers: Optional[int] = None, threads_per_task: int = 1, progress: bool = True,
                        fit_segments: bool = True, task_timeout: Optional[float] = None) -> Dict[str, dict]:
    """Registers every scan into out_dir: NAME.ply (the model's topology, the scan's frame and
    units), NAME.json (the report sscape learn reads) and, with pictures, NAME.png; then
    out_dir/pipeline/manifest.json with each scan's status ("registered", "reused" or "failed"), error and
    times.

    scans: a folder (every .ply and .obj; NAME.lnd beside a scan: its landmarks) or a list of scan
    paths or (scan, landmarks) pairs. model: a .sscape file (None: the built-in model). units: "m",
    "cm" or "mm" for scans and landmark files (None: metres and the .lnd's millimetres). up: the
    scans' up axis (None: "y"). fit_segments: the model's segment shape spaces join each model fit
    (as `sscape register`; False as its --no-segments). task_timeout: seconds after which a scan's
    registration is stopped and recorded as failed (None: no limit).

    Runs on `client` (any Dask cluster whose workers see the same files: a shared file system across
    machines), else on the scheduler at `scheduler`, else on a LocalCluster of `workers` processes.
    Each worker loads the model once. A failed scan is in the manifest with its error and does not
    stop the others; running again skips the scans already registered from the same model, scan,
    landmarks, units and up axis. Returns the manifest's scans by name."""
    check_cluster_settings(workers, threads_per_task, task_timeout)
    scan_list = as_scans(scans)
    os.makedirs(out_dir, exist_ok=True)
    model_path = os.path.abspath(model) if model else None
    if model_path and not os.path.isfile(model_path):
        raise FileNotFoundError(f"model {model} is not a file")
    jobs = []
    for s in scan_list:
        mesh = os.path.abspath(os.path.join(out_dir, s.name + ".ply"))
        jobs.append({"name": s.name, "scan": os.path.abspath(s.path), "landmarks": s.landmarks and os.path.abspath(s.landmarks),
                     "mesh": mesh, "model": model_path, "units": units, "up": up, "reuse": True, "threads": threads_per_task,
                     "picture": mesh[:-4] + ".png" if pictures else None, "fit_segments": bool(fit_segments),
                     "timeout": task_timeout})
    header = {"command": "register", "model": model_path or "built-in", "units": units, "up": up}
    with client_for(client, scheduler, workers) as c:
        return run_into_manifest(c, _worker.register_job, jobs, out_dir, header, "register", progress)
