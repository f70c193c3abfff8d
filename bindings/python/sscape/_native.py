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


class LevelInfo(ctypes.Structure):
    _fields_ = [("struct_size", c_uint32), ("name", c_char_p), ("vertex_count", c_uint32), ("triangle_count", c_uint32),
                ("uv_count", c_uint32)]


class SliderInfo(ctypes.Structure):
    _fields_ = [("struct_size", c_uint32), ("name", c_char_p), ("unit", c_char_p), ("description", c_char_p),
                ("mean", c_float), ("minimum", c_float), ("maximum", c_float)]


class BatchDesc(ctypes.Structure):
    _fields_ = [("struct_size", c_uint32), ("body_count", c_uint32), ("shapes", c_float_p), ("shape_count", c_uint32),
                ("pose_format", c_int32), ("poses", c_float_p), ("translations", c_float_p), ("vertices", c_float_p),
                ("vertices_capacity", c_size_t), ("normals", c_float_p), ("normals_capacity", c_size_t), ("level", c_uint32)]


class ContextDef(ctypes.Structure):
    _fields_ = [("struct_size", c_uint32), ("worker_count", c_uint32), ("alloc", c_void_p), ("free", c_void_p), ("alloc_user", c_void_p),
                ("log", c_void_p), ("log_user", c_void_p), ("log_level", c_int32), ("max_model_bytes", ctypes.c_uint64)]


class MadeToMeasureDef(ctypes.Structure):
    _fields_ = [("struct_size", c_uint32), ("sex", c_float), ("age", c_float), ("max_iterations", c_uint32), ("tolerance", c_float)]


class FitterDef(ctypes.Structure):
    _fields_ = [("struct_size", c_uint32), ("shape_count", c_uint32), ("fit_scale", c_uint32), ("max_iterations", c_uint32),
                ("landmark_sigma", c_float), ("point_sigma", c_float), ("shape_prior", c_float), ("pose_prior", c_float),
                ("max_points", c_uint32), ("seed", c_uint32), ("joint_limits", c_uint32), ("fit_segments", c_uint32)]


class FitReport(ctypes.Structure):
    _fields_ = [("struct_size", c_uint32), ("iterations", c_uint32), ("converged", c_uint32), ("reserved", c_uint32),
                ("initial_cost", c_float), ("final_cost", c_float), ("landmark_rms", c_float), ("point_mean", c_float),
                ("inlier_fraction", c_float), ("seconds", c_float), ("restarts", c_uint32), ("unexplained_fraction", c_float),
                ("implausible", c_uint32), ("problem", c_uint32), ("failed_frames", c_uint32)]


class FitFrameReport(ctypes.Structure):
    _fields_ = [("struct_size", c_uint32), ("failed", c_uint32), ("left_out", c_uint32), ("problem", c_uint32), ("joint", c_int32),
                ("region", c_int32), ("unexplained_fraction", c_float), ("joint_excess_degrees", c_float),
                ("problem_text", c_char_p), ("unscanned", c_char_p)]


class RegistrationDef(ctypes.Structure):
    _fields_ = [("struct_size", c_uint32), ("start", c_int32), ("schedule", c_int32), ("stiffness", c_float),
                ("landmark_weight", c_float), ("gamma", c_float), ("max_iterations", c_uint32), ("rbf_kernel", c_int32),
                ("rbf_scale", c_float), ("fit_segments", c_uint32)]


class RegistrationQuality(ctypes.Structure):
    _fields_ = [("scan_mean", c_float), ("scan_median", c_float), ("scan_p95", c_float), ("within", c_float * 4)]


class RegistrationReport(ctypes.Structure):
    _fields_ = [("struct_size", c_uint32), ("rounds", c_uint32), ("solves", c_uint32), ("valid_vertices", c_uint32),
                ("seconds", c_float), ("fit_seconds", c_float), ("quality", RegistrationQuality), ("scan_points", c_uint32),
                ("landmarks", c_uint32)]
class ExportDef(ctypes.Structure):
    _fields_ = [("struct_size", c_uint32), ("format", c_int32), ("level", c_uint32), ("morphs", c_int32), ("morph_count", c_uint32)]
class BodyDef(ctypes.Structure):
    _fields_ = [("struct_size", c_uint32), ("reserved", c_uint32)]
