"""Fitter: the model fitted to landmarks and point clouds of one person, in one or more frames."""
from __future__ import annotations

import ctypes
import os
from typing import Callable, Dict, Optional, Sequence, Tuple

import numpy as np

from ._native import (FRAME_FN, PROGRESS_FN, DepthImageDef, FitFileDef, FitFileInfo, FitFrameReport, FitReport, FitterDef, c_float_p,
                      lib, need_offline)
from ._handle import Handle, progress_callback
from .errors import check
from .model import Model

_OPTIONS = {"shape_count", "fit_scale", "max_iterations", "landmark_sigma", "point_sigma", "shape_prior", "pose_prior",
            "max_points", "seed", "joint_limits", "fit_segments"}


_FLAGS = ("converged", "implausible", "failed", "left_out")  # the reports' yes/no fields
# ssc_fit_problem and ssc_body_region by name.
_PROBLEMS = ("none", "joint_past_range", "scan_unexplained", "limb_off_scan", "limb_inside", "arm_off_points",
             "hand_off_points")
_REGIONS = ("head", "trunk", "left_arm", "right_arm", "left_leg", "right_leg")


def _frame_dict(r: FitFrameReport, joint_names) -> Dict[str, object]:
    """A frame report as a dict: problem and region by name, the joint by name (None when none)."""
    return {"failed": bool(r.failed), "left_out": bool(r.left_out), "problem": _PROBLEMS[r.problem] if r.problem < len(_PROBLEMS) else str(r.problem),
            "problem_text": (r.problem_text or b"").decode(), "unscanned": (r.unscanned or b"").decode(),
            "joint": joint_names[r.joint] if 0 <= r.joint < len(joint_names) else None, "joint_excess_degrees": r.joint_excess_degrees,
            "region": _REGIONS[r.region] if 0 <= r.region < len(_REGIONS) else None, "unexplained_fraction": r.unexplained_fraction}


def _points(values, what: str) -> np.ndarray:
    a = np.ascontiguousarray(values, dtype=np.float32)
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{what} must have shape (N, 3), not {a.shape}")
    return a


