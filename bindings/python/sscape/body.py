"""Body: one body of a model, its shape and pose in, its vertices, joints and measurements out."""
from __future__ import annotations

import ctypes
import os
from typing import Dict, List, Optional, Union

import numpy as np

from ._native import BodyDef, ExportDef, MadeToMeasureDef, c_float_p, c_uint32_p, lib
from ._handle import Handle, progress_callback
from .errors import check
from .model import Model

_FORMATS = {None: 0, "obj": 1, "ply": 2, "glb": 3}


def measurement_names() -> List[str]:
    """The measurements Body.measure returns, in the library's order (SI units)."""
    names = []
    for m in range(lib.ssc_measurement_count()):
        name = ctypes.c_char_p()
        check(lib.ssc_measurement_get_info(m, ctypes.byref(name), None, None))
        names.append(name.value.decode())
    return names


def _floats(values, what: str) -> np.ndarray:
    a = np.ascontiguousarray(values, dtype=np.float32)
    if a.ndim != 1:
        raise ValueError(f"{what} must be one-dimensional, not of shape {a.shape}")
    return a


def quaternion_from_axis_angle(axis_angle) -> np.ndarray:
    """(4,) float32 x y z w of an axis-angle vector (3,), as the library converts them."""
    v = _floats(axis_angle, "axis_angle")
    if v.shape != (3,):
        raise ValueError("an axis-angle rotation has 3 values")
    out = np.empty(4, np.float32)
    check(lib.ssc_rotation_from_axis_angle(v.ctypes.data_as(c_float_p), out.ctypes.data_as(c_float_p)))
    return out


def _pointer(a: Optional[np.ndarray]):
    """A float32 array's data for C, or NULL for None."""
    return None if a is None else a.ctypes.data_as(c_float_p)