class DepthImageDef(ctypes.Structure):
    _fields_ = [("struct_size", c_uint32), ("width", c_uint32), ("height", c_uint32), ("format", c_int32), ("samples", c_void_p),
                ("row_stride", c_size_t), ("mask", c_void_p), ("fx", c_float), ("fy", c_float), ("cx", c_float), ("cy", c_float),
                ("camera_to_world", c_float_p), ("min_depth", c_float), ("max_depth", c_float)]
class JointLimit(ctypes.Structure):
    _fields_ = [("limited", c_uint32), ("frame", c_float * 9), ("lower", c_float * 3), ("upper", c_float * 3)]
# sscape_offline.h
class ScanFileJob(ctypes.Structure):
    _fields_ = [("struct_size", c_uint32), ("scan_path", c_char_p), ("landmarks_path", c_char_p), ("units", c_char_p), ("up", c_char_p),
                ("mesh_path", c_char_p), ("write_report", c_uint32), ("reuse", c_uint32), ("picture_path", c_char_p)]
class FitFileDef(ctypes.Structure):
    _fields_ = [("struct_size", c_uint32), ("path", c_char_p), ("units", c_char_p), ("use_hands", c_uint32), ("units_option", c_char_p)]
class FitFileInfo(ctypes.Structure):
    _fields_ = [("struct_size", c_uint32), ("used", c_uint32), ("left_out", c_uint32), ("unknown", c_uint32), ("span", c_float)]
class BootstrapDef(ctypes.Structure):
    _fields_ = [("struct_size", c_uint32), ("scans_dir", c_char_p), ("out_dir", c_char_p), ("init_model_path", c_char_p),
                ("template_only", c_uint32), ("components", c_uint32), ("posture", c_int32), ("scale", c_uint32),
                ("segment_components", c_uint32), ("segment_band", c_float), ("units", c_char_p), ("up", c_char_p),
                ("decisions_path", c_char_p), ("attributes_path", c_char_p), ("name", c_char_p), ("license", c_char_p),
                ("threads", c_uint32), ("contact_sheet_entries", c_uint32), ("fit_segments", c_uint32),
                ("posture_model_path", c_char_p)]


#: int (*ssc_stage_progress_fn)(void* user, const char* stage, uint32_t done, uint32_t total)
STAGE_PROGRESS_FN = ctypes.CFUNCTYPE(ctypes.c_int, c_void_p, c_char_p, c_uint32, c_uint32)

#: int (*ssc_line_fn)(void* user, const char* line)
LINE_FN = ctypes.CFUNCTYPE(ctypes.c_int, c_void_p, c_char_p)
#: int (*ssc_progress_fn)(void* user, uint32_t iteration, float cost)
PROGRESS_FN = ctypes.CFUNCTYPE(ctypes.c_int, c_void_p, c_uint32, c_float)
FRAME_FN = ctypes.CFUNCTYPE(ctypes.c_int, c_void_p, c_uint32, POINTER(FitFrameReport))
#: void (*ssc_log_fn)(void* user, ssc_log_level level, const char* message)
LOG_FN = ctypes.CFUNCTYPE(None, c_void_p, c_int32, c_char_p)

_STATUS = c_int32
_MODEL = c_void_p
_BODY = c_void_p

