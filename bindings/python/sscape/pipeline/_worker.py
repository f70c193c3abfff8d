"""What runs on a Dask worker: one scan file registered per task, with the model loaded once per
worker process and a registration kept per model and thread (a registration is one thread at a
time). Tasks return plain dicts, never raise for a scan's own failure: one bad scan fails alone."""
from __future__ import annotations

import os
import threading
import time
from typing import Dict, Optional, Tuple

from ..errors import SscapeError
from ..model import Context, Model
from ..registration import Registration

# Per process: (model path or "", file size, mtime, context threads) -> Model, the few used last (a
# bootstrapping moves on to each round's model); per thread: a registration of the model used last.
_KEEP_MODELS = 2
_models: Dict[Tuple, Model] = {}
_models_lock = threading.Lock()
_local = threading.local()


def _model_key(path: Optional[str], threads: int) -> Tuple:
    if not path:
        return ("", 0, 0, threads)
    st = os.stat(path)  # a model file written again (the next round's) is loaded again
    return (os.path.abspath(path), st.st_size, st.st_mtime_ns, threads)


def model_for(path: Optional[str], threads: int = 1) -> Model:
    """The model at path (None: the built-in one), loaded once per worker process."""
    key = _model_key(path, threads)
    with _models_lock:
        model = _models.pop(key, None)
        if model is None:
            context = Context(worker_count=threads)
            model = Model.from_file(path, context=context) if path else Model(context=context)
        _models[key] = model  # most recently used last
        while len(_models) > _KEEP_MODELS:
            _models.pop(next(iter(_models)))
        return model


def registration_for(path: Optional[str], threads: int = 1) -> Registration:
    """This thread's registration of the model at path (default options, as the CLI's)."""
    key = _model_key(path, threads)
    last = getattr(_local, "registration", None)
    if last is None or last[0] != key:
        _local.registration = (key, Registration(model_for(path, threads)))
    else:
        model_for(path, threads)  # keeps the model recently used
    return _local.registration[1]


def register_job(job: dict) -> dict:
    """Registers job["scan"] into job["mesh"] (report beside it) with the model at job["model"]:
    a dict with the scan's name, status "registered", "reused" or "failed", error, seconds, quality."""
    t0 = time.perf_counter()
    out = {"name": job["name"], "scan": job["scan"], "mesh": job["mesh"], "status": "failed", "error": None, "pid": os.getpid()}
    try:
        reg = registration_for(job.get("model"), job.get("threads", 1))
        report = reg.run_file(job["scan"], job["mesh"], landmarks=job.get("landmarks"), units=job.get("units"), up=job.get("up"),
                              report=True, reuse=job.get("reuse", True), picture=job.get("picture"))
        out["status"] = "reused" if report["reused"] else "registered"
        out["registration_seconds"] = report["seconds"]
        out["quality"] = report["quality"]
    except SscapeError as e:
        out["error"] = str(e)
    except Exception as e:  # a bug or a full disk: reported with the scan, the others go on
        out["error"] = f"{type(e).__name__}: {e}"
    out["seconds"] = time.perf_counter() - t0
    return out


def no_op(x):
    """A task that does nothing: the scheduler's own cost per task (the benchmark)."""
    return x
