"""bootstrap: rounds of registration, inspection and learning over a folder of scans, each round's
registrations spread over a Dask cluster (one task per scan, with the previous round's model) and
the rest (inspection, decisions, contact sheets, learning) done here by the library as
`sscape bootstrap` does it, so both give the same files."""
from __future__ import annotations

import ctypes
import os
import sys
from typing import Callable, Dict, List, Optional

from .._handle import Handle, progress_callback
from .._native import LINE_FN, BootstrapDef, ScanFileJob, lib, need_offline
from ..errors import check
from . import _worker
from ._cluster import check_cluster_settings, client_for, run_into_manifest, whole_number

_POSTURES = {"skeleton": 0, "none": 1, "laplacian": 2}


class Bootstrapping(Handle):
    """The library's bootstrapping of a folder of scans (ssc_bootstrap): its scans, each round's
    registration jobs, and the rounds run here. Settings as `sscape bootstrap`'s options."""

    _what = "bootstrapping"

    def __init__(self, scans_dir: str, out_dir: str, init_model: Optional[str] = None, *, components: int = 20,
                 posture: str = "skeleton", template_only: bool = False, scale: bool = False, segment_components: int = 0,
                 segment_band_mm: float = 80.0, units: Optional[str] = None, up: Optional[str] = None,
                 decisions: Optional[str] = None, attributes: Optional[str] = None, name: Optional[str] = None,
                 license: Optional[str] = None, threads: int = 0, contact_sheet_entries: int = 12, fit_segments: bool = True,
                 posture_model: Optional[str] = None):
        need_offline("sscape.pipeline.bootstrap")
        if posture not in _POSTURES:
            raise ValueError(f"posture must be one of {', '.join(_POSTURES)}, not {posture!r}")
        whole_number("components", components, 1, 1000)
        whole_number("segment_components", segment_components, 0, 1000)
        whole_number("threads", threads, 0, 256)
        whole_number("contact_sheet_entries", contact_sheet_entries, 0, 100)
        d = BootstrapDef()
        lib.ssc_bootstrap_def_init(ctypes.byref(d), ctypes.sizeof(BootstrapDef))
        text = lambda v: None if v is None else os.fsencode(v)
        self._strings = [text(v) for v in (scans_dir, out_dir, init_model, units, up, decisions, attributes, name, license, posture_model)]
        (d.scans_dir, d.out_dir, d.init_model_path, d.units, d.up, d.decisions_path, d.attributes_path, d.name,
         d.license, d.posture_model_path) = self._strings
        d.components, d.posture, d.template_only, d.scale = int(components), _POSTURES[posture], int(template_only), int(scale)
        d.segment_components, d.segment_band = int(segment_components), float(segment_band_mm) * 1e-3
        d.threads, d.contact_sheet_entries = int(threads), int(contact_sheet_entries)
        d.fit_segments = int(fit_segments)
        self.fit_segments = bool(fit_segments)
        handle = ctypes.c_void_p()
        check(lib.ssc_bootstrap_create(None, ctypes.byref(d), ctypes.byref(handle)))
        self._own(handle, lib.ssc_bootstrap_destroy)
        self.out_dir = out_dir

    @property
    def scan_names(self) -> List[str]:
        """The collection's scans, by name (the file name without its extension), in the run's order."""
        names = []
        for i in range(lib.ssc_bootstrap_scan_count(self.handle)):
            name = ctypes.c_char_p()
            check(lib.ssc_bootstrap_get_scan(self.handle, i, ctypes.byref(name), None, None))
            names.append(os.fsdecode(name.value))  # the file's name, any bytes
        return names

    def prepare(self) -> None:
        """Writes round 0's starting model."""
        check(lib.ssc_bootstrap_prepare(self.handle))

    def jobs(self, round: int) -> List[dict]:
        """Round `round`'s registrations as tasks for _worker.register_job."""
        out = []
        for i, name in enumerate(self.scan_names):
            job, model = ScanFileJob(), ctypes.c_char_p()
            lib.ssc_scan_file_job_init(ctypes.byref(job), ctypes.sizeof(ScanFileJob))
            check(lib.ssc_bootstrap_get_job(self.handle, round, i, ctypes.byref(job), ctypes.byref(model)))
            text = lambda v: os.path.abspath(os.fsdecode(v)) if v else None
            out.append({"name": name, "scan": text(job.scan_path), "landmarks": text(job.landmarks_path),
                        "units": job.units.decode() if job.units else None, "up": job.up.decode() if job.up else None,
                        "mesh": text(job.mesh_path), "model": text(model.value), "reuse": bool(job.reuse), "threads": 1,
                        "fit_segments": self.fit_segments})
        return out

    def run(self, rounds: int, progress: Optional[Callable[[str], None]] = None) -> None:
        """Runs rounds 1..rounds here, reusing every registration already on disk."""
        callback, errors = progress_callback(LINE_FN, (lambda line: progress(line) and False) if progress else None,
                                             lambda line: (line.decode("utf-8", "backslashreplace"),))
        status = lib.ssc_bootstrap_run(self.handle, rounds, callback, None)
        if errors:
            raise errors[0]
        check(status)


