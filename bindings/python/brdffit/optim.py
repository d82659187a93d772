"""The general Levenberg-Marquardt optimizer (``brdffit_optimizer``, optim.h).

:class:`Optimizer` minimises ``cost(x) = sum_i r_i(x)^2`` (no factor 1/2)
over a parameter vector, given residuals and their Jacobian (residual form)
or J^T J, J^T r and the cost directly (normal form); docs/optimizer.md
describes the algorithm. Its damping policy is a
:class:`~brdffit.DampingPolicy` (brdffit/damping.py).
"""

import ctypes
from typing import Callable, Optional, Sequence, Tuple, Union

import numpy as np

from . import _lib
from ._handle import Handle
from ._lib import dptr, lib
from .damping import DampingPolicy, as_policy
from .errors import BrdffitError, Status, check, new_error
from .fit import STOP_REASONS, IterationInfo

__all__ = ["Optimizer"]

# brdffit_optim_setting values
_SETTINGS = {"gtol": 1, "xtol": 2, "ftol": 3, "max_iterations": 4, "max_evaluations": 5,
             "scaling": 6, "diag_floor": 7}


def _setting_property(name: str, doc: str, cast=float):
    key = _SETTINGS[name]

    def getter(self):
        v = ctypes.c_double()
        self._check(lib.brdffit_optimizer_get(self._handle, key, ctypes.byref(v)))
        return cast(v.value)

    def setter(self, value):
        self._check(lib.brdffit_optimizer_set(self._handle, key, float(value)))

    return property(getter, setter, doc=doc)


ResidualFn = Callable[[np.ndarray, bool], Tuple[np.ndarray, Optional[np.ndarray]]]
NormalFn = Callable[[np.ndarray, bool],
                    Tuple[float, Optional[np.ndarray], Optional[np.ndarray]]]