class Fitter(Handle):
    """Finds the shape (shared by all frames), each frame's pose and translation, and optionally a
    global scale that best explain the observations added. Options as ssc_fitter_def:
    shape_count, fit_scale, max_iterations, landmark_sigma, point_sigma, shape_prior, pose_prior,
    max_points, seed, joint_limits, fit_segments. One thread at a time.

        fitter = sscape.Fitter(model)
        fitter.add_points(scan_points)               # (N, 3) metres
        report = fitter.solve()
        body_vertices = fitter.vertices()
    """

    _what = "fitter"

    def __init__(self, model: Model, **options):
        unknown = set(options) - _OPTIONS
        if unknown:
            raise TypeError(f"unknown fitter options: {', '.join(sorted(unknown))} (known: {', '.join(sorted(_OPTIONS))})")
        d = FitterDef()
        lib.ssc_fitter_def_init(ctypes.byref(d), ctypes.sizeof(FitterDef))
        for key, value in options.items():
            setattr(d, key, int(value) if isinstance(getattr(d, key), int) else float(value))
        handle = ctypes.c_void_p()
        check(lib.ssc_fitter_create(model.handle, ctypes.byref(d), ctypes.byref(handle)))
        self.model = model
        self._own(handle, lib.ssc_fitter_destroy)

    @property
    def frame_count(self) -> int:
        """Frames of this fit (one shape shared by all, a pose each); observations go to frame 0 unless told."""
        return lib.ssc_fitter_frame_count(self.handle)

    def _frame(self, frame: Optional[int]) -> int:
        return max(self.frame_count - 1, 0) if frame is None else int(frame)

    def add_landmarks(self, names: Sequence[str], positions, weights=None, frame: Optional[int] = None) -> None:
        """Landmarks by the model's names (CAESAR for the default model), (N, 3) metres; frame None: the last (or first)."""
        p = _points(positions, "positions")
        if len(names) != p.shape[0]:
            raise ValueError(f"{len(names)} names for {p.shape[0]} positions")
        w = None if weights is None else np.ascontiguousarray(weights, dtype=np.float32)
        if w is not None and w.shape != (p.shape[0],):
            raise ValueError(f"weights must have shape ({p.shape[0]},)")
        c_names = (ctypes.c_char_p * len(names))(*[n.encode() for n in names])
        check(lib.ssc_fitter_add_landmarks_by_name(self.handle, self._frame(frame), c_names, p.ctypes.data_as(c_float_p),
                                                   None if w is None else w.ctypes.data_as(c_float_p), p.shape[0]))

    def add_landmark_indices(self, indices, positions, weights=None, frame: Optional[int] = None) -> None:
        """Landmarks by the model's landmark indices (N,), (N, 3) metres; as add_landmarks otherwise."""
        i = np.ascontiguousarray(indices, dtype=np.uint32)
        p = _points(positions, "positions")
        if i.shape != (p.shape[0],):
            raise ValueError(f"{i.shape[0] if i.ndim == 1 else i.shape} indices for {p.shape[0]} positions")
        w = None if weights is None else np.ascontiguousarray(weights, dtype=np.float32)
        if w is not None and w.shape != (p.shape[0],):
            raise ValueError(f"weights must have shape ({p.shape[0]},)")
        check(lib.ssc_fitter_add_landmarks(self.handle, self._frame(frame), i.ctypes.data_as(ctypes.POINTER(ctypes.c_uint32)),
                                           p.ctypes.data_as(c_float_p), None if w is None else w.ctypes.data_as(c_float_p), p.shape[0]))

    def add_points(self, points, normals=None, confidence=None, frame: Optional[int] = None) -> None:
        """A point cloud, (N, 3) metres, with optional outward normals (N, 3) and confidences (N,) in [0, 1]."""
        p = _points(points, "points")
        n = None if normals is None else _points(normals, "normals")
        c = None if confidence is None else np.ascontiguousarray(confidence, dtype=np.float32)
        if (n is not None and n.shape != p.shape) or (c is not None and c.shape != (p.shape[0],)):
            raise ValueError("normals and confidence need one entry per point")
        check(lib.ssc_fitter_add_points(self.handle, self._frame(frame), p.ctypes.data_as(c_float_p),
                                        None if n is None else n.ctypes.data_as(c_float_p),
                                        None if c is None else c.ctypes.data_as(c_float_p), p.shape[0], 0))

    def add_depth_image(self, depth, fx: float, fy: float, cx: float, cy: float, camera_to_world=None, mask=None,
                        min_depth: float = 0.0, max_depth: float = 0.0, frame: Optional[int] = None) -> int:
        """A depth image through a pinhole camera (x right, y down, z forward; OpenCV's): depth (H, W)
        uint16 millimetres (0: no reading) or float32 metres; fx, fy, cx, cy in pixels;
        camera_to_world: (4, 4) rigid transform (None: the camera is the world frame); mask (H, W):
        False ignores a pixel; readings outside [min_depth, max_depth] metres are ignored
        (max_depth 0: no limit). Several cameras at one instant go in one frame. Returns the points
        added (the usable pixels, row-major: the order of point_residuals)."""
        d = np.asarray(depth)
        if d.ndim != 2:
            raise ValueError(f"depth must have shape (H, W), not {d.shape}")
        if d.dtype == np.uint16:
            fmt = 0
        elif np.issubdtype(d.dtype, np.floating):
            d, fmt = d.astype(np.float32), 1
        else:
            raise TypeError(f"depth must be uint16 millimetres or float metres, not {d.dtype}")
        d = np.ascontiguousarray(d)
        image = DepthImageDef()
        lib.ssc_depth_image_def_init(ctypes.byref(image), ctypes.sizeof(DepthImageDef))
        image.height, image.width = d.shape
        image.format, image.samples = fmt, d.ctypes.data
        m = None
        if mask is not None:
            m = np.ascontiguousarray(mask, dtype=np.uint8)
            if m.shape != d.shape:
                raise ValueError("the mask needs one entry per pixel")
            image.mask = m.ctypes.data
        image.fx, image.fy, image.cx, image.cy = float(fx), float(fy), float(cx), float(cy)
        pose = None
        if camera_to_world is not None:
            pose = np.ascontiguousarray(np.asarray(camera_to_world, dtype=np.float32).T)  # rows -> the C API's columns
            if pose.shape != (4, 4):
                raise ValueError("camera_to_world must be a (4, 4) matrix")
            image.camera_to_world = pose.ctypes.data_as(c_float_p)
        image.min_depth, image.max_depth = float(min_depth), float(max_depth)
        added = ctypes.c_uint32()
        check(lib.ssc_fitter_add_depth_image(self.handle, self._frame(frame), ctypes.byref(image), ctypes.byref(added)))
        return added.value

    def _add_file(self, fn, path, units, hands: bool, frame: Optional[int]) -> Dict[str, float]:
        need_offline("Fitter file inputs")
        d = FitFileDef()
        lib.ssc_fit_file_def_init(ctypes.byref(d), ctypes.sizeof(FitFileDef))
        d.path, d.units, d.use_hands = os.fsencode(path), None if units is None else units.encode(), int(hands)
        info = FitFileInfo(struct_size=ctypes.sizeof(FitFileInfo))
        check(fn(self.handle, self._frame(frame), ctypes.byref(d), ctypes.byref(info)))
        return {"used": info.used, "left_out": info.left_out, "unknown": info.unknown, "span": info.span}

    def add_points_file(self, path, units: Optional[str] = None, frame: Optional[int] = None) -> Dict[str, float]:
        """A PLY or OBJ scan as `sscape fit --points` reads it (units "m" (None), "cm", "mm"; needs
        libsscape_offline). Returns used (points), left_out (normals estimated), span (metres)."""
        return self._add_file(lib.ssc_fitter_add_points_file, path, units, False, frame)

    def add_landmarks_file(self, path, units: Optional[str] = None, hands: bool = False, frame: Optional[int] = None) -> Dict[str, float]:
        """A CAESAR .lnd as `sscape fit --landmarks` reads it (units None: the format's millimetres;
        hand landmarks only with hands). Returns used, left_out (hand landmarks), unknown (names), span."""
        return self._add_file(lib.ssc_fitter_add_landmarks_file, path, units, hands, frame)

    def write_params(self, path) -> None:
        """The last solve's parameters as JSON, as `sscape fit --params` writes them (needs libsscape_offline)."""
        need_offline("Fitter.write_params")
        if getattr(self, "_report", None) is None:
            raise ValueError("write_params needs a solved fit")
        check(lib.ssc_fitter_write_params(self.handle, ctypes.byref(self._report), os.fsencode(path)))

    def solve(self, progress: Optional[Callable[[int, float], bool]] = None,
              frame_done: Optional[Callable[[int, Dict[str, object]], bool]] = None) -> Dict[str, object]:
        """Runs the fit; returns the report as a dict (problem by name). progress(iteration, cost)
        returning True cancels (SscapeError SSC_ERROR_CANCELLED; the results hold the state reached).
        frame_done(frame, frame_report) is called as each frame is fitted (see frame_report);
        returning True cancels. With several frames, a frame that failed is left out of the shared
        shape and reported (frame_report(f)["failed"]); every other frame is returned."""
        report = FitReport(struct_size=ctypes.sizeof(FitReport))
        callback, errors = progress_callback(PROGRESS_FN, progress, lambda iteration, cost: (int(iteration), float(cost)))
        names = self.model.joint_names
        frame_callback, frame_errors = progress_callback(FRAME_FN, frame_done, lambda frame, r: (int(frame), _frame_dict(r.contents, names)))
        check(lib.ssc_fitter_set_frame_callback(self.handle, frame_callback, None))
        try:
            status = lib.ssc_fitter_solve(self.handle, callback, None, ctypes.byref(report))
        finally:
            check(lib.ssc_fitter_set_frame_callback(self.handle, FRAME_FN(), None))
        if errors or frame_errors:
            raise (errors + frame_errors)[0]
        check(status)
        self._report = report
        # The C flags (uint32 0 / 1) as Python's bool, so `report["converged"] is True` reads as it should.
        out = {name: bool(getattr(report, name)) if name in _FLAGS else getattr(report, name)
               for name, _ in FitReport._fields_ if name not in ("struct_size", "reserved")}
        out["problem"] = _PROBLEMS[report.problem] if report.problem < len(_PROBLEMS) else str(report.problem)
        return out

    def frame_report(self, frame: int = 0) -> Dict[str, object]:
        """How a frame's fit was judged, after solve(): failed (the fit did not find the person),
        left_out (failed, so kept out of the shared shape), problem ("none", "joint_past_range",
        "scan_unexplained", "limb_off_scan", "limb_inside", "arm_off_points", "hand_off_points")
        and problem_text, the joint furthest past its range, the region off the scan (or the most
        unscanned one), unscanned (parts a partial scan does not show)."""
        r = FitFrameReport(struct_size=ctypes.sizeof(FitFrameReport))
        check(lib.ssc_fitter_get_frame_report(self.handle, frame, ctypes.byref(r)))
        return _frame_dict(r, self.model.joint_names)

    @property
    def shape(self) -> np.ndarray:
        """(K,) float32 the fitted shape coefficients, standard deviations (shared by every frame)."""
        out = np.empty(self.model.shape_count, np.float32)
        check(lib.ssc_fitter_get_shape(self.handle, out.ctypes.data_as(c_float_p), out.shape[0]))
        return out

    def segment_shape(self, segment) -> np.ndarray:
        """(shape_count,) float32 one segment's fitted coefficients (by index or name; zeros when the
        fit had no segments). With shape and pose, Body.set_segment_shape rebuilds the fitted body."""
        return self.model.read_segment_shape(segment, lambda index, out, count: lib.ssc_fitter_get_segment_shape(self.handle, index, out, count))

    def pose(self, frame: int = 0) -> Tuple[np.ndarray, np.ndarray, float]:
        """(rotations (J, 4) x y z w, translation (3,), scale) of a frame."""
        J = self.model.joint_count
        rotations, translation, scale = np.empty((J, 4), np.float32), np.empty(3, np.float32), ctypes.c_float()
        check(lib.ssc_fitter_get_pose(self.handle, frame, rotations.ctypes.data_as(c_float_p), J, translation.ctypes.data_as(c_float_p),
                                      ctypes.byref(scale)))
        return rotations, translation, scale.value

    def vertices(self, frame: int = 0) -> np.ndarray:
        """(V, 3) the fitted surface of a frame (scale and translation applied)."""
        V = self.model.vertex_count
        out = np.empty((V, 3), np.float32)
        check(lib.ssc_fitter_get_vertices(self.handle, frame, out.ctypes.data_as(c_float_p), V, 0))
        return out

    def point_residuals(self, frame: int = 0) -> np.ndarray:
        """(N,) distances of a frame's points to the fitted surface, metres, in the order added."""
        n = lib.ssc_fitter_point_count(self.handle, frame)
        out = np.empty(n, np.float32)
        check(lib.ssc_fitter_get_point_residuals(self.handle, frame, out.ctypes.data_as(c_float_p), n))
        return out
