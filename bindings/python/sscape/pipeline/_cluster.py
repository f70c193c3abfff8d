"""The Dask side shared by the pipeline's commands: a client (the caller's, one for a scheduler
address, or a LocalCluster on this machine), tasks mapped over scans with their results gathered
as they finish (a progress bar when tqdm is installed), and the manifest written as they come."""
from __future__ import annotations

import contextlib
import json
import numbers
import os
import sys
import tempfile
import time
from typing import Callable, Iterator, List, Optional


def whole_number(name: str, value, lo: int, hi: int) -> int:
    """value as an int in lo..hi, else ValueError naming the setting (ctypes would take -5 as
    4294967291, and a local cluster of -1 workers waits forever for one)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not lo <= value <= hi:
        raise ValueError(f"{name} must be a whole number in {lo}..{hi}, not {value!r}")
    return int(value)


def check_cluster_settings(workers: Optional[int], threads_per_task: int = 1, task_timeout: Optional[float] = None) -> None:
    """The cluster settings every collection function takes, checked before it writes anything."""
    if workers is not None:
        whole_number("workers", workers, 1, 4096)
    whole_number("threads_per_task", threads_per_task, 1, 256)
    if task_timeout is not None and (isinstance(task_timeout, bool) or not isinstance(task_timeout, numbers.Real)
                                     or not 0 < task_timeout <= 1e6):
        raise ValueError(f"task_timeout must be a number of seconds in (0, 1e6], not {task_timeout!r}")


@contextlib.contextmanager
def client_for(client=None, scheduler: Optional[str] = None, workers: Optional[int] = None) -> Iterator[object]:
    """The given client; else one connected to `scheduler` (tcp://host:8786); else a LocalCluster of
    `workers` processes (default: one per core) with one thread each, closed at the end."""
    if workers is not None:
        whole_number("workers", workers, 1, 4096)
    if client is not None:
        yield client
        return
    from distributed import Client, LocalCluster
    if scheduler:
        with Client(scheduler) as c:
            say_dashboard(c)
            yield c
        return
    n = workers or os.cpu_count() or 1
    # Dask serves its dashboard (tasks, workers, memory) only where bokeh is installed: offered then,
    # on a free port, and its address said.
    dashboard = ":0" if has_bokeh() else None
    with LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=dashboard) as cluster, Client(cluster) as c:
        say_dashboard(c)
        yield c


def has_bokeh() -> bool:
    """Whether bokeh, which Dask's dashboard needs, can be imported here."""
    try:
        import bokeh  # noqa: F401
    except ImportError:
        return False
    return True


def say_dashboard(client) -> None:
    """Prints the dashboard's address to stderr when the scheduler serves one: its web server runs
    either way, the dashboard's pages only where the scheduler's python has bokeh."""
    with contextlib.suppress(Exception):
        if "dashboard" in client.scheduler_info().get("services", {}) and client.run_on_scheduler(has_bokeh):
            print(f"sscape.pipeline: the Dask dashboard is at {client.dashboard_link}", file=sys.stderr)


def manifest_path(folder: str) -> str:
    """Where a run over folder records its tasks: folder/pipeline/manifest.json. The pipeline's own
    files live in a subfolder because every name a file of the folder could have is some scan's
    (a scan named manifest.ply once had its report replaced by the manifest); scans' outputs are
    files, so no scan's can be that folder."""
    return os.path.join(folder, "pipeline", "manifest.json")


def remove_stale_temporaries(folder: str) -> None:
    """Manifest temporaries a killed run left (it stopped between writing one and renaming it)."""
    with contextlib.suppress(OSError):
        for name in os.listdir(folder):
            if name.startswith(".manifest."):
                with contextlib.suppress(OSError):
                    os.unlink(os.path.join(folder, name))


def write_json_atomically(path: str, value) -> None:
    """The manifest is replaced whole: a reader (or a killed run) never sees half of it."""
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix=".manifest.", dir=folder)
    try:
        with os.fdopen(fd, "w") as f:
            json.dump(value, f, indent=1)
            f.write("\n")
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def run_tasks(client, function: Callable, jobs: List[dict], on_result: Callable[[dict], None], label: str, progress: bool) -> None:
    """Runs function(job) for every job on the cluster; on_result(result) as each finishes. A task
    whose worker died counts as a failed scan."""
    from distributed import as_completed
    futures = client.map(function, jobs, pure=False)
    by_future = dict(zip(futures, jobs))
    bar = None
    if progress:
        try:
            from tqdm import tqdm
            bar = tqdm(total=len(jobs), desc=label, unit="scan", file=sys.stderr)
        except ImportError:
            bar = None
    try:
        for future in as_completed(futures):
            job = by_future[future]
            try:
                result = future.result()
            except Exception as e:  # the worker died or the task could not run
                result = {k: job[k] for k in ("name", "scan", "mesh", "body", "params") if k in job}
                result.update(status="failed", error=f"{type(e).__name__}: {e}")
            on_result(result)
            if bar is not None:
                bar.update(1)
    finally:
        if bar is not None:
            bar.close()
        client.cancel(futures)


def run_into_manifest(client, function, jobs: List[dict], folder: str, header: dict, label: str, progress: bool,
                      kept: Optional[dict] = None) -> dict:
    """Runs function(job) for every job, each result recorded by scan name in manifest_path(folder)
    as it comes (header: what the run is; kept: results carried over without running). Returns the
    manifest's scans, sorted by name."""
    path = manifest_path(folder)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    remove_stale_temporaries(os.path.dirname(path))
    manifest = {**header, "started": time.time(), "finished": None, "scans": dict(kept or {})}

    def record(result: dict) -> None:
        manifest["scans"][result["name"]] = result
        write_json_atomically(path, manifest)

    run_tasks(client, function, jobs, record, label, progress)
    manifest["finished"] = time.time()
    manifest["scans"] = dict(sorted(manifest["scans"].items()))
    write_json_atomically(path, manifest)
    return manifest["scans"]