class Optimizer(Handle):
    """The general Levenberg-Marquardt optimizer (``brdffit_optimizer``).

    Give the problem with :meth:`set_residuals` or :meth:`set_normal` (or
    the ``residuals``/``normal`` and ``n_rows`` arguments), then call
    :meth:`run` with a start vector. Settings (properties, or keyword
    arguments): ``gtol``, ``xtol``, ``ftol``, ``max_iterations``,
    ``max_evaluations``, ``scaling`` (``"marquardt"`` or ``"levenberg"``),
    ``diag_floor``; see ``brdffit_optim_setting`` in optim.h. Also
    ``damping`` (a policy or its name), ``bounds`` (``(lower, upper)``) and
    ``fixed`` (a boolean mask).

    An exception raised by the problem function, the callback or a Python
    damping policy cancels the run and is re-raised by :meth:`run`. To mark
    a point that cannot be evaluated, return NaN residuals (a rejected step).
    Not thread-safe, except :meth:`cancel`.

    Example::

        t = np.linspace(0, 1, 20); y = 2 * np.exp(-3 * t)
        def f(x, jacobian):
            e = np.exp(-x[1] * t)
            r = x[0] * e - y
            return r, (np.stack([e, -x[0] * t * e], axis=1) if jacobian else None)
        opt = Optimizer(2, residuals=f, n_rows=t.size)
        x = opt.run([1.0, 1.0])        # about [2, 3]
    """

    _kind = "optimizer"

    def __init__(self, n_params: int, residuals: Optional[ResidualFn] = None,
                 normal: Optional[NormalFn] = None, n_rows: Optional[int] = None, **settings):
        super().__init__(None)
        out = ctypes.c_void_p()
        err = new_error()
        check(lib.brdffit_optimizer_create(ctypes.byref(out), int(n_params), None,
                                           ctypes.byref(err)), err)
        self._ptr = ctypes.c_void_p(out.value)
        self._p = int(n_params)
        self._problem = self._callback = self._damping = None
        self._error = None
        if residuals is not None and normal is not None:
            raise ValueError("give residuals or normal, not both")
        if residuals is not None or normal is not None:
            if n_rows is None:
                raise ValueError("n_rows is needed with a problem function")
            (self.set_residuals if residuals is not None else self.set_normal)(
                residuals if residuals is not None else normal, n_rows)
        if "bounds" in settings:
            self.set_bounds(*settings.pop("bounds"))
        for name in ("damping", "fixed", "callback"):
            if name in settings:
                getattr(self, "set_" + name)(settings.pop(name))
        for name, value in settings.items():
            if name not in _SETTINGS:
                raise TypeError("unknown optimizer setting %r" % name)
            setattr(self, name, value)

    def _destroy_ptr(self, ptr):
        lib.brdffit_optimizer_destroy(ptr)

    def _check(self, status):
        if status != Status.OK:
            check(status, message=lib.brdffit_optimizer_message(self._handle).decode(
                "utf-8", "replace"))

    def _fail(self, exc):
        if self._error is None:
            self._error = exc
        lib.brdffit_optimizer_cancel(self._handle)
        return Status.E_CALLBACK_FAILED

    @property
    def param_count(self) -> int:
        """Number of parameters."""
        return self._p

    gtol = _setting_property("gtol", "Gradient tolerance (cosine test); default 1e-13.")
    xtol = _setting_property("xtol", "Relative step tolerance; default 1e-10.")
    ftol = _setting_property("ftol", "Relative cost-reduction tolerance; default 1e-15.")
    max_iterations = _setting_property("max_iterations", "Iteration limit; default 10000.", int)
    max_evaluations = _setting_property("max_evaluations", "Evaluation limit; default 24000.",
                                        int)
    diag_floor = _setting_property(
        "diag_floor",
        "Floor of Marquardt's scaling without the scale memory, relative to the "
        "largest value of the entry's own column; default 1e-12.")

    @property
    def scaling(self) -> str:
        """``"marquardt"`` (D = diag(J^T J), default) or ``"levenberg"``."""
        v = ctypes.c_double()
        self._check(lib.brdffit_optimizer_get(self._handle, _SETTINGS["scaling"],
                                              ctypes.byref(v)))
        return "marquardt" if v.value else "levenberg"

    @scaling.setter
    def scaling(self, value: str):
        if value not in ("marquardt", "levenberg"):
            raise ValueError("scaling must be 'marquardt' or 'levenberg'")
        self._check(lib.brdffit_optimizer_set(self._handle, _SETTINGS["scaling"],
                                              1.0 if value == "marquardt" else 0.0))

    # ---- the problem --------------------------------------------------------

    def set_residuals(self, fn: ResidualFn, n_rows: int) -> None:
        """Residual form: ``fn(x, jacobian) -> (r, J)`` with ``r`` of
        ``n_rows`` values and, when ``jacobian`` is true, ``J`` of shape
        ``(n_rows, n_params)`` (else None)."""
        p, m = self._p, int(n_rows)

        def trampoline(x_p, r_p, jac_p, user):
            try:
                x = np.ctypeslib.as_array(x_p, (p,)).copy()
                r, jac = fn(x, bool(jac_p))
                np.ctypeslib.as_array(r_p, (m,))[:] = np.reshape(r, m)
                if jac_p:
                    np.ctypeslib.as_array(jac_p, (m, p))[:] = np.reshape(jac, (m, p))
                return Status.OK
            except BaseException as exc:
                return self._fail(exc)

        c_fn = _lib.RESIDUAL_FN(trampoline)
        self._check(lib.brdffit_optimizer_set_residuals(self._handle, m, c_fn, None))
        self._problem = c_fn

    def set_normal(self, fn: NormalFn, n_rows: int) -> None:
        """Normal form: ``fn(x, derivatives) -> (cost, JtJ, Jtr)``; ``JtJ``
        of shape ``(n_params, n_params)`` and ``Jtr`` of ``n_params`` values
        when ``derivatives`` is true (else None). ``n_rows`` is the number of
        residuals the sums run over (for the covariance)."""
        p = self._p

        def trampoline(x_p, cost_p, jtj_p, jtr_p, user):
            try:
                x = np.ctypeslib.as_array(x_p, (p,)).copy()
                cost, jtj, jtr = fn(x, bool(jtj_p))
                cost_p[0] = float(cost)
                if jtj_p:
                    np.ctypeslib.as_array(jtj_p, (p, p))[:] = np.reshape(jtj, (p, p))
                    np.ctypeslib.as_array(jtr_p, (p,))[:] = np.reshape(jtr, p)
                return Status.OK
            except BaseException as exc:
                return self._fail(exc)

        c_fn = _lib.NORMAL_FN(trampoline)
        self._check(lib.brdffit_optimizer_set_normal(self._handle, int(n_rows), c_fn, None))
        self._problem = c_fn

    def set_damping(self, policy: Union[str, DampingPolicy, None]) -> None:
        """Use a damping policy (a :class:`DampingPolicy` or a built-in name;
        None restores the default, ``"nielsen"``)."""
        policy = as_policy(policy)
        self._check(lib.brdffit_optimizer_set_damping(
            self._handle, None if policy is None else policy._c_policy()))
        self._damping = policy

    def set_bounds(self, lower: Optional[Sequence[float]] = None,
                   upper: Optional[Sequence[float]] = None) -> None:
        """Box bounds (None: unbounded on that side; +-inf allowed)."""
        lo = None if lower is None else self._vec(lower, "lower")
        hi = None if upper is None else self._vec(upper, "upper")
        self._check(lib.brdffit_optimizer_set_bounds(self._handle, dptr(lo), dptr(hi)))

    def set_fixed(self, mask: Optional[Sequence[bool]]) -> None:
        """Hold the parameters where ``mask`` is true at their start value
        (None frees all)."""
        m = None
        if mask is not None:
            m = np.ascontiguousarray(np.asarray(mask, dtype=bool), dtype=np.uint8)
            if m.shape != (self._p,):
                raise ValueError("mask must have %d entries, got shape %s" % (self._p, m.shape))
        self._check(lib.brdffit_optimizer_set_fixed(self._handle, _lib.bptr(m)))

    def set_callback(self, fn: Optional[Callable]) -> None:
        """Call ``fn(info)`` after every iteration with an
        :class:`~brdffit.IterationInfo`; a true result stops the run
        (stop reason ``"callback"``). None removes it."""
        if fn is None:
            self._check(lib.brdffit_optimizer_set_callback(self._handle, _lib.ITERATION_FN(),
                                                           None))
            self._callback = None
            return

        def trampoline(info_p, user):
            try:
                i = info_p.contents
                x = np.ctypeslib.as_array(i.x, (i.n_params,)).copy()
                return 1 if fn(IterationInfo(i.iteration, bool(i.accepted), i.cost,
                                             i.lambda_, i.rho, x)) else 0
            except BaseException as exc:
                self._fail(exc)
                return 1

        c_fn = _lib.ITERATION_FN(trampoline)
        self._check(lib.brdffit_optimizer_set_callback(self._handle, c_fn, None))
        self._callback = c_fn

    def cancel(self) -> None:
        """Ask a run to stop (from any thread); stop reason ``"cancelled"``."""
        lib.brdffit_optimizer_cancel(self._handle)

    def _vec(self, values, what):
        v = np.ascontiguousarray(values, dtype=np.float64).reshape(-1)
        if v.size != self._p:
            raise ValueError("%s has %d entries, expected %d" % (what, v.size, self._p))
        return v.copy()

    # ---- running and results -------------------------------------------------

    def run(self, x0: Sequence[float]) -> np.ndarray:
        """Run from ``x0``; returns the best point found (also when a limit
        or a cancel ended the run; see :attr:`stop_reason`).

        Raises:
            BrdffitError: ``E_NOT_READY`` without a problem, ``E_NONFINITE``
                for a NaN start or NaN at the start point,
                ``E_CALLBACK_FAILED`` when the problem fails at the start.
            Exception: whatever the problem function, the callback or a
                Python damping policy raised (then the run was cancelled).
        """
        h = self._handle
        x = self._vec(x0, "x0")
        self._error = None
        policy = self._damping
        if policy is not None:
            policy._on_error = self.cancel
        status = lib.brdffit_optimizer_run(h, dptr(x))
        msg = lib.brdffit_optimizer_message(h).decode("utf-8", "replace")
        error, self._error = self._error, None
        if policy is not None:
            error = error or policy._take_error()
        if error is not None:
            if status != Status.OK:
                raise error from BrdffitError(status, msg)
            raise error
        check(status, message=msg)
        return x

    @property
    def stop_reason(self) -> str:
        """Why the last run ended (``"none"`` before a run)."""
        r = lib.brdffit_optimizer_stop_reason(self._handle)
        return STOP_REASONS[r] if 0 <= r < len(STOP_REASONS) else "unknown"

    @property
    def initial_cost(self) -> float:
        """Cost at the start point of the last run (NaN before a run)."""
        return lib.brdffit_optimizer_initial_cost(self._handle)

    @property
    def final_cost(self) -> float:
        """Cost at the returned point of the last run (NaN before a run)."""
        return lib.brdffit_optimizer_final_cost(self._handle)

    @property
    def iterations(self) -> int:
        """Accepted plus rejected steps of the last run."""
        return lib.brdffit_optimizer_iterations(self._handle)

    @property
    def evaluations(self) -> int:
        """Problem evaluations of the last run, the start point included."""
        return lib.brdffit_optimizer_evaluations(self._handle)

    @property
    def last_improvement(self) -> int:
        """The last iteration that lowered the cost (0 if none did)."""
        return lib.brdffit_optimizer_last_improvement(self._handle)

    @property
    def used_fallback(self) -> bool:
        """Whether a step fell back from Cholesky to the eigen-decomposition."""
        return bool(lib.brdffit_optimizer_used_fallback(self._handle))

    @property
    def condition(self) -> float:
        """Condition number of J^T J over the free parameters (NaN before a run)."""
        return lib.brdffit_optimizer_condition(self._handle)

    def history(self) -> Tuple[np.ndarray, np.ndarray]:
        """``(cost, lambda)``: start value and value after every iteration."""
        h = self._handle
        n = lib.brdffit_optimizer_history(h, None, None)
        cost, lam = np.empty(n), np.empty(n)
        if n:
            lib.brdffit_optimizer_history(h, dptr(cost), dptr(lam))
        return cost, lam

    def covariance(self) -> np.ndarray:
        """``s^2 (J^T J)^+`` at the returned point, ``(n_params, n_params)``;
        rows of fixed parameters and of parameters on a bound are 0."""
        out = np.empty((self._p, self._p))
        self._check(lib.brdffit_optimizer_covariance(self._handle, dptr(out)))
        return out

    def std_errors(self) -> np.ndarray:
        """Square roots of the covariance diagonal."""
        out = np.empty(self._p)
        self._check(lib.brdffit_optimizer_std_errors(self._handle, dptr(out)))
        return out

    def __repr__(self):
        return "<brdffit.Optimizer %d parameters%s>" % (self._p,
                                                        " (closed)" if self._closed else "")
