"""What runs on a Dask worker: one scan file registered per task, with the model loaded once per
worker process and a registration kept per model and thread (a registration is one thread at a
time). Tasks return plain dicts, never raise for a scan's own failure: one bad scan fails alone."""
from __future__ import annotations

import os
import threading
import time
from typing import Dict, Optional, Tuple

import json

import numpy as np

from ..body import Body
from ..errors import SscapeError
from ..fitter import Fitter
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


def registration_for(path: Optional[str], threads: int = 1, fit_segments: bool = True) -> Registration:
    """This thread's registration of the model at path (default options, as the CLI's, but
    fit_segments)."""
    key = _model_key(path, threads) + (bool(fit_segments),)
    last = getattr(_local, "registration", None)
    if last is None or last[0] != key:
        _local.registration = (key, Registration(model_for(path, threads), fit_segments=bool(fit_segments)))
    else:
        model_for(path, threads)  # keeps the model recently used
    return _local.registration[1]


def _failing_alone(out: dict, work) -> dict:
    """out updated with what work() returns; a failure of this scan (the library's, a bug's, a full
    disk's) goes into out["error"] instead, so the others go on. out["seconds"]: the task's time."""
    t0 = time.perf_counter()
    try:
        out.update(work())
    except SscapeError as e:
        out["error"] = str(e)
    except Exception as e:
        out["error"] = f"{type(e).__name__}: {e}"
    out["seconds"] = time.perf_counter() - t0
    return out


def _deadline(job: dict):
    """A progress callback that cancels the library's call once job["timeout"] seconds have passed
    (None: never). The library calls it between its stages and solver iterations, so a scan that
    takes too long stops there, writes nothing and fails alone instead of holding the run."""
    limit = job.get("timeout")
    if limit is None:
        return None
    end = time.monotonic() + float(limit)
    return lambda *progress: time.monotonic() > end


def _timed_out(job: dict, error: SscapeError) -> Exception:
    """The cancellation _deadline caused, said as a timeout."""
    if error.status_name == "SSC_ERROR_CANCELLED" and job.get("timeout") is not None:
        return TimeoutError(f"stopped after the task timeout of {job['timeout']:g} s (task_timeout); nothing written")
    return error


def register_job(job: dict) -> dict:
    """Registers job["scan"] into job["mesh"] (report beside it) with the model at job["model"]:
    a dict with the scan's name, status "registered", "reused" or "failed", error, seconds, quality."""
    def work():
        reg = registration_for(job.get("model"), job.get("threads", 1), job.get("fit_segments", True))
        try:
            report = reg.run_file(job["scan"], job["mesh"], landmarks=job.get("landmarks"), units=job.get("units"), up=job.get("up"),
                                  report=True, reuse=job.get("reuse", True), picture=job.get("picture"), progress=_deadline(job))
        except SscapeError as e:
            raise _timed_out(job, e) from None
        return {"status": "reused" if report["reused"] else "registered", "registration_seconds": report["seconds"],
                "quality": report["quality"]}

    return _failing_alone({"name": job["name"], "scan": job["scan"], "mesh": job["mesh"], "status": "failed", "error": None,
                           "pid": os.getpid()}, work)


# SSC_FIT_UNEXPLAINED_LIMIT: above it a fit has not found the person (sscape fit refuses it too).
_FIT_UNEXPLAINED_LIMIT = np.float32(0.1)


def fit_job(job: dict) -> dict:
    """Fits the model at job["model"] to job["scan"] (and job["landmarks"]) as `sscape fit --points
    SCAN --landmarks LND -o BODY --params PARAMS` does: the body file and the parameters, or status
    "failed" with the reason (nothing written). job["key"] (what the fit is made from) is kept."""
    def work():
        model = model_for(job.get("model"), job.get("threads", 1))
        options = {k: job[k] for k in ("shape_count", "max_iterations") if job.get(k)}
        with Fitter(model, **options) as fitter:
            if job.get("landmarks"):
                fitter.add_landmarks_file(job["landmarks"], units=job.get("units"), hands=job.get("hands", False), frame=0)
            fitter.add_points_file(job["scan"], units=job.get("units"), frame=0)
            try:
                report = fitter.solve(progress=_deadline(job))
            except SscapeError as e:
                raise _timed_out(job, e) from None
            if np.float32(report["unexplained_fraction"]) > _FIT_UNEXPLAINED_LIMIT:
                raise ValueError(f"{100 * report['unexplained_fraction']:.0f} % of the scan lies farther than 5 cm from the fitted body: "
                                 "a limb or the whole body is in the wrong place, or the scan holds clutter")
            if report["implausible"]:
                raise ValueError("the best fit has joints far past their anatomical limits: a limb or the body is in the wrong place")
            rotations, translation, _ = fitter.pose(0)
            with Body(model) as body:
                body.shape = fitter.shape
                body.set_pose(rotations, translation)
                body.write(job["body"])
            fitter.write_params(job["params"])
        return {"status": "fitted", "report": report}

    return _failing_alone({"name": job["name"], "scan": job["scan"], "body": job["body"], "params": job["params"], "key": job.get("key"),
                           "status": "failed", "error": None, "pid": os.getpid()}, work)


def measure_job(job: dict) -> dict:
    """Measures the body of the shape in job["params"] (a fit's parameters) with the model at
    job["model"], as `sscape measure --shape ...` does: every measurement by name, SI units."""
    def work():
        with open(job["params"]) as f:
            params = json.load(f)
        shape = np.asarray(params["shape"], np.float32)
        model = model_for(job.get("model"), job.get("threads", 1))
        fitted_with = params.get("model_digest")
        if fitted_with and fitted_with != model.digest:  # another model's coefficients make another body
            raise ValueError(f"{job['params']} was fitted with the model of digest {fitted_with}, not this one ({model.digest}): "
                             "measure with the model the fits were made with")
        with Body(model) as body:
            body.shape = shape
            return {"status": "measured", "measurements": body.measure()}

    return _failing_alone({"name": job["name"], "params": job["params"], "status": "failed", "error": None}, work)


def no_op(x):
    """A task that does nothing: the scheduler's own cost per task (the benchmark)."""
    return x