# name: (result type, argument types)
_DECLARATIONS = {
    "ssc_version": (c_uint32, []),
    "ssc_status_name": (c_char_p, [_STATUS]),
    "ssc_last_error": (c_char_p, []),
    "ssc_context_def_init": (None, [POINTER(ContextDef), c_size_t]),
    "ssc_context_create": (_STATUS, [POINTER(ContextDef), POINTER(c_void_p)]),
    "ssc_context_destroy": (None, [c_void_p]),
    "ssc_model_load_file": (_STATUS, [c_void_p, c_char_p, POINTER(_MODEL)]),
    "ssc_model_load_memory": (_STATUS, [c_void_p, c_void_p, c_size_t, POINTER(_MODEL)]),
    "ssc_model_load_default": (_STATUS, [c_void_p, POINTER(_MODEL)]),
    "ssc_default_model_file": (_STATUS, [POINTER(c_void_p), POINTER(c_size_t)]),
    "ssc_model_release": (None, [_MODEL]),
    "ssc_model_vertex_count": (c_uint32, [_MODEL]),
    "ssc_model_triangle_count": (c_uint32, [_MODEL]),
    "ssc_model_joint_count": (c_uint32, [_MODEL]),
    "ssc_model_shape_count": (c_uint32, [_MODEL]),
    "ssc_model_landmark_count": (c_uint32, [_MODEL]),
    "ssc_model_get_triangles": (_STATUS, [_MODEL, c_uint32_p, c_uint32]),
    "ssc_model_quad_count": (c_uint32, [_MODEL]),
    "ssc_model_uv_count": (c_uint32, [_MODEL]),
    "ssc_model_vertex_set_count": (c_uint32, [_MODEL]),
    "ssc_model_get_quads": (_STATUS, [_MODEL, c_uint32_p, c_uint32]),
    "ssc_model_get_uvs": (_STATUS, [_MODEL, c_float_p, c_uint32]),
    "ssc_model_get_triangle_uvs": (_STATUS, [_MODEL, c_uint32_p, c_uint32]),
    "ssc_model_get_vertex_set": (_STATUS, [_MODEL, c_uint32, POINTER(c_char_p), c_uint32_p]),
    "ssc_model_get_vertex_set_indices": (_STATUS, [_MODEL, c_uint32, c_uint32_p, c_uint32]),
    "ssc_model_get_joint_parents": (_STATUS, [_MODEL, POINTER(c_int32), c_uint32]),
    "ssc_model_get_joint_name": (_STATUS, [_MODEL, c_uint32, POINTER(c_char_p)]),
    "ssc_model_get_landmark_name": (_STATUS, [_MODEL, c_uint32, POINTER(c_char_p)]),
    "ssc_model_get_shape_stddevs": (_STATUS, [_MODEL, c_float_p, c_uint32]),
    "ssc_model_get_metadata": (_STATUS, [_MODEL, c_int32, POINTER(c_char_p)]),
    "ssc_body_create": (_STATUS, [_MODEL, c_void_p, POINTER(_BODY)]),  # def: a BodyDef by reference
    "ssc_body_destroy": (None, [_BODY]),
    "ssc_body_set_shape": (_STATUS, [_BODY, c_float_p, c_uint32]),
    "ssc_body_get_shape": (_STATUS, [_BODY, c_float_p, c_uint32]),
    "ssc_body_set_pose": (_STATUS, [_BODY, c_float_p, c_uint32, c_float_p]),
    "ssc_model_sample_shapes": (_STATUS, [_MODEL, c_uint32, c_uint32, c_float, c_float_p, c_uint32]),
    "ssc_batch_desc_init": (None, [POINTER(BatchDesc), c_size_t]),
    "ssc_model_synthesize_batch": (_STATUS, [_MODEL, POINTER(BatchDesc)]),
    "ssc_body_get_vertices": (_STATUS, [_BODY, c_float_p, c_uint32, c_size_t]),
    "ssc_body_get_normals": (_STATUS, [_BODY, c_float_p, c_uint32, c_size_t]),
    "ssc_body_get_rest_vertices": (_STATUS, [_BODY, c_float_p, c_uint32, c_size_t]),
    "ssc_body_get_landmarks": (_STATUS, [_BODY, c_float_p, c_uint32, c_size_t]),
    "ssc_body_get_joint_transforms": (_STATUS, [_BODY, c_float_p, c_uint32]),
    "ssc_body_get_inverse_bind_matrices": (_STATUS, [_BODY, c_float_p, c_uint32]),
    "ssc_body_get_skinning_matrices": (_STATUS, [_BODY, c_float_p, c_uint32]),
    "ssc_model_get_skin": (_STATUS, [_MODEL, POINTER(c_uint16), c_float_p, c_uint32]),
    "ssc_body_write_file": (_STATUS, [_BODY, c_char_p, c_int32]),
    "ssc_fitter_def_init": (None, [POINTER(FitterDef), c_size_t]),
    "ssc_fitter_create": (_STATUS, [_MODEL, POINTER(FitterDef), POINTER(c_void_p)]),
    "ssc_fitter_destroy": (None, [c_void_p]),
    "ssc_fitter_clear": (_STATUS, [c_void_p]),
    "ssc_fitter_frame_count": (c_uint32, [c_void_p]),
    "ssc_fitter_add_landmarks_by_name": (_STATUS, [c_void_p, c_uint32, POINTER(c_char_p), c_float_p, c_float_p, c_uint32]),
    "ssc_fitter_add_points": (_STATUS, [c_void_p, c_uint32, c_float_p, c_float_p, c_float_p, c_uint32, c_size_t]),
    "ssc_fitter_solve": (_STATUS, [c_void_p, PROGRESS_FN, c_void_p, POINTER(FitReport)]),
    "ssc_fitter_get_frame_report": (_STATUS, [c_void_p, c_uint32, POINTER(FitFrameReport)]),
    "ssc_fitter_set_frame_callback": (_STATUS, [c_void_p, FRAME_FN, c_void_p]),
    "ssc_fitter_get_shape": (_STATUS, [c_void_p, c_float_p, c_uint32]),
    "ssc_fitter_get_segment_shape": (_STATUS, [c_void_p, c_uint32, c_float_p, c_uint32]),
    "ssc_fitter_get_pose": (_STATUS, [c_void_p, c_uint32, c_float_p, c_uint32, c_float_p, c_float_p]),
    "ssc_fitter_get_vertices": (_STATUS, [c_void_p, c_uint32, c_float_p, c_uint32, c_size_t]),
    "ssc_fitter_get_point_residuals": (_STATUS, [c_void_p, c_uint32, c_float_p, c_uint32]),
    "ssc_fitter_point_count": (c_uint32, [c_void_p, c_uint32]),
    "ssc_registration_def_init": (None, [POINTER(RegistrationDef), c_size_t]),
    "ssc_registration_create": (_STATUS, [_MODEL, POINTER(RegistrationDef), POINTER(c_void_p)]),
    "ssc_registration_destroy": (None, [c_void_p]),
    "ssc_registration_set_scan": (_STATUS, [c_void_p, c_float_p, c_float_p, c_uint32, c_size_t, c_uint32_p, c_uint32]),
    "ssc_registration_set_landmarks_by_name": (_STATUS, [c_void_p, POINTER(c_char_p), c_float_p, c_uint32]),
    "ssc_registration_run": (_STATUS, [c_void_p, STAGE_PROGRESS_FN, c_void_p, POINTER(RegistrationReport)]),
    "ssc_registration_get_vertices": (_STATUS, [c_void_p, c_float_p, c_uint32, c_size_t]),
    "ssc_registration_get_valid": (_STATUS, [c_void_p, POINTER(ctypes.c_uint8), c_uint32]),
    "ssc_registration_get_vertex_distances": (_STATUS, [c_void_p, c_float_p, c_uint32]),
    "ssc_registration_get_fit": (_STATUS, [c_void_p, c_float_p, c_uint32, c_float_p, c_uint32, c_float_p, c_float_p]),
    "ssc_registration_get_fit_segment_shape": (_STATUS, [c_void_p, c_uint32, c_float_p, c_uint32]),
    "ssc_registration_region_count": (c_uint32, [c_void_p]),
    "ssc_registration_get_region": (_STATUS, [c_void_p, c_uint32, POINTER(c_char_p), POINTER(RegistrationQuality)]),
    "ssc_named_pose_count": (c_uint32, []),
    "ssc_named_pose_get_info": (_STATUS, [c_uint32, POINTER(c_char_p), POINTER(c_char_p)]),
    "ssc_model_get_named_pose": (_STATUS, [_MODEL, c_char_p, c_float_p, c_uint32]),
    "ssc_model_close_hands": (_STATUS, [_MODEL, c_float, c_float, c_float_p, c_uint32]),
    "ssc_body_set_pose_limited": (_STATUS, [_BODY, c_float_p, c_uint32, c_float_p, c_int32, c_uint32_p]),
    "ssc_measurement_count": (c_uint32, []),
    "ssc_measurement_get_info": (_STATUS, [c_uint32, POINTER(c_char_p), POINTER(c_int32), POINTER(c_char_p)]),
    "ssc_body_measure": (_STATUS, [_BODY, c_float_p, c_uint32]),
    "ssc_model_slider_count": (c_uint32, [_MODEL]),
    "ssc_model_get_slider_info": (_STATUS, [_MODEL, c_uint32, POINTER(SliderInfo)]),
    "ssc_body_get_sliders": (_STATUS, [_BODY, c_float_p, c_uint32]),
    "ssc_body_set_slider": (_STATUS, [_BODY, c_uint32, c_float]),
    "ssc_measurement_find": (_STATUS, [c_char_p, c_uint32_p]),
    "ssc_made_to_measure_def_init": (None, [POINTER(MadeToMeasureDef), c_size_t]),
    "ssc_body_make_to_measure": (_STATUS, [_BODY, c_uint32_p, c_float_p, c_uint32, POINTER(MadeToMeasureDef), c_float_p, c_uint32,
                                           c_uint32_p]),
    "ssc_model_segment_count": (c_uint32, [_MODEL]),
    "ssc_model_get_segment_info": (_STATUS, [_MODEL, c_uint32, POINTER(SegmentInfo)]),
    "ssc_body_set_segment_shape": (_STATUS, [_BODY, c_uint32, c_float_p, c_uint32]),
    "ssc_body_get_segment_shape": (_STATUS, [_BODY, c_uint32, c_float_p, c_uint32]),
    "ssc_model_get_joint_limit": (_STATUS, [_MODEL, c_uint32, POINTER(JointLimit)]),
    "ssc_body_def_init": (None, [POINTER(BodyDef), c_size_t]),
    "ssc_model_retain": (None, [_MODEL]),  # declared for completeness: Python's references keep models alive
    "ssc_model_find_joint": (_STATUS, [_MODEL, c_char_p, c_uint32_p]),
    "ssc_model_find_landmark": (_STATUS, [_MODEL, c_char_p, c_uint32_p]),
    "ssc_model_find_slider": (_STATUS, [_MODEL, c_char_p, c_uint32_p]),
    "ssc_model_find_segment": (_STATUS, [_MODEL, c_char_p, c_uint32_p]),
    "ssc_body_measure_by_name": (_STATUS, [_BODY, c_char_p, c_float_p]),
    "ssc_fitter_add_landmarks": (_STATUS, [c_void_p, c_uint32, c_uint32_p, c_float_p, c_float_p, c_uint32]),
    "ssc_depth_image_def_init": (None, [POINTER(DepthImageDef), c_size_t]),
    "ssc_fitter_add_depth_image": (_STATUS, [c_void_p, c_uint32, POINTER(DepthImageDef), c_uint32_p]),
    "ssc_model_get_landmark_positions": (_STATUS, [_MODEL, c_float_p, c_uint32, c_size_t]),
    "ssc_model_get_segment_vertices": (_STATUS, [_MODEL, c_uint32, c_uint32_p, c_float_p, c_uint32]),
    "ssc_body_set_pose_axis_angle": (_STATUS, [_BODY, c_float_p, c_uint32, c_float_p]),
    "ssc_rotation_from_axis_angle": (_STATUS, [c_float_p, c_float_p]),
    "ssc_body_set_sliders": (_STATUS, [_BODY, c_float_p, c_uint32]),
    "ssc_model_level_count": (c_uint32, [_MODEL]),
    "ssc_model_get_level_info": (_STATUS, [_MODEL, c_uint32, POINTER(LevelInfo)]),
    "ssc_model_get_level_triangles": (_STATUS, [_MODEL, c_uint32, c_uint32_p, c_uint32]),
    "ssc_model_get_level_uvs": (_STATUS, [_MODEL, c_uint32, c_float_p, c_uint32]),
    "ssc_model_get_level_triangle_uvs": (_STATUS, [_MODEL, c_uint32, c_uint32_p, c_uint32]),
    "ssc_model_get_level_skin": (_STATUS, [_MODEL, c_uint32, POINTER(ctypes.c_uint16), c_float_p, c_uint32]),
    "ssc_model_get_level_sources": (_STATUS, [_MODEL, c_uint32, c_uint32_p, c_float_p, c_uint32]),
    "ssc_model_get_level_landmarks": (_STATUS, [_MODEL, c_uint32, c_uint32_p, c_float_p, c_uint32]),
    "ssc_body_get_level_vertices": (_STATUS, [_BODY, c_uint32, c_float_p, c_uint32, c_size_t]),
    "ssc_body_get_level_normals": (_STATUS, [_BODY, c_uint32, c_float_p, c_uint32, c_size_t]),
    "ssc_body_get_level_rest_vertices": (_STATUS, [_BODY, c_uint32, c_float_p, c_uint32, c_size_t]),
    "ssc_body_write_level_file": (_STATUS, [_BODY, c_uint32, c_char_p, c_int32]),
    "ssc_export_def_init": (None, [POINTER(ExportDef), c_size_t]),
    "ssc_body_export": (_STATUS, [_BODY, c_char_p, POINTER(ExportDef)]),
}

