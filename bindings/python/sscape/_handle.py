"""What every object over a C handle shares: the handle, its release at close(), at the end of a
``with`` block or at garbage collection (weakref.finalize), and a clear error once released."""
from __future__ import annotations

import ctypes
import weakref
from typing import Callable, List


class Handle:
    _what = "object"

    def _own(self, handle: ctypes.c_void_p, release: Callable) -> None:
        self._handle = handle
        self._finalizer = weakref.finalize(self, release, handle)

    @property
    def handle(self) -> ctypes.c_void_p:
        if not self._finalizer.alive:
            raise ValueError(f"the {self._what} is closed")
        return self._handle

    def close(self) -> None:
        """Releases the handle now (idempotent)."""
        self._finalizer()

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def progress_callback(function_type, progress, convert):
    """A C progress callback calling progress(*convert(args)): non-zero (cancel) when it returns True.
    An exception in it cancels the call and is kept in the returned list, for the caller to raise
    after the C call returns: never across the C boundary."""
    errors: List[BaseException] = []
    if progress is None:
        return function_type(), errors

    def call(_user, *args):
        try:
            return 1 if progress(*convert(*args)) else 0
        except BaseException as e:
            errors.append(e)
            return 1

    return function_type(call), errors
