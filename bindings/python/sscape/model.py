"""Model: a loaded .sscape body model, immutable and shareable between threads and bodies."""
from __future__ import annotations

import ctypes
import logging
import os
from typing import Dict, List, NamedTuple, Union

import numpy as np

from ._native import LOG_FN, BatchDesc, ContextDef, JointLimit, LevelInfo, SegmentInfo, SliderInfo, c_float_p, c_uint32_p, lib, need_offline
from ._handle import Handle
from .errors import check


_NOT_FOUND = -7  # SSC_ERROR_NOT_FOUND


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


class Level(NamedTuple):
    """A level of detail: 0 the full mesh, then the model's coarser meshes, finest first."""
    index: int
    name: str
    vertex_count: int
    triangle_count: int
    uv_count: int


#: The library's log messages (an unknown landmark name ignored, a scan subsampled, ...) go to this
#: logger: warnings reach stderr unless the application configures logging otherwise.
logger = logging.getLogger("sscape")
_PYTHON_LEVEL = {0: logging.DEBUG, 1: logging.INFO, 2: logging.WARNING, 3: logging.ERROR}


def _log(user, level, message):
    logger.log(_PYTHON_LEVEL.get(level, logging.WARNING), "%s", message.decode("utf-8", "backslashreplace"))


# One sink for the process, never freed: a context keeps its pointer as long as it lives.
_LOG_SINK = LOG_FN(_log)


class Context(Handle):
    """Library settings shared by the models loaded with it: worker threads for batch synthesis and
    the fits' searches (0: one per hardware thread; 1: the calling thread only), and the largest
    model accepted (bytes, decompressed; 0: 256 MiB). Models keep their context alive. The
    library's messages go to the ``sscape`` logger (``sscape.model.logger``), from the level it
    has when the context is made (warnings by default)."""

    _what = "context"

    def __init__(self, worker_count: int = 0, max_model_bytes: int = 0):
        d = ContextDef()
        lib.ssc_context_def_init(ctypes.byref(d), ctypes.sizeof(ContextDef))
        d.worker_count, d.max_model_bytes = int(worker_count), int(max_model_bytes)
        d.log = ctypes.cast(_LOG_SINK, ctypes.c_void_p)
        effective = logger.getEffectiveLevel()
        d.log_level = next((ssc for ssc, py in sorted(_PYTHON_LEVEL.items()) if py >= effective), 3)
        handle = ctypes.c_void_p()
        check(lib.ssc_context_create(ctypes.byref(d), ctypes.byref(handle)))
        self._own(handle, lib.ssc_context_destroy)


def default_model_bytes() -> bytes:
    """The built-in default model as .sscape file bytes (what Model() loads): write them to get the file."""
    data, size = ctypes.c_void_p(), ctypes.c_size_t()
    check(lib.ssc_default_model_file(ctypes.byref(data), ctypes.byref(size)))
    return ctypes.string_at(data.value, size.value)


def named_poses() -> Dict[str, str]:
    """The library's named poses (a_pose, t_pose, ...) with their descriptions: Model.named_pose takes them."""
    out = {}
    for i in range(lib.ssc_named_pose_count()):
        name, description = ctypes.c_char_p(), ctypes.c_char_p()
        check(lib.ssc_named_pose_get_info(i, ctypes.byref(name), ctypes.byref(description)))
        out[name.value.decode()] = description.value.decode()
    return out


_METADATA = {"name": 0, "version": 1, "units": 2, "axes": 3, "license": 4, "provenance": 5, "description": 6}