def bootstrap(scans_dir: str, init_model: Optional[str] = None, rounds: int = 3, out_dir: str = "bootstrap", client=None, *,
              scheduler: Optional[str] = None, workers: Optional[int] = None, threads_per_task: int = 1, progress: bool = True,
              log: Optional[Callable[[str], None]] = None, task_timeout: Optional[float] = None, **settings) -> List[Dict[str, str]]:
    """Bootstraps a model from the scans in scans_dir, as `sscape bootstrap` does: for each round,
    every scan registered with the previous round's model (one Dask task per scan; reused when
    already done), then inspected, decided and learned from here; out_dir holds round_N/ per round
    (with pipeline/manifest.json: each registration task's status and error), model.sscape and rounds.csv.

    init_model: the starting .sscape (None: the built-in model). settings: components, posture
    ("skeleton", "none" or "laplacian"), posture_model (skeleton: the model whose fits to the scans unpose
    the registrations, made here; None: the built-in model where it shares the starting model's rig; "":
    each round's own fits), template_only, scale, segment_components, segment_band_mm, fit_segments,
    units, up, decisions, attributes, name, license, threads (of the learning here), contact_sheet_entries.
    Cluster and task_timeout as register_collection's (a scan stopped on the cluster is registered
    once more, without a limit, by the round's learning here). Returns rounds.csv's rows."""
    say = log or (lambda line: print(line, file=sys.stderr))
    whole_number("rounds", rounds, 1, 100)  # before anything is written: 0 once left round_0 and no rounds.csv
    check_cluster_settings(workers, threads_per_task, task_timeout)
    b = Bootstrapping(scans_dir, out_dir, init_model, **settings)
    b.prepare()
    with client_for(client, scheduler, workers) as c:
        for r in range(1, rounds + 1):
            jobs = b.jobs(r)
            for job in jobs:
                job["threads"] = threads_per_task
                job["timeout"] = task_timeout
            header = {"command": "bootstrap", "round": r, "model": jobs[0]["model"]}
            folder = os.path.join(out_dir, f"round_{r}")
            os.makedirs(folder, exist_ok=True)
            scans = run_into_manifest(c, _worker.register_job, jobs, folder, header, f"round {r}", progress)
            failed = [n for n, s in scans.items() if s["status"] == "failed"]
            say(f"round {r}: {len(jobs) - len(failed)} of {len(jobs)} scans registered on the cluster"
                + (f"; failed: {', '.join(failed)}" if failed else ""))
            # Inspection and learning here; the registrations are all on disk, so nothing registers
            # again but the failed scans (which fail again, with their reason in decisions.csv).
            b.run(r, say)
    import csv
    with open(os.path.join(out_dir, "rounds.csv"), newline="") as f:
        return list(csv.DictReader(f))