# The offline tools (sscape_offline.h): in libsscape_offline.so only.
_OFFLINE_DECLARATIONS = {
    "ssc_scan_list_create": (_STATUS, [c_char_p, POINTER(c_void_p)]),
    "ssc_scan_list_destroy": (None, [c_void_p]),
    "ssc_scan_list_count": (c_uint32, [c_void_p]),
    "ssc_scan_list_get": (_STATUS, [c_void_p, c_uint32, POINTER(c_char_p), POINTER(c_char_p), POINTER(c_char_p)]),
    "ssc_scan_list_skipped_count": (c_uint32, [c_void_p]),
    "ssc_scan_list_get_skipped": (_STATUS, [c_void_p, c_uint32, POINTER(c_char_p), POINTER(c_char_p)]),
    "ssc_scan_file_job_init": (None, [POINTER(ScanFileJob), c_size_t]),
    "ssc_registration_run_file": (_STATUS, [c_void_p, POINTER(ScanFileJob), STAGE_PROGRESS_FN, c_void_p, POINTER(RegistrationReport),
                                            c_uint32_p]),
    "ssc_fit_file_def_init": (None, [POINTER(FitFileDef), c_size_t]),
    "ssc_fitter_add_points_file": (_STATUS, [c_void_p, c_uint32, POINTER(FitFileDef), POINTER(FitFileInfo)]),
    "ssc_fitter_add_landmarks_file": (_STATUS, [c_void_p, c_uint32, POINTER(FitFileDef), POINTER(FitFileInfo)]),
    "ssc_fitter_write_params": (_STATUS, [c_void_p, POINTER(FitReport), c_char_p]),
    "ssc_model_get_digest": (_STATUS, [c_void_p, POINTER(c_char_p)]),
    "ssc_bootstrap_def_init": (None, [POINTER(BootstrapDef), c_size_t]),
    "ssc_bootstrap_create": (_STATUS, [c_void_p, POINTER(BootstrapDef), POINTER(c_void_p)]),
    "ssc_bootstrap_destroy": (None, [c_void_p]),
    "ssc_bootstrap_scan_count": (c_uint32, [c_void_p]),
    "ssc_bootstrap_get_scan": (_STATUS, [c_void_p, c_uint32, POINTER(c_char_p), POINTER(c_char_p), POINTER(c_char_p)]),
    "ssc_bootstrap_prepare": (_STATUS, [c_void_p]),
    "ssc_bootstrap_get_job": (_STATUS, [c_void_p, c_uint32, c_uint32, POINTER(ScanFileJob), POINTER(c_char_p)]),
    "ssc_bootstrap_run": (_STATUS, [c_void_p, c_uint32, LINE_FN, c_void_p]),
}


