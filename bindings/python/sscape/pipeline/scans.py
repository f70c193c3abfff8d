"""A collection's scans: a folder listed as the library lists it (ssc_scan_list: every .ply and
.obj, NAME.lnd beside a scan as its landmarks), or the caller's own list."""
from __future__ import annotations

import ctypes
import os
import warnings
from typing import List, NamedTuple, Optional, Sequence, Tuple, Union

from .._native import lib, need_offline
from ..errors import check


class Scan(NamedTuple):
    name: str                 # the file's stem: names its outputs
    path: str                 # PLY or OBJ
    landmarks: Optional[str]  # a CAESAR .lnd, or None


def list_scans(folder: Union[str, os.PathLike]) -> List[Scan]:
    """The scans of a folder, sorted by name (ssc_scan_list_create): every .ply and .obj file in it
    (not in subfolders, not hidden), each with NAME.lnd beside it when there is one. Keep other
    meshes (true meshes, results) elsewhere, as `sscape simulate --count` does."""
    need_offline("sscape.pipeline")
    handle = ctypes.c_void_p()
    check(lib.ssc_scan_list_create(os.fsencode(folder), ctypes.byref(handle)))
    try:
        out = []
        # File names are bytes to the file system: os.fsdecode keeps any of them (a name that is
        # not UTF-8 round-trips to the same file).
        for i in range(lib.ssc_scan_list_count(handle)):
            name, path, lnd = ctypes.c_char_p(), ctypes.c_char_p(), ctypes.c_char_p()
            check(lib.ssc_scan_list_get(handle, i, ctypes.byref(name), ctypes.byref(path), ctypes.byref(lnd)))
            out.append(Scan(os.fsdecode(name.value), os.fsdecode(path.value), os.fsdecode(lnd.value) or None))
        # Entries that cannot be scans (a link to nothing, a loop of links): left out, said.
        for i in range(lib.ssc_scan_list_skipped_count(handle)):
            path, reason = ctypes.c_char_p(), ctypes.c_char_p()
            check(lib.ssc_scan_list_get_skipped(handle, i, ctypes.byref(path), ctypes.byref(reason)))
            warnings.warn(f"{os.fsdecode(path.value)} left out of the scans: {reason.value.decode(errors='replace')}", stacklevel=2)
        return out
    finally:
        lib.ssc_scan_list_destroy(handle)


def as_scans(scans: Union[str, os.PathLike, Sequence[Union[str, Tuple[str, Optional[str]], Scan]]]) -> List[Scan]:
    """A folder, or a list of scan paths or (scan path, landmarks path) pairs; names must be unique."""
    if isinstance(scans, (str, os.PathLike)):
        out = list_scans(scans)
    else:
        out = []
        for s in scans:
            if isinstance(s, Scan):
                out.append(s)
                continue
            path, lnd = (s, None) if isinstance(s, (str, os.PathLike)) else s
            path = os.fspath(path)
            out.append(Scan(os.path.splitext(os.path.basename(path))[0], path, None if lnd is None else os.fspath(lnd)))
    names = [s.name for s in out]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise ValueError(f"scans named twice (names are file stems): {', '.join(twice)}")
    return out