class Body(Handle):
    """A body of a model, at the mean shape in the rest pose when made.

    Shape coefficients are in standard deviations; the pose is a unit quaternion (x, y, z, w) per
    joint. Arrays come back as new numpy arrays the library wrote into directly. A body is used from
    one thread at a time (the C API's rule); different bodies may be used on different threads.
    Freed at ``close()``, at the end of a ``with`` block, or when garbage collected.
    """

    _what = "body"

    def __init__(self, model: Model):
        handle = ctypes.c_void_p()
        d = BodyDef()
        lib.ssc_body_def_init(ctypes.byref(d), ctypes.sizeof(BodyDef))
        check(lib.ssc_body_create(model.handle, ctypes.byref(d), ctypes.byref(handle)))
        self.model = model
        self._own(handle, lib.ssc_body_destroy)
        self._V = model.vertex_count
        self._J = model.joint_count

    # Shape and pose.
    @property
    def shape(self) -> np.ndarray:
        """(K,) float32 whole-body coefficients. Setting takes up to K values (the rest become 0)."""
        out = np.empty(self.model.shape_count, np.float32)
        check(lib.ssc_body_get_shape(self.handle, out.ctypes.data_as(c_float_p), out.shape[0]))
        return out

    @shape.setter
    def shape(self, coefficients) -> None:
        c = _floats(coefficients, "shape")
        check(lib.ssc_body_set_shape(self.handle, c.ctypes.data_as(c_float_p), c.shape[0]))

    def _pose_arguments(self, rotations, translation):
        """Checked (J, 4) rotations and (3,) translation as float32 arrays (None stays None)."""
        r = None if rotations is None else np.ascontiguousarray(rotations, dtype=np.float32)
        if r is not None and r.shape != (self._J, 4):
            raise ValueError(f"rotations must have shape ({self._J}, 4), not {r.shape}")
        t = None if translation is None else _floats(translation, "translation")
        if t is not None and t.shape != (3,):
            raise ValueError("translation needs 3 values")
        return r, t

    def set_pose(self, rotations: Optional[np.ndarray] = None, translation=None) -> None:
        """rotations: (J, 4) quaternions x y z w per joint (None: the rest pose); translation: the root's, metres."""
        r, t = self._pose_arguments(rotations, translation)
        check(lib.ssc_body_set_pose(self.handle, _pointer(r), self._J, _pointer(t)))

    def set_pose_axis_angle(self, rotations, translation=None) -> None:
        """rotations: (J, 3) axis-angle vectors per joint (unit axis times radians); as set_pose otherwise."""
        r = np.ascontiguousarray(rotations, dtype=np.float32)
        if r.shape != (self._J, 3):
            raise ValueError(f"rotations must have shape ({self._J}, 3), not {r.shape}")
        _, t = self._pose_arguments(None, translation)
        check(lib.ssc_body_set_pose_axis_angle(self.handle, _pointer(r), self._J, _pointer(t)))

    def set_pose_limited(self, rotations, translation=None, clamp: bool = True) -> int:
        """As set_pose, within the joints' anatomical limits: clamp (default) or refuse (SscapeError)
        rotations beyond them. Returns how many joints were outside."""
        if rotations is None:
            raise ValueError("set_pose_limited needs rotations")
        r, t = self._pose_arguments(rotations, translation)
        outside = ctypes.c_uint32()
        check(lib.ssc_body_set_pose_limited(self.handle, _pointer(r), self._J, _pointer(t), 1 if clamp else 0, ctypes.byref(outside)))
        return outside.value

    def set_segment_shape(self, segment: Union[int, str], coefficients) -> None:
        """One segment's coefficients (by index or name), on top of the whole-body shape."""
        index = self._segment_index(segment)
        c = _floats(coefficients, "coefficients")
        check(lib.ssc_body_set_segment_shape(self.handle, index, c.ctypes.data_as(c_float_p), c.shape[0]))

    def segment_shape(self, segment: Union[int, str]) -> np.ndarray:
        """One segment's (by index or name) shape coefficients on this body, standard deviations."""
        index = self._segment_index(segment)
        out = np.empty(self.model.segments[index].shape_count, np.float32)
        check(lib.ssc_body_get_segment_shape(self.handle, index, out.ctypes.data_as(c_float_p), out.shape[0]))
        return out

    def _segment_index(self, segment: Union[int, str]) -> int:
        if isinstance(segment, str):
            names = [s.name for s in self.model.segments]
            if segment not in names:
                raise KeyError(f"the model has no segment {segment!r} (it has: {', '.join(names) or 'none'})")
            return names.index(segment)
        return int(segment)

    # Sliders.
    @property
    def sliders(self) -> Dict[str, float]:
        """The body's slider values by name (read from its shape)."""
        names = [s.name for s in self.model.sliders]
        out = np.empty(len(names), np.float32)
        if names:
            check(lib.ssc_body_get_sliders(self.handle, out.ctypes.data_as(c_float_p), out.shape[0]))
        return dict(zip(names, (float(v) for v in out)))

    def set_slider(self, name: str, value: float) -> None:
        """Moves one slider (SI units), keeping the others' values."""
        names = [s.name for s in self.model.sliders]
        if name not in names:
            raise KeyError(f"the model has no slider {name!r} (it has: {', '.join(names) or 'none'})")
        check(lib.ssc_body_set_slider(self.handle, names.index(name), float(value)))

    def set_sliders(self, values: Dict[str, float]) -> None:
        """Replaces the shape by the population's typical body with these slider values: every
        slider by name (SI units), as Model.sliders lists them."""
        names = [s.name for s in self.model.sliders]
        missing, unknown = [n for n in names if n not in values], [n for n in values if n not in names]
        if missing or unknown:
            raise KeyError(f"set_sliders needs exactly the model's sliders ({', '.join(names) or 'none'}); "
                           f"missing: {', '.join(missing) or 'none'}, unknown: {', '.join(unknown) or 'none'}")
        v = np.array([values[n] for n in names], np.float32)
        check(lib.ssc_body_set_sliders(self.handle, v.ctypes.data_as(c_float_p), v.shape[0]))

    def make_to_measure(self, targets: Dict[str, float], sex: Optional[float] = None, age: Optional[float] = None,
                        tolerance: Optional[float] = None) -> bool:
        """Sets the shape to reproduce the measurements asked for ({"stature": 1.75, "waist_girth": 0.82},
        SI units), for a person of the given sex (0 female, 1 male) and age when known. Returns whether
        every target was reached within the tolerance (metres; default 0.5 mm)."""
        if not targets:
            raise ValueError("make_to_measure needs at least one measurement")
        ids = np.empty(len(targets), np.uint32)
        for i, name in enumerate(targets):
            found = ctypes.c_uint32()
            check(lib.ssc_measurement_find(name.encode(), ctypes.byref(found)))
            ids[i] = found.value
        values = np.array([float(v) for v in targets.values()], np.float32)
        d = MadeToMeasureDef()
        lib.ssc_made_to_measure_def_init(ctypes.byref(d), ctypes.sizeof(MadeToMeasureDef))
        if sex is not None:
            d.sex = float(sex)
        if age is not None:
            d.age = float(age)
        if tolerance is not None:
            d.tolerance = float(tolerance)
        converged = ctypes.c_uint32()
        check(lib.ssc_body_make_to_measure(self.handle, ids.ctypes.data_as(c_uint32_p), values.ctypes.data_as(c_float_p), len(values),
                                           ctypes.byref(d), None, 0, ctypes.byref(converged)))
        return bool(converged.value)

    # Outputs.
    def _vertices(self, fn, n: int, out: Optional[np.ndarray] = None) -> np.ndarray:
        if out is None:
            out = np.empty((n, 3), np.float32)
        elif not (isinstance(out, np.ndarray) and out.dtype == np.float32 and out.shape == (n, 3) and out.flags.c_contiguous
                  and out.flags.writeable):
            got = f"{out.dtype} {out.shape}" if isinstance(out, np.ndarray) else type(out).__name__
            raise ValueError(f"out must be a writable C-contiguous float32 array of shape ({n}, 3); got {got}")
        check(fn(self.handle, out.ctypes.data_as(c_float_p), n, 12))
        return out

    @property
    def vertices(self) -> np.ndarray:
        """(V, 3) float32 posed vertices, metres (a new array; get_vertices(out=) fills one you keep)."""
        return self._vertices(lib.ssc_body_get_vertices, self._V)

    @property
    def normals(self) -> np.ndarray:
        """(V, 3) float32 unit vertex normals of the posed body (a new array; get_normals(out=) fills one)."""
        return self._vertices(lib.ssc_body_get_normals, self._V)

    def get_vertices(self, out: Optional[np.ndarray] = None) -> np.ndarray:
        """(V, 3) float32 posed vertices written into out (float32, C-contiguous, shape (V, 3)) without
        a copy, or into a new array; returns it. For loops over many bodies: no allocation per body."""
        return self._vertices(lib.ssc_body_get_vertices, self._V, out)

    def get_normals(self, out: Optional[np.ndarray] = None) -> np.ndarray:
        """(V, 3) float32 unit vertex normals written into out (as get_vertices) or a new array; returns it."""
        return self._vertices(lib.ssc_body_get_normals, self._V, out)

    @property
    def rest_vertices(self) -> np.ndarray:
        """(V, 3) float32 vertices of the shaped body in the rest pose."""
        return self._vertices(lib.ssc_body_get_rest_vertices, self._V)

    @property
    def landmarks(self) -> np.ndarray:
        """(L, 3) float32 posed landmarks, in Model.landmark_names order."""
        return self._vertices(lib.ssc_body_get_landmarks, self.model.landmark_count)

    @property
    def joint_transforms(self) -> np.ndarray:
        """(J, 4, 4) float32 world transforms of the joints (the C API's column-major, transposed to rows)."""
        out = np.empty((self._J, 16), np.float32)
        check(lib.ssc_body_get_joint_transforms(self.handle, out.ctypes.data_as(c_float_p), self._J))
        return out.reshape(self._J, 4, 4).transpose(0, 2, 1).copy()

    def _matrices(self, fn) -> np.ndarray:
        out = np.empty((self._J, 16), np.float32)
        check(fn(self.handle, out.ctypes.data_as(c_float_p), self._J))
        return out.reshape(self._J, 4, 4).transpose(0, 2, 1).copy()

    @property
    def inverse_bind_matrices(self) -> np.ndarray:
        """(J, 4, 4) inverse bind matrices of the shaped body (row-major here)."""
        return self._matrices(lib.ssc_body_get_inverse_bind_matrices)

    @property
    def skinning_matrices(self) -> np.ndarray:
        """(J, 4, 4) world transform x inverse bind per joint, for engines that skin themselves (row-major here)."""
        return self._matrices(lib.ssc_body_get_skinning_matrices)

    def measure(self) -> Dict[str, float]:
        """Every measurement by name, SI units (m, m^2, m^3, kg)."""
        names = measurement_names()
        out = np.empty(len(names), np.float32)
        check(lib.ssc_body_measure(self.handle, out.ctypes.data_as(c_float_p), out.shape[0]))
        return dict(zip(names, (float(v) for v in out)))

    def measure_one(self, name: str) -> float:
        """One measurement by name (as measurement_names lists them), SI units."""
        out = ctypes.c_float()
        check(lib.ssc_body_measure_by_name(self.handle, name.encode(), ctypes.byref(out)))
        return out.value

    def write(self, path: Union[str, os.PathLike], format: Optional[str] = None, level: Union[int, str] = 0,
              morphs: Union[int, str, None] = None) -> None:
        """Writes the body as OBJ, PLY or rigged glTF (.glb); format None: from the extension; level: a level of
        detail (Model.levels) by index or name, 0 the full mesh, or "all": every level in one .glb (a node each).
        morphs (.glb only): K for the first K shape components as morph targets (weight 1 = +1 SD), or
        "sliders" for the semantic sliders (weight 1 = +1 SD of the attribute); the file's
        skins[0].extras.sscape_morphs says how the joints move per unit of weight (docs/engines.md)."""
        if format not in _FORMATS:
            raise ValueError(f"format must be one of obj, ply, glb or None, not {format!r}")
        index = 0xFFFFFFFF if level == "all" else self.model.level(level).index
        d = ExportDef()
        lib.ssc_export_def_init(ctypes.byref(d), ctypes.sizeof(d))
        d.format, d.level = _FORMATS[format], index
        if morphs == "sliders":
            d.morphs = 2
        elif morphs is not None:
            if isinstance(morphs, bool) or not isinstance(morphs, int):
                raise TypeError(f"morphs must be a component count or 'sliders', not {morphs!r}")
            d.morphs, d.morph_count = 1, morphs
        check(lib.ssc_body_export(self.handle, os.fsencode(path), ctypes.byref(d)))

    def level_vertices(self, level: Union[int, str], out: Optional[np.ndarray] = None) -> np.ndarray:
        """(N, 3) float32 posed vertices of a level of detail (Model.levels; by index or name), metres."""
        lv = self.model.level(level)
        return self._vertices(lambda h, p, n, s: lib.ssc_body_get_level_vertices(h, lv.index, p, n, s), lv.vertex_count, out)

    def level_normals(self, level: Union[int, str], out: Optional[np.ndarray] = None) -> np.ndarray:
        """(N, 3) float32 unit normals of a level of detail's posed mesh."""
        lv = self.model.level(level)
        return self._vertices(lambda h, p, n, s: lib.ssc_body_get_level_normals(h, lv.index, p, n, s), lv.vertex_count, out)

    def level_rest_vertices(self, level: Union[int, str], out: Optional[np.ndarray] = None) -> np.ndarray:
        """(N, 3) float32 shaped, unposed vertices of a level of detail."""
        lv = self.model.level(level)
        return self._vertices(lambda h, p, n, s: lib.ssc_body_get_level_rest_vertices(h, lv.index, p, n, s), lv.vertex_count, out)