def _candidates():
    """Where the library may be: SSCAPE_LIBRARY, beside the package, then the system's search path;
    libsscape_offline (the whole C API with the offline tools) before libsscape (the runtime)."""
    env = os.environ.get("SSCAPE_LIBRARY")
    if env:
        yield env
        return
    here = Path(__file__).resolve().parent
    for name in ("libsscape_offline.so", "libsscape.so", "libsscape.so.0", "libsscape.dylib", "sscape.dll"):
        if (here / name).exists():
            yield str(here / name)
    for name in ("sscape_offline", "sscape"):
        found = ctypes.util.find_library(name)
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
        offline = hasattr(lib, "ssc_bootstrap_create")
        for name, (restype, argtypes) in list(_DECLARATIONS.items()) + (list(_OFFLINE_DECLARATIONS.items()) if offline else []):
            fn = getattr(lib, name)
            fn.restype = restype
            fn.argtypes = argtypes
        major = lib.ssc_version() // 10000
        if major != ABI_MAJOR:
            raise ImportError(f"{path} is libsscape {lib.ssc_version()}: its ABI major version {major} is not this package's {ABI_MAJOR}")
        return lib, path, offline
    raise ImportError("libsscape not found (set SSCAPE_LIBRARY to its path, or install it beside the package or on the "
                      "system's library path)" + ("; tried " + "; ".join(tried) if tried else ""))


lib, library_path, has_offline = _load()


def need_offline(what: str) -> None:
    """Raises a clear error when the loaded library lacks the offline tools."""
    if not has_offline:
        raise RuntimeError(f"{what} needs libsscape_offline (the offline tools); {library_path} is the runtime alone: "
                           "point SSCAPE_LIBRARY at build/sdk/libsscape_offline.so or install the package from a full build")
