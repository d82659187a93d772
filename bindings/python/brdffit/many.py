"""Many fits over one geometry in one call (``brdffit_fit_many()``, many.h).

A per-texel SVBRDF map, or a material library measured on one layout, is
many small fits that differ only in their values. :func:`fit_many` fits
them all with the model and options of one prototype :class:`~brdffit.Fit`
(whose grid gives the geometry; its values are not used), on the
prototype's ``threads``, without a grid or fit per item; the results come
back as numpy arrays. Item ``i``'s result is exactly (bit for bit) that of
a :class:`~brdffit.Fit` with the same options and ``threads=1`` on a grid
made from the same directions and item ``i``'s values, except where two
points of auto's scan tie to rounding (docs/fitting.md, Many fits over one
geometry).

Example::

    proto = brdffit.Fit(geometry_grid, model, threads=2)
    result = brdffit.fit_many(proto, values)   # (n_texels, n_samples, n_channels)
    result.params[result.ok]
"""

import ctypes
from ctypes import CFUNCTYPE, POINTER, Structure, c_double, c_int, c_size_t, c_ubyte, c_uint
from ctypes import c_void_p
from typing import Callable, List, Optional

import numpy as np

from ._lib import as_float64, lib
from .errors import BrdffitError, Status, check, status_name, status_string
from .fit import STOP_REASONS

__all__ = ["fit_many", "ManyResult"]


class _ManyOut(Structure):
    """struct brdffit_many_out (many.h)."""
    _fields_ = [("struct_size", c_size_t), ("status", POINTER(c_int)),
                ("params", POINTER(c_double)), ("std_errors", POINTER(c_double)),
                ("cost", POINTER(c_double)), ("rms", POINTER(c_double)),
                ("ngan", POINTER(c_double)), ("stop", POINTER(c_int)),
                ("iterations", POINTER(c_size_t)), ("warnings", POINTER(c_uint)),
                ("n_run", c_size_t)]


#: brdffit_many_progress_fn
_PROGRESS_FN = CFUNCTYPE(c_int, c_void_p, c_size_t, c_size_t)

lib.brdffit_fit_many.restype = c_int
lib.brdffit_fit_many.argtypes = [c_void_p, c_size_t, POINTER(c_double), POINTER(c_ubyte),
                                 POINTER(_ManyOut), _PROGRESS_FN, c_void_p]


class ManyResult:
    """The results of :func:`fit_many`, one entry per item in input order.

    Attributes:
        status: ``(n,)`` int: ``Status.OK``, or why the item failed
            (``E_NOT_READY``: not run, the call was cancelled).
        params, std_errors: ``(n, n_params)``, NaN rows for failed items.
        cost, rms, ngan: ``(n,)`` error figures (all channels), NaN for failures.
        stop: ``(n,)`` int stop reasons (:data:`~brdffit.STOP_REASONS` index).
        iterations: ``(n,)`` iterations of the final LM run.
        warnings: ``(n,)`` ``brdffit_warning`` bits.
        n_run: items run (all unless cancelled).
    """

    def __init__(self, n: int, n_params: int):
        self.status = np.zeros(n, dtype=np.intc)
        self.params = np.zeros((n, n_params))
        self.std_errors = np.zeros((n, n_params))
        self.cost, self.rms, self.ngan = np.zeros(n), np.zeros(n), np.zeros(n)
        self.stop = np.zeros(n, dtype=np.intc)
        self.iterations = np.zeros(n, dtype=np.uintp)
        self.warnings = np.zeros(n, dtype=np.uintc)
        self.n_run = 0

    def _out(self) -> _ManyOut:
        def p(a, t):
            return a.ctypes.data_as(POINTER(t))
        return _ManyOut(ctypes.sizeof(_ManyOut), p(self.status, c_int), p(self.params, c_double),
                        p(self.std_errors, c_double), p(self.cost, c_double),
                        p(self.rms, c_double), p(self.ngan, c_double), p(self.stop, c_int),
                        p(self.iterations, c_size_t), p(self.warnings, c_uint), 0)

    def __len__(self):
        return self.status.size

    @property
    def ok(self) -> np.ndarray:
        """True where the item was fitted."""
        return self.status == int(Status.OK)

    def stop_reasons(self) -> List[str]:
        """The stop reason of every item by name (``"none"`` for failures)."""
        return [STOP_REASONS[s] if 0 <= s < len(STOP_REASONS) else str(s)
                for s in self.stop.tolist()]

    def warning_names(self, item: int) -> List[str]:
        """The short names of item ``item``'s warnings (e.g. ``"at-bound"``)."""
        bits, bit, out = int(self.warnings[item]), 1, []
        while bits >= bit:
            if bits & bit:
                out.append(lib.brdffit_warning_name(bit).decode())
            bit <<= 1
        return out

    def error(self, item: int) -> Optional[str]:
        """None for a fitted item, else ``"STATUS_NAME: description"``."""
        s = int(self.status[item])
        return None if s == Status.OK else "%s: %s" % (status_name(s), status_string(s))

    def __repr__(self):
        return "<brdffit.ManyResult %d items, %d fitted>" % (len(self), int(self.ok.sum()))


