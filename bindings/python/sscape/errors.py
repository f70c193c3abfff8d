"""Errors: every failing C call becomes an SscapeError carrying its status and the library's message."""
from __future__ import annotations

from ._native import lib


class SscapeError(Exception):
    """A call into libsscape failed. ``status`` is the ssc_status (negative), ``status_name`` its name
    (``"SSC_ERROR_INVALID_ARGUMENT"``), and the message is ssc_last_error() of that call."""

    def __init__(self, status: int, message: str):
        self.status = status
        self.status_name = lib.ssc_status_name(status).decode()
        super().__init__(f"{self.status_name}: {message}")


def check(status: int) -> None:
    """Raises SscapeError for a failed status (read on the thread that made the call)."""
    if status != 0:
        message = lib.ssc_last_error()
        # A message names files, whose names need not be UTF-8: their odd bytes shown as \\xe4.
        raise SscapeError(status, message.decode("utf-8", "backslashreplace") if message else "")
