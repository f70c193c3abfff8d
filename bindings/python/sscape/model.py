"""Model: a loaded .sscape body model, immutable and shareable between threads and bodies."""
from __future__ import annotations

import ctypes
import os
import weakref
from typing import Dict, List, NamedTuple, Union

import numpy as np

from ._native import SegmentInfo, SliderInfo, c_float_p, c_uint32_p, lib
from .errors import check


class Slider(NamedTuple):
    name: str
    unit: str
    description: str
    mean: float
    minimum: float
    maximum: float


class Segment(NamedTuple):
    name: str
    shape_count: int
    vertex_count: int


_METADATA = {"name": 0, "version": 1, "units": 2, "axes": 3, "license": 4, "provenance": 5, "description": 6}


class Model:
    """A statistical body model: template mesh, shape space, skeleton, skinning, landmarks.

    ``Model()`` is the default model built into the library; ``Model.from_file(path)`` and
    ``Model.from_bytes(data)`` load .sscape files (verified whole: a damaged file raises
    SscapeError and loads nothing). Any thread may use a model; it is freed when the last Python
    reference and the last Body made from it are gone, or at ``close()``.
    """

    def __init__(self, _handle: Union[int, None] = None):
        handle = ctypes.c_void_p()
        if _handle is None:
            check(lib.ssc_model_load_default(None, ctypes.byref(handle)))
        else:
            handle.value = _handle
        self._handle = handle
        self._finalizer = weakref.finalize(self, lib.ssc_model_release, handle)

    @classmethod
    def from_file(cls, path: Union[str, os.PathLike]) -> "Model":
        handle = ctypes.c_void_p()
        check(lib.ssc_model_load_file(None, os.fsencode(path), ctypes.byref(handle)))
        return cls(handle.value)

    @classmethod
    def from_bytes(cls, data: bytes) -> "Model":
        handle = ctypes.c_void_p()
        buffer = bytes(data)
        check(lib.ssc_model_load_memory(None, buffer, len(buffer), ctypes.byref(handle)))
        return cls(handle.value)

    def close(self) -> None:
        """Drops this object's reference now (bodies keep their own)."""
        self._finalizer()

    def __enter__(self) -> "Model":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    @property
    def handle(self) -> ctypes.c_void_p:
        if not self._finalizer.alive:
            raise ValueError("the model is closed")
        return self._handle

    # Counts.
    @property
    def vertex_count(self) -> int:
        return lib.ssc_model_vertex_count(self.handle)

    @property
    def triangle_count(self) -> int:
        return lib.ssc_model_triangle_count(self.handle)

    @property
    def joint_count(self) -> int:
        return lib.ssc_model_joint_count(self.handle)

    @property
    def shape_count(self) -> int:
        """Whole-body shape components (coefficients in standard deviations)."""
        return lib.ssc_model_shape_count(self.handle)

    @property
    def landmark_count(self) -> int:
        return lib.ssc_model_landmark_count(self.handle)

    # Topology and names.
    @property
    def triangles(self) -> np.ndarray:
        """(T, 3) uint32 vertex indices, counter-clockwise seen from outside."""
        out = np.empty((self.triangle_count, 3), np.uint32)
        check(lib.ssc_model_get_triangles(self.handle, out.ctypes.data_as(c_uint32_p), out.shape[0]))
        return out

    @property
    def joint_parents(self) -> np.ndarray:
        """(J,) int32: each joint's parent, -1 for the root."""
        out = np.empty(self.joint_count, np.int32)
        check(lib.ssc_model_get_joint_parents(self.handle, out.ctypes.data_as(ctypes.POINTER(ctypes.c_int32)), out.shape[0]))
        return out

    @property
    def joint_names(self) -> List[str]:
        return [self._name(lib.ssc_model_get_joint_name, j) for j in range(self.joint_count)]

    @property
    def landmark_names(self) -> List[str]:
        return [self._name(lib.ssc_model_get_landmark_name, i) for i in range(self.landmark_count)]

    def _name(self, fn, index: int) -> str:
        s = ctypes.c_char_p()
        check(fn(self.handle, index, ctypes.byref(s)))
        return s.value.decode()

    @property
    def shape_stddevs(self) -> np.ndarray:
        """(K,) float32: each component's standard deviation, metres for a unit basis vector."""
        out = np.empty(self.shape_count, np.float32)
        check(lib.ssc_model_get_shape_stddevs(self.handle, out.ctypes.data_as(c_float_p), out.shape[0]))
        return out

    @property
    def metadata(self) -> Dict[str, str]:
        """name, version, units, axes, license, provenance, description."""
        out = {}
        for key, value in _METADATA.items():
            s = ctypes.c_char_p()
            check(lib.ssc_model_get_metadata(self.handle, value, ctypes.byref(s)))
            out[key] = s.value.decode() if s.value else ""
        return out

    @property
    def sliders(self) -> List[Slider]:
        """Semantic sliders (stature, mass, ...): what a Body's set_slider takes."""
        out = []
        for i in range(lib.ssc_model_slider_count(self.handle)):
            info = SliderInfo(struct_size=ctypes.sizeof(SliderInfo))
            check(lib.ssc_model_get_slider_info(self.handle, i, ctypes.byref(info)))
            out.append(Slider(info.name.decode(), info.unit.decode(), info.description.decode(), info.mean, info.minimum, info.maximum))
        return out

    @property
    def segments(self) -> List[Segment]:
        """Segment shape spaces (head, arm_l, ...), empty for a model without them."""
        out = []
        for i in range(lib.ssc_model_segment_count(self.handle)):
            info = SegmentInfo(struct_size=ctypes.sizeof(SegmentInfo))
            check(lib.ssc_model_get_segment_info(self.handle, i, ctypes.byref(info)))
            out.append(Segment(info.name.decode(), info.shape_count, info.vertex_count))
        return out

    def sample_shapes(self, count: int, seed: int = 1, truncation: float = 2.5) -> np.ndarray:
        """(count, K) float32 random shapes: standard normal coefficients truncated at ``truncation`` SD."""
        out = np.empty((count, self.shape_count), np.float32)
        check(lib.ssc_model_sample_shapes(self.handle, seed, count, truncation, out.ctypes.data_as(c_float_p), out.size))
        return out

    def __repr__(self) -> str:
        return f"<sscape.Model {self.metadata['name']!r}: {self.vertex_count} vertices, {self.shape_count} components, {self.joint_count} joints>"