def _values(fit, values, missing):
    ns, nc = fit.grid.sample_count, fit.grid.channel_count
    v = as_float64(values, "values")
    if v.size % (ns * nc) != 0:
        raise ValueError("values of shape %s are not whole items of %d samples x %d channels"
                         % (v.shape, ns, nc))
    v = v.reshape(-1, ns * nc)
    nan = np.isnan(v)
    if missing is not None:
        m = np.asarray(missing, dtype=bool).reshape(v.shape)
        m = m | nan
    else:
        m = nan
    if m.any():
        v = np.where(m, 0.0, v)
        return np.ascontiguousarray(v), np.ascontiguousarray(m, dtype=np.uint8)
    return v, None


def fit_many(fit, values, missing=None,
             progress: Optional[Callable[[int, int], object]] = None) -> ManyResult:
    """Fit many value sets with the model, options and geometry of ``fit``.

    Args:
        fit: the prototype :class:`~brdffit.Fit` (a built-in model; its own
            result is not changed). Its ``threads`` are the threads of the
            call; its iteration callback is not called.
        values: ``(n_items, n_samples, n_channels)`` (any shape of
            ``n_items * n_samples * n_channels`` values), each item's
            samples in the order the prototype's grid was made from (for a
            regular grid the axis order, for a scattered one the order of its
            input arrays). NaN marks a missing value.
        missing: None, or a boolean mask of the same size (True: missing).
        progress: None, or ``progress(done, total)`` called on this thread as
            items finish; a true return value (or an exception, re-raised
            here) cancels the items not yet started.

    Returns:
        A :class:`ManyResult`. A bad item (an infinite value, nothing inside
        the cap, values too large) is reported in ``status``, never raised.

    Raises:
        BrdffitError: when the call itself fails (e.g. out of memory).
        ValueError: a Python model, or values that are not whole items.
    """
    if fit.model._python_eval is not None:
        raise ValueError("fit_many needs a built-in model (a Python model runs one Fit per item)")
    v, m = _values(fit, values, missing)
    n = v.shape[0]
    result = ManyResult(n, fit.param_count)
    out = result._out()
    raised = []

    def on_progress(user, done, total):
        try:
            return 1 if progress(done, total) else 0
        except BaseException as exc:  # re-raised after the call
            raised.append(exc)
            return 1

    cb = _PROGRESS_FN(on_progress) if progress is not None else _PROGRESS_FN()
    with fit._idle() as h:
        fit._running = True
    try:
        status = lib.brdffit_fit_many(
            h, n, v.ctypes.data_as(POINTER(c_double)),
            None if m is None else m.ctypes.data_as(POINTER(c_ubyte)),
            ctypes.byref(out), cb, None)
        msg = lib.brdffit_fit_message(h).decode("utf-8", "replace")
    finally:
        with fit._lock:
            fit._running = False
            closed = fit._closed
        if closed:
            fit._destroy()
    if raised:
        raise raised[0]
    if closed:
        raise BrdffitError(Status.E_BAD_HANDLE, "the fit was closed during fit_many()")
    check(status, message=msg)
    result.n_run = out.n_run
    return result