class Model(Handle):
    """A statistical body model: template mesh, shape space, skeleton, skinning, landmarks.

    ``Model()`` is the default model built into the library; ``Model.from_file(path)`` and
    ``Model.from_bytes(data)`` load .sscape files (verified whole: a damaged file raises
    SscapeError and loads nothing). Any thread may use a model; it is freed when the last Python
    reference and the last Body made from it are gone, or at ``close()``.
    """

    _what = "model"

    def __init__(self, context: Union[Context, None] = None, _handle: Union[int, None] = None):
        handle = ctypes.c_void_p()
        if _handle is None:
            context = context if context is not None else Context()  # held until loaded: the model then keeps it
            check(lib.ssc_model_load_default(context.handle, ctypes.byref(handle)))
        else:
            handle.value = _handle
        self._own(handle, lib.ssc_model_release)

    @classmethod
    def from_file(cls, path: Union[str, os.PathLike], context: Union[Context, None] = None) -> "Model":
        """Loads and verifies a .sscape model file (SscapeError if it is missing, corrupt or of another version)."""
        handle = ctypes.c_void_p()
        context = context if context is not None else Context()  # held until loaded: the model then keeps it
        check(lib.ssc_model_load_file(context.handle, os.fsencode(path), ctypes.byref(handle)))
        return cls(_handle=handle.value)

    @classmethod
    def from_bytes(cls, data: bytes, context: Union[Context, None] = None) -> "Model":
        """Loads and verifies a model from the bytes of a .sscape file (copied; the caller may drop them)."""
        handle = ctypes.c_void_p()
        buffer = bytes(data)
        context = context if context is not None else Context()  # held until loaded: the model then keeps it
        check(lib.ssc_model_load_memory(context.handle, buffer, len(buffer), ctypes.byref(handle)))
        return cls(_handle=handle.value)

    @property
    def digest(self) -> str:
        """16 hex digits of the file bytes the model was loaded from (the built-in model's as compiled
        in): what fit parameters and registration reports record as model_digest (needs libsscape_offline)."""
        need_offline("Model.digest")
        out = ctypes.c_char_p()
        check(lib.ssc_model_get_digest(self.handle, ctypes.byref(out)))
        return out.value.decode()

    # Counts.
    @property
    def vertex_count(self) -> int:
        """Vertices of every body of this model (13380 for the default model)."""
        return lib.ssc_model_vertex_count(self.handle)

    @property
    def triangle_count(self) -> int:
        """Triangles of the fixed mesh that every body shares."""
        return lib.ssc_model_triangle_count(self.handle)

    @property
    def joint_count(self) -> int:
        """Joints of the skeleton (53 for the default model); pose arrays have one row per joint."""
        return lib.ssc_model_joint_count(self.handle)

    @property
    def shape_count(self) -> int:
        """Whole-body shape components (coefficients in standard deviations)."""
        return lib.ssc_model_shape_count(self.handle)

    @property
    def landmark_count(self) -> int:
        """Named landmarks on the surface (the 73 CAESAR landmarks for the default model)."""
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
    def quads(self) -> np.ndarray:
        """(Q, 4) uint32: the authoring quads (empty when the model has none)."""
        n = lib.ssc_model_quad_count(self.handle)
        out = np.empty((n, 4), np.uint32)
        if n:
            check(lib.ssc_model_get_quads(self.handle, out.ctypes.data_as(c_uint32_p), n))
        return out

    @property
    def uvs(self):
        """(coordinates (U, 2) float32, triangle_uvs (T, 3) uint32 indices into them), or None without UVs."""
        n = lib.ssc_model_uv_count(self.handle)
        if n == 0:
            return None
        uv, tri = np.empty((n, 2), np.float32), np.empty((self.triangle_count, 3), np.uint32)
        check(lib.ssc_model_get_uvs(self.handle, uv.ctypes.data_as(c_float_p), n))
        check(lib.ssc_model_get_triangle_uvs(self.handle, tri.ctypes.data_as(c_uint32_p), tri.shape[0]))
        return uv, tri

    @property
    def vertex_sets(self) -> Dict[str, np.ndarray]:
        """Named body parts (head, torso, arms, ...): sorted uint32 vertex indices."""
        out = {}
        for i in range(lib.ssc_model_vertex_set_count(self.handle)):
            name, size = ctypes.c_char_p(), ctypes.c_uint32()
            check(lib.ssc_model_get_vertex_set(self.handle, i, ctypes.byref(name), ctypes.byref(size)))
            idx = np.empty(size.value, np.uint32)
            check(lib.ssc_model_get_vertex_set_indices(self.handle, i, idx.ctypes.data_as(c_uint32_p), size.value))
            out[name.value.decode()] = idx
        return out

    @property
    def skin(self):
        """(joints (V, 4) uint16, weights (V, 4) float32): 4 influences per vertex, weights summing to 1."""
        V = self.vertex_count
        joints, weights = np.empty((V, 4), np.uint16), np.empty((V, 4), np.float32)
        check(lib.ssc_model_get_skin(self.handle, joints.ctypes.data_as(ctypes.POINTER(ctypes.c_uint16)), weights.ctypes.data_as(c_float_p), V))
        return joints, weights

    def named_pose(self, name: str, left_hand: float = 0.0, right_hand: float = 0.0) -> np.ndarray:
        """(J, 4) quaternions of a named pose for this rig (sscape.named_poses() lists them), with the
        hands closed by the given amounts (0 open, 1 a loose fist)."""
        J = self.joint_count
        out = np.empty((J, 4), np.float32)
        check(lib.ssc_model_get_named_pose(self.handle, name.encode(), out.ctypes.data_as(c_float_p), J))
        if left_hand or right_hand:
            check(lib.ssc_model_close_hands(self.handle, float(left_hand), float(right_hand), out.ctypes.data_as(c_float_p), J))
        return out

    @property
    def joint_names(self) -> List[str]:
        """The joints' names, in pose order (parents before children)."""
        return [self._name(lib.ssc_model_get_joint_name, j) for j in range(self.joint_count)]

    @property
    def landmark_names(self) -> List[str]:
        """The landmarks' names, in Body.landmarks order."""
        return [self._name(lib.ssc_model_get_landmark_name, i) for i in range(self.landmark_count)]

    def read_segment_shape(self, segment, read) -> np.ndarray:
        """One segment's coefficients (by index or name; KeyError for a name the model lacks) from
        read(index, out, capacity), a C getter's call (a fit's or a registration's)."""
        segments = self.segments
        if isinstance(segment, str):
            names = [s.name for s in segments]
            if segment not in names:
                raise KeyError(f"the model has no segment {segment!r} (it has: {', '.join(names) or 'none'})")
            segment = names.index(segment)
        count = segments[int(segment)].shape_count if 0 <= int(segment) < len(segments) else 0
        out = np.empty(max(count, 1), np.float32)
        check(read(int(segment), out.ctypes.data_as(c_float_p), count))
        return out[:count]

    def index(self, kind: str, name: str) -> int:
        """The index of a "joint", "landmark", "slider" or "segment" by its exact name; KeyError if none."""
        fn = {"joint": lib.ssc_model_find_joint, "landmark": lib.ssc_model_find_landmark, "slider": lib.ssc_model_find_slider,
              "segment": lib.ssc_model_find_segment}.get(kind)
        if fn is None:
            raise ValueError(f"kind must be joint, landmark, slider or segment, not {kind!r}")
        out = ctypes.c_uint32()
        status = fn(self.handle, name.encode(), ctypes.byref(out))
        if status == _NOT_FOUND:
            raise KeyError(f"the model has no {kind} named {name!r}")
        check(status)
        return out.value

    @property
    def landmark_positions(self) -> np.ndarray:
        """(L, 3) float32: the landmarks on the mean body in the rest pose, metres (landmark_names order)."""
        out = np.empty((self.landmark_count, 3), np.float32)
        check(lib.ssc_model_get_landmark_positions(self.handle, out.ctypes.data_as(c_float_p), out.shape[0], 0))
        return out

    def joint_limits(self) -> Dict[str, Union[Dict[str, np.ndarray], None]]:
        """Each joint's anatomical range of motion by name: None for a joint without one (root,
        fingers), else {"frame": (3, 3) rotation vector -> anatomical angles, "lower", "upper":
        (3,) radians of flexion, axial rotation, abduction}."""
        out: Dict[str, Union[Dict[str, np.ndarray], None]] = {}
        for j, name in enumerate(self.joint_names):
            limit = JointLimit()
            check(lib.ssc_model_get_joint_limit(self.handle, j, ctypes.byref(limit)))
            out[name] = None if not limit.limited else {
                "frame": np.array(limit.frame, np.float32).reshape(3, 3),
                "lower": np.array(limit.lower, np.float32), "upper": np.array(limit.upper, np.float32)}
        return out

    def segment_vertices(self, segment: Union[int, str]):
        """A segment shape space's vertices and blend weights: ((N,) uint32 indices, (N,) float32 weights in (0, 1])."""
        names = [s.name for s in self.segments]
        index = names.index(segment) if isinstance(segment, str) and segment in names else segment
        if not isinstance(index, int) or not 0 <= index < len(names):
            raise KeyError(f"the model has no segment {segment!r} (it has: {', '.join(names) or 'none'})")
        n = self.segments[index].vertex_count
        vertices, weights = np.empty(n, np.uint32), np.empty(n, np.float32)
        check(lib.ssc_model_get_segment_vertices(self.handle, index, vertices.ctypes.data_as(c_uint32_p),
                                                 weights.ctypes.data_as(c_float_p), n))
        return vertices, weights

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

    @property
    def levels(self) -> List[Level]:
        """Levels of detail: 0 the full mesh ("full"), then the model's ("simplified", "proxy741", ...)."""
        out = []
        for i in range(lib.ssc_model_level_count(self.handle)):
            info = LevelInfo(struct_size=ctypes.sizeof(LevelInfo))
            check(lib.ssc_model_get_level_info(self.handle, i, ctypes.byref(info)))
            out.append(Level(i, info.name.decode(), info.vertex_count, info.triangle_count, info.uv_count))
        return out

    def level(self, level: Union[int, str]) -> Level:
        """One level of detail, by index or name."""
        levels = self.levels
        if isinstance(level, str):
            for lv in levels:
                if lv.name == level:
                    return lv
            raise KeyError(f"the model has no level {level!r}; its levels: {', '.join(lv.name for lv in levels)}")
        if not 0 <= int(level) < len(levels):
            raise IndexError(f"level {level} of a model with {len(levels)} levels (0 the full mesh)")
        return levels[int(level)]

    def level_triangles(self, level: Union[int, str]) -> np.ndarray:
        """(T, 3) uint32 vertex indices of a level's triangles."""
        lv = self.level(level)
        out = np.empty((lv.triangle_count, 3), np.uint32)
        check(lib.ssc_model_get_level_triangles(self.handle, lv.index, out.ctypes.data_as(c_uint32_p), out.shape[0]))
        return out

    def level_uvs(self, level: Union[int, str]):
        """(coordinates (U, 2) float32, triangle_uvs (T, 3) uint32) of a level, or None without UVs."""
        lv = self.level(level)
        if lv.uv_count == 0:
            return None
        uv, tri = np.empty((lv.uv_count, 2), np.float32), np.empty((lv.triangle_count, 3), np.uint32)
        check(lib.ssc_model_get_level_uvs(self.handle, lv.index, uv.ctypes.data_as(c_float_p), lv.uv_count))
        check(lib.ssc_model_get_level_triangle_uvs(self.handle, lv.index, tri.ctypes.data_as(c_uint32_p), lv.triangle_count))
        return uv, tri

    def level_skin(self, level: Union[int, str]):
        """(joints (N, 4) uint16, weights (N, 4) float32): a level's own skin, at most 4 influences."""
        lv = self.level(level)
        joints, weights = np.empty((lv.vertex_count, 4), np.uint16), np.empty((lv.vertex_count, 4), np.float32)
        check(lib.ssc_model_get_level_skin(self.handle, lv.index, joints.ctypes.data_as(ctypes.POINTER(ctypes.c_uint16)),
                                           weights.ctypes.data_as(c_float_p), lv.vertex_count))
        return joints, weights

    def level_sources(self, level: Union[int, str]):
        """(vertices (N, 4) uint32, weights (N, 4) float32): each level vertex as a weighted sum of body vertices."""
        lv = self.level(level)
        vertices, weights = np.empty((lv.vertex_count, 4), np.uint32), np.empty((lv.vertex_count, 4), np.float32)
        check(lib.ssc_model_get_level_sources(self.handle, lv.index, vertices.ctypes.data_as(c_uint32_p), weights.ctypes.data_as(c_float_p),
                                              lv.vertex_count))
        return vertices, weights

    def level_landmarks(self, level: Union[int, str]):
        """(triangles (L,) uint32, barycentric (L, 3) float32): each landmark on a level's triangles, in landmark order."""
        lv = self.level(level)
        n = self.landmark_count
        triangles, barycentric = np.empty(n, np.uint32), np.empty((n, 3), np.float32)
        check(lib.ssc_model_get_level_landmarks(self.handle, lv.index, triangles.ctypes.data_as(c_uint32_p), barycentric.ctypes.data_as(c_float_p), n))
        return triangles, barycentric

    def sample_shapes(self, count: int, seed: int = 1, truncation: float = 2.5) -> np.ndarray:
        """(count, K) float32 random shapes: standard normal coefficients truncated at ``truncation`` SD."""
        out = np.empty((count, self.shape_count), np.float32)
        check(lib.ssc_model_sample_shapes(self.handle, seed, count, truncation, out.ctypes.data_as(c_float_p), out.size))
        return out

    def synthesize(self, shapes=None, poses=None, translations=None, normals: bool = False, count: Union[int, None] = None,
                   level: Union[int, str] = 0):
        """Many bodies at once on the library's worker threads: (N, V, 3) float32 vertices (and normals
        when asked, as a second array), equal to what a Body gives for the same parameters; with a
        level of detail (index or name, 0 the full mesh), its N vertices, as Body.level_vertices.

        shapes: (N, k) coefficients, k <= K (None: the mean); poses: (N, J, 4) quaternions x y z w
        (None: the rest pose); translations: (N, 3) (None: zero); count: N when nothing else gives it.
        """
        arrays = {}
        for name, value, tail in (("shapes", shapes, None), ("poses", poses, (self.joint_count, 4)), ("translations", translations, (3,))):
            if value is None:
                continue
            a = np.ascontiguousarray(value, dtype=np.float32)
            if a.ndim != (2 if tail is None or len(tail) == 1 else 3) or (tail is not None and a.shape[1:] != tail):
                raise ValueError(f"{name} has shape {a.shape}; expected (N, {'k' if tail is None else ', '.join(map(str, tail))})")
            arrays[name] = a
        counts = {a.shape[0] for a in arrays.values()} | ({count} if count is not None else set())
        if len(counts) != 1:
            raise ValueError("give count, or shapes/poses/translations with one number of bodies" if not counts else
                             f"the arrays disagree on the number of bodies: {sorted(counts)}")
        n = counts.pop()
        lv = self.level(level)
        V = lv.vertex_count
        vertices = np.empty((n, V, 3), np.float32)
        out_normals = np.empty((n, V, 3), np.float32) if normals else None
        desc = BatchDesc()
        lib.ssc_batch_desc_init(ctypes.byref(desc), ctypes.sizeof(BatchDesc))
        desc.body_count = n
        desc.level = lv.index
        if "shapes" in arrays:
            desc.shapes = arrays["shapes"].ctypes.data_as(c_float_p)
            desc.shape_count = arrays["shapes"].shape[1]
        if "poses" in arrays:
            desc.poses = arrays["poses"].ctypes.data_as(c_float_p)
        if "translations" in arrays:
            desc.translations = arrays["translations"].ctypes.data_as(c_float_p)
        desc.vertices = vertices.ctypes.data_as(c_float_p)
        desc.vertices_capacity = n * V
        if normals:
            desc.normals = out_normals.ctypes.data_as(c_float_p)
            desc.normals_capacity = n * V
        check(lib.ssc_model_synthesize_batch(self.handle, ctypes.byref(desc)))
        return (vertices, out_normals) if normals else vertices

    def __repr__(self) -> str:
        return f"<sscape.Model {self.metadata['name']!r}: {self.vertex_count} vertices, {self.shape_count} components, {self.joint_count} joints>"
