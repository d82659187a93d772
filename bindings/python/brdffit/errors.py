"""Status codes and the exception every failing call raises."""

import enum

from ._lib import Error, lib


class Status(enum.IntEnum):
    """The C library's status codes (``brdffit_status``); values are fixed forever."""
    OK = 0
    E_INVALID_ARGUMENT = 1
    E_OUT_OF_MEMORY = 2
    E_IO = 3
    E_PARSE = 4
    E_RANGE = 5
    E_INCOMPLETE_GRID = 6
    E_DUPLICATE = 7
    E_FORMAT = 8
    E_TOO_LARGE = 9
    E_UNSUPPORTED = 10
    E_MODEL_FAILED = 11
    E_NONFINITE = 12
    E_NO_DATA = 13
    E_CALLBACK_FAILED = 14
    E_BAD_HANDLE = 15
    E_NOT_FOUND = 16
    E_NUMERICAL = 17
    E_NOT_READY = 18


def status_name(status):
    """The symbolic name of a status code, such as ``"BRDFFIT_E_PARSE"``."""
    return lib.brdffit_status_name(int(status)).decode()


def status_string(status):
    """The library's short description of a status code, such as ``"malformed input"``."""
    return lib.brdffit_status_string(int(status)).decode()


class BrdffitError(Exception):
    """A call into libbrdffit failed.

    Attributes:
        status: the C status code (an int; compare with :class:`Status`).
        status_name: its symbolic name, e.g. ``"BRDFFIT_E_PARSE"``.
        message: the library's detailed message (what went wrong and where),
            or the status description when the call gives no message.
    """

    def __init__(self, status, message=None):
        self.status = int(status)
        self.status_name = status_name(self.status)
        self.message = message if message else status_string(self.status)
        super().__init__("%s: %s" % (self.status_name, self.message))


def new_error():
    """A fresh ``brdffit_error`` record for a call that fills one in."""
    return Error()


def check(status, err=None, message=None):
    """Raise :class:`BrdffitError` unless ``status`` is ``BRDFFIT_OK``.

    The message is taken from ``err`` (a ``brdffit_error`` the call filled
    in) or from ``message``, else the status description is used.
    """
    if status == Status.OK:
        return
    if err is not None and err.status == status:
        message = err.message.decode("utf-8", "replace")
    raise BrdffitError(status, message)
