"""Registration: the model's template brought onto a raw scan (model fit, then per-vertex affine
deformation), giving the scan in the template's topology."""
from __future__ import annotations

import ctypes
import os
from typing import Callable, Dict, Optional, Sequence

import numpy as np

from ._native import (STAGE_PROGRESS_FN, RegistrationDef, RegistrationQuality, RegistrationReport, ScanFileJob, c_float_p, c_uint32_p, lib,
                      need_offline)
from ._handle import Handle, progress_callback
from .errors import check
from .model import Model

_STARTS = {"model": 0, "rigid": 1, "rbf": 2}
_SCHEDULES = {"relaxed": 0, "constant": 1}
_KERNELS = {"thin_plate": 0, "multiquadric": 1, "gaussian": 2}
_NUMBERS = {"stiffness", "landmark_weight", "gamma", "max_iterations", "rbf_scale"}


def _quality(q: RegistrationQuality) -> Dict[str, float]:
    out = {"scan_mean": q.scan_mean, "scan_median": q.scan_median, "scan_p95": q.scan_p95}
    for mm, share in zip((2, 5, 10, 20), q.within):
        out[f"within_{mm}mm"] = share
    return out


class Registration(Handle):
    """Registers one scan at a time to the model's template. Options as ssc_registration_def:
    start ("model", "rigid", "rbf"), schedule ("relaxed", "constant"), stiffness, landmark_weight,
    gamma, max_iterations, rbf_kernel ("thin_plate", "multiquadric", "gaussian"), rbf_scale,
    fit_segments (True, the default: the model's segment shape spaces join the model fit; False: the
    whole body's components only). One thread at a time.

        reg = sscape.Registration(model)
        reg.set_scan(points, triangles=faces)        # metres; faces optional
        report = reg.run()
        registered = reg.vertices()                  # (V, 3) in the template's topology
    """

    _what = "registration"

    def __init__(self, model: Model, start: str = "model", schedule: str = "relaxed", rbf_kernel: str = "thin_plate",
                 fit_segments: bool = True, **numbers):
        unknown = set(numbers) - _NUMBERS
        if unknown:
            raise TypeError(f"unknown registration options: {', '.join(sorted(unknown))}")
        d = RegistrationDef()
        lib.ssc_registration_def_init(ctypes.byref(d), ctypes.sizeof(RegistrationDef))
        for value, table, what in ((start, _STARTS, "start"), (schedule, _SCHEDULES, "schedule"), (rbf_kernel, _KERNELS, "rbf_kernel")):
            if value not in table:
                raise ValueError(f"{what} must be one of {', '.join(table)}, not {value!r}")
        d.start, d.schedule, d.rbf_kernel = _STARTS[start], _SCHEDULES[schedule], _KERNELS[rbf_kernel]
        d.fit_segments = 1 if fit_segments else 0
        for key, value in numbers.items():
            setattr(d, key, int(value) if key == "max_iterations" else float(value))
        handle = ctypes.c_void_p()
        check(lib.ssc_registration_create(model.handle, ctypes.byref(d), ctypes.byref(handle)))
        self.model = model
        self._own(handle, lib.ssc_registration_destroy)

    def set_scan(self, points, normals=None, triangles=None) -> None:
        """The scan: (N, 3) points in metres, optional (N, 3) outward normals, optional (T, 3) mesh triangles."""
        p = np.ascontiguousarray(points, dtype=np.float32)
        if p.ndim != 2 or p.shape[1] != 3:
            raise ValueError(f"points must have shape (N, 3), not {p.shape}")
        n = None if normals is None else np.ascontiguousarray(normals, dtype=np.float32)
        if n is not None and n.shape != p.shape:
            raise ValueError("normals need one per point")
        t = None if triangles is None else np.ascontiguousarray(triangles, dtype=np.uint32)
        if t is not None and (t.ndim != 2 or t.shape[1] != 3):
            raise ValueError(f"triangles must have shape (T, 3), not {t.shape}")
        check(lib.ssc_registration_set_scan(self.handle, p.ctypes.data_as(c_float_p), None if n is None else n.ctypes.data_as(c_float_p),
                                            p.shape[0], 0, None if t is None else t.ctypes.data_as(c_uint32_p),
                                            0 if t is None else t.shape[0]))

    def set_landmarks(self, names: Sequence[str], positions) -> None:
        """Landmarks on the scan by the model's names, (N, 3) metres; an empty list removes them."""
        p = np.ascontiguousarray(positions, dtype=np.float32).reshape(-1, 3)
        if len(names) != p.shape[0]:
            raise ValueError(f"{len(names)} names for {p.shape[0]} positions")
        c_names = (ctypes.c_char_p * max(len(names), 1))(*[n.encode() for n in names])
        check(lib.ssc_registration_set_landmarks_by_name(self.handle, c_names, p.ctypes.data_as(c_float_p), p.shape[0]))

    def run(self, progress: Optional[Callable[[str, int, int], bool]] = None) -> Dict[str, object]:
        """Registers the scan; returns the report (rounds, solves, valid_vertices, seconds, fit_seconds,
        quality, regions). progress(stage, done, total) returning True cancels (SSC_ERROR_CANCELLED)."""
        report = RegistrationReport(struct_size=ctypes.sizeof(RegistrationReport))
        callback, errors = progress_callback(STAGE_PROGRESS_FN, progress,
                                             lambda stage, done, total: (stage.decode(), int(done), int(total)))
        status = lib.ssc_registration_run(self.handle, callback, None, ctypes.byref(report))
        if errors:
            raise errors[0]
        check(status)
        return self._report(report)

    def run_file(self, scan: str, mesh: str, landmarks: Optional[str] = None, units: Optional[str] = None, up: Optional[str] = None,
                 report: bool = True, reuse: bool = False, picture: Optional[str] = None,
                 progress: Optional[Callable[[str, int, int], bool]] = None) -> Dict[str, object]:
        """Registers a scan file (PLY or OBJ; landmarks: a CAESAR .lnd) and writes the registered mesh
        (.ply or .obj, the scan's frame and units), the JSON report beside it and, on request, a PNG:
        what `sscape register` does (ssc_registration_run_file; needs libsscape_offline). units: "m",
        "cm" or "mm" for both files (None: metres for the scan, millimetres for the .lnd); up: the
        scan's up axis (None: "y"). With reuse, a registration already there from the same model,
        scan, landmarks, units and up axis is kept (the result's "reused" is then True and the
        getters have nothing). Returns the report as run() does, plus "reused"."""
        need_offline("Registration.run_file")
        job = ScanFileJob()
        lib.ssc_scan_file_job_init(ctypes.byref(job), ctypes.sizeof(ScanFileJob))
        path = lambda v: None if v is None else os.fsencode(v)  # any name the file system allows
        text = lambda v: None if v is None else str(v).encode()
        job.scan_path, job.mesh_path = path(scan), path(mesh)
        job.landmarks_path, job.units, job.up, job.picture_path = path(landmarks), text(units), text(up), path(picture)
        job.write_report, job.reuse = int(bool(report)), int(bool(reuse))
        out = RegistrationReport(struct_size=ctypes.sizeof(RegistrationReport))
        reused = ctypes.c_uint32()
        callback, errors = progress_callback(STAGE_PROGRESS_FN, progress,
                                             lambda stage, done, total: (stage.decode(), int(done), int(total)))
        status = lib.ssc_registration_run_file(self.handle, ctypes.byref(job), callback, None, ctypes.byref(out), ctypes.byref(reused))
        if errors:
            raise errors[0]
        check(status)
        result = self._report(out, regions=not reused.value)
        result["reused"] = bool(reused.value)
        return result

    def _report(self, report: RegistrationReport, regions: bool = True) -> Dict[str, object]:
        regions_out = {}
        for i in range(lib.ssc_registration_region_count(self.handle) if regions else 0):
            name, q = ctypes.c_char_p(), RegistrationQuality()
            check(lib.ssc_registration_get_region(self.handle, i, ctypes.byref(name), ctypes.byref(q)))
            regions_out[name.value.decode()] = _quality(q)
        return {"rounds": report.rounds, "solves": report.solves, "valid_vertices": report.valid_vertices,
                "seconds": report.seconds, "fit_seconds": report.fit_seconds, "quality": _quality(report.quality),
                "scan_points": report.scan_points, "landmarks": report.landmarks, "regions": regions_out}

    def vertices(self) -> np.ndarray:
        """(V, 3) the registered template (the model's triangles)."""
        V = self.model.vertex_count
        out = np.empty((V, 3), np.float32)
        check(lib.ssc_registration_get_vertices(self.handle, out.ctypes.data_as(c_float_p), V, 0))
        return out

    def valid(self) -> np.ndarray:
        """(V,) bool: vertices that ended on a compatible scan point (the others were filled in)."""
        V = self.model.vertex_count
        out = np.empty(V, np.uint8)
        check(lib.ssc_registration_get_valid(self.handle, out.ctypes.data_as(ctypes.POINTER(ctypes.c_uint8)), V))
        return out.astype(bool)

    def vertex_distances(self) -> np.ndarray:
        """(V,) metres to the scan, -1 where no compatible point lies within 5 cm."""
        V = self.model.vertex_count
        out = np.empty(V, np.float32)
        check(lib.ssc_registration_get_vertex_distances(self.handle, out.ctypes.data_as(c_float_p), V))
        return out

    def fit(self):
        """The model fit that started the run: (shape (K,), rotations (J, 4), translation (3,), scale)."""
        K, J = self.model.shape_count, self.model.joint_count
        shape, rotations, translation, scale = np.empty(K, np.float32), np.empty((J, 4), np.float32), np.empty(3, np.float32), ctypes.c_float()
        check(lib.ssc_registration_get_fit(self.handle, shape.ctypes.data_as(c_float_p), K, rotations.ctypes.data_as(c_float_p), J,
                                           translation.ctypes.data_as(c_float_p), ctypes.byref(scale)))
        return shape, rotations, translation, scale.value

    def fit_segment_shape(self, segment) -> np.ndarray:
        """One segment's coefficients (by index or name) in that fit: with fit()'s shape and pose,
        Body.set_segment_shape rebuilds the fitted body."""
        return self.model.read_segment_shape(segment, lambda index, out, count: lib.ssc_registration_get_fit_segment_shape(
            self.handle, index, out, count))
