"""The C ABI of libsscape through ctypes: finding the library and declaring each function used.

Every function the package calls is declared here with its argument and result types, in the
order of include/sscape/sscape.h, so that a wrong call fails in Python instead of corrupting memory.
"""
from __future__ import annotations

import ctypes
import ctypes.util
import os
from ctypes import POINTER, c_char_p, c_float, c_int32, c_size_t, c_uint16, c_uint32, c_void_p
from pathlib import Path

#: The C API's major version this package is written for (SSC_VERSION_MAJOR).
ABI_MAJOR = 0

c_float_p = POINTER(c_float)
c_uint32_p = POINTER(c_uint32)


class SegmentInfo(ctypes.Structure):
    _fields_ = [("struct_size", c_uint32), ("name", c_char_p), ("shape_count", c_uint32), ("vertex_count", c_uint32)]


class SliderInfo(ctypes.Structure):
    _fields_ = [("struct_size", c_uint32), ("name", c_char_p), ("unit", c_char_p), ("description", c_char_p),
                ("mean", c_float), ("minimum", c_float), ("maximum", c_float)]


_STATUS = c_int32
_MODEL = c_void_p
_BODY = c_void_p

# name: (result type, argument types)
_DECLARATIONS = {
    "ssc_version": (c_uint32, []),
    "ssc_status_name": (c_char_p, [_STATUS]),
    "ssc_last_error": (c_char_p, []),
    "ssc_model_load_file": (_STATUS, [c_void_p, c_char_p, POINTER(_MODEL)]),
    "ssc_model_load_memory": (_STATUS, [c_void_p, c_void_p, c_size_t, POINTER(_MODEL)]),
    "ssc_model_load_default": (_STATUS, [c_void_p, POINTER(_MODEL)]),
    "ssc_model_release": (None, [_MODEL]),
    "ssc_model_vertex_count": (c_uint32, [_MODEL]),
    "ssc_model_triangle_count": (c_uint32, [_MODEL]),
    "ssc_model_joint_count": (c_uint32, [_MODEL]),
    "ssc_model_shape_count": (c_uint32, [_MODEL]),
    "ssc_model_landmark_count": (c_uint32, [_MODEL]),
    "ssc_model_get_triangles": (_STATUS, [_MODEL, c_uint32_p, c_uint32]),
    "ssc_model_get_joint_parents": (_STATUS, [_MODEL, POINTER(c_int32), c_uint32]),
    "ssc_model_get_joint_name": (_STATUS, [_MODEL, c_uint32, POINTER(c_char_p)]),
    "ssc_model_get_landmark_name": (_STATUS, [_MODEL, c_uint32, POINTER(c_char_p)]),
    "ssc_model_get_shape_stddevs": (_STATUS, [_MODEL, c_float_p, c_uint32]),
    "ssc_model_get_metadata": (_STATUS, [_MODEL, c_int32, POINTER(c_char_p)]),
    "ssc_body_create": (_STATUS, [_MODEL, c_void_p, POINTER(_BODY)]),
    "ssc_body_destroy": (None, [_BODY]),
    "ssc_body_set_shape": (_STATUS, [_BODY, c_float_p, c_uint32]),
    "ssc_body_get_shape": (_STATUS, [_BODY, c_float_p, c_uint32]),
    "ssc_body_set_pose": (_STATUS, [_BODY, c_float_p, c_uint32, c_float_p]),
    "ssc_model_sample_shapes": (_STATUS, [_MODEL, c_uint32, c_uint32, c_float, c_float_p, c_uint32]),
    "ssc_body_get_vertices": (_STATUS, [_BODY, c_float_p, c_uint32, c_size_t]),
    "ssc_body_get_normals": (_STATUS, [_BODY, c_float_p, c_uint32, c_size_t]),
    "ssc_body_get_rest_vertices": (_STATUS, [_BODY, c_float_p, c_uint32, c_size_t]),
    "ssc_body_get_landmarks": (_STATUS, [_BODY, c_float_p, c_uint32, c_size_t]),
    "ssc_body_get_joint_transforms": (_STATUS, [_BODY, c_float_p, c_uint32]),
    "ssc_body_write_file": (_STATUS, [_BODY, c_char_p, c_int32]),
    "ssc_measurement_count": (c_uint32, []),
    "ssc_measurement_get_info": (_STATUS, [c_uint32, POINTER(c_char_p), POINTER(c_int32), POINTER(c_char_p)]),
    "ssc_body_measure": (_STATUS, [_BODY, c_float_p, c_uint32]),
    "ssc_model_slider_count": (c_uint32, [_MODEL]),
    "ssc_model_get_slider_info": (_STATUS, [_MODEL, c_uint32, POINTER(SliderInfo)]),
    "ssc_body_get_sliders": (_STATUS, [_BODY, c_float_p, c_uint32]),
    "ssc_body_set_slider": (_STATUS, [_BODY, c_uint32, c_float]),
    "ssc_model_segment_count": (c_uint32, [_MODEL]),
    "ssc_model_get_segment_info": (_STATUS, [_MODEL, c_uint32, POINTER(SegmentInfo)]),
    "ssc_body_set_segment_shape": (_STATUS, [_BODY, c_uint32, c_float_p, c_uint32]),
    "ssc_body_get_segment_shape": (_STATUS, [_BODY, c_uint32, c_float_p, c_uint32]),
}


def _candidates():
    """Where the library may be: SSCAPE_LIBRARY, beside the package, then the system's search path."""
    env = os.environ.get("SSCAPE_LIBRARY")
    if env:
        yield env
        return
    here = Path(__file__).resolve().parent
    for name in ("libsscape.so", "libsscape.so.0", "libsscape.dylib", "sscape.dll"):
        if (here / name).exists():
            yield str(here / name)
    found = ctypes.util.find_library("sscape")
    if found:
        yield found


def _load():
    tried = []
    for path in _candidates():
        try:
            lib = ctypes.CDLL(path)
        except OSError as e:
            tried.append(f"{path}: {e}")
            continue
        for name, (restype, argtypes) in _DECLARATIONS.items():
            fn = getattr(lib, name)
            fn.restype = restype
            fn.argtypes = argtypes
        major = lib.ssc_version() // 10000
        if major != ABI_MAJOR:
            raise ImportError(f"{path} is libsscape {lib.ssc_version()}: its ABI major version {major} is not this package's {ABI_MAJOR}")
        return lib, path
    raise ImportError("libsscape not found (set SSCAPE_LIBRARY to its path, or install it beside the package or on the "
                      "system's library path)" + ("; tried " + "; ".join(tried) if tried else ""))


lib, library_path = _load()
