"""Lifetime management shared by Grid, Model and Fit."""

import ctypes

from .errors import BrdffitError, Status


class Handle:
    """Owner of one C handle.

    ``close()`` (or leaving a ``with`` block, or garbage collection) destroys
    the handle. A handle that other handles borrow (a grid or model used by a
    fit) is destroyed only when the last borrower is closed, so closing a
    grid while a fit still uses it never leaves the fit with a dangling
    pointer; the closed object itself can no longer be used.
    """

    _kind = "handle"

    def __init__(self, ptr):
        self._ptr = ctypes.c_void_p(ptr) if ptr else None
        self._closed = False
        self._borrowers = 0

    def _destroy_ptr(self, ptr):  # pragma: no cover - overridden
        raise NotImplementedError

    def _destroy(self):
        ptr, self._ptr = self._ptr, None
        if ptr is not None:
            self._destroy_ptr(ptr)

    @property
    def _handle(self):
        """The C pointer; raises if the object was closed."""
        if self._closed or self._ptr is None:
            raise BrdffitError(Status.E_BAD_HANDLE, "%s is closed" % self._kind)
        return self._ptr

    def _acquire(self):
        """Record a borrower; returns the C pointer."""
        ptr = self._handle
        self._borrowers += 1
        return ptr

    def _release(self):
        """Drop a borrower; destroys the handle if it was closed meanwhile."""
        self._borrowers -= 1
        if self._closed and self._borrowers == 0:
            self._destroy()

    @property
    def closed(self):
        """True once :meth:`close` was called."""
        return self._closed

    def close(self):
        """Destroy the C handle (deferred while a fit still borrows it). Idempotent."""
        if self._closed:
            return
        self._closed = True
        if self._borrowers == 0:
            self._destroy()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def __del__(self):
        try:
            self.close()
        except Exception:  # interpreter shutdown: the library may be gone
            pass
