"""Fitting a model to a measured grid."""

import collections
import contextlib
import ctypes
import threading

import numpy as np

from . import _lib
from ._handle import Handle
from ._interrupt import SigintCancel
from ._lib import ALL_CHANNELS, dptr, lib
from .errors import BrdffitError, Status, check, new_error
from .grid import Weighting

__all__ = ["Fit", "IterationInfo", "Stage", "PIPELINES", "OBJECTIVES", "ESTIMATORS", "METRICS",
           "STOP_REASONS"]

#: Pipeline names and their ``brdffit_pipeline`` values.
PIPELINES = {"auto": 0, "joint": 1, "two-stage": 2}
#: Objective names and their ``brdffit_objective`` values (what a fit minimises).
OBJECTIVES = {"squares": 0, "log": 1, "cube-root": 2, "relative": 3}
#: Covariance estimator names and their ``BRDFFIT_FIT_COVARIANCE`` values.
ESTIMATORS = {"classic": 0, "sandwich": 1}
#: Error metric names and their ``brdffit_fit_metric`` values.
METRICS = {"rms": 0, "ngan": 1, "cost": 2}
#: Stop reason names, indexed by ``brdffit_stop_reason`` value.
STOP_REASONS = ("none", "gradient", "step", "cost", "max-iterations", "max-evaluations",
                "cancelled", "callback", "zero-cost", "stalled")

# brdffit_fit_setting values
_PIPELINE, _CAP, _WEIGHTING, _CLEARCOAT, _THREADS, _MAX_ITERATIONS = 1, 2, 3, 4, 5, 6
_OBJECTIVE, _PLAUSIBLE, _COVARIANCE = 7, 8, 9

#: What an iteration callback receives: the 1-based iteration number of the
#: current LM run, whether the step was accepted, the cost at the current
#: point, the damping lambda after the iteration, the gain ratio rho and a copy
#: of the current parameters (the LM run's own parameter vector).
IterationInfo = collections.namedtuple("IterationInfo", "iteration accepted cost lambda_ rho x")

#: One stage of a fit run (``brdffit_fit_stage``): ``kind`` (``"scan"``,
#: ``"polish"``, ``"joint"``, ``"mean"`` or ``"channel"``), ``index`` (a
#: polish's candidate rank, a channel stage's channel, else 0), ``kept``
#: (its result is in the returned parameters), ``converged``, ``stop`` (one
#: of :data:`STOP_REASONS`; ``"none"`` for the scan), ``iterations``,
#: ``evaluations`` and its history ``cost`` and ``lambda_`` (arrays).
Stage = collections.namedtuple(
    "Stage", "kind index kept converged stop iterations evaluations cost lambda_")


def _real(value, what):
    """A float from a real number (a complex one is refused, not truncated)."""
    if isinstance(value, (complex, np.complexfloating)):
        raise TypeError("%s must be a real number, got %r" % (what, value))
    return float(value)


def _lookup(table, value, what):
    if isinstance(value, str):
        try:
            return table[value]
        except KeyError:
            raise ValueError("unknown %s %r (one of %s)" % (what, value, ", ".join(table)))
    return int(value)


class Fit(Handle):
    """A fit of a :class:`~brdffit.Model` to a :class:`~brdffit.Grid` (``brdffit_fit``).

    Options may be given as keyword arguments or set later as properties:

    - ``pipeline``: ``"auto"`` (default: global search, no start values),
      ``"joint"`` or ``"two-stage"``;
    - ``cap``: angle cap in radians (default 75 degrees);
    - ``weighting``: :class:`~brdffit.Weighting` flags (default both);
    - ``clearcoat``: clear-coat R0 in [0, 1), 0 = off;
    - ``threads``: threads per pass over the samples, 1 .. 64;
    - ``max_iterations``: iteration limit of each LM run;
    - ``objective``: what the fit minimises, ``"cube-root"`` (default: the
      fits that render closest to the measurement), ``"log"``,
      ``"relative"`` or ``"squares"`` (the thesis's weighted squares;
      docs/fitting.md);
    - ``plausible``: 0, 1 (default: the diffuse colour <= 1 and each
      built-in specular lobe's directional albedo <= 1, from a table) or 2
      (every term's directional albedo <= 1 by the integral: slower); True
      means 1, False 0;
    - ``errors``: the estimator of :attr:`std_errors` and :meth:`covariance`,
      ``"classic"`` (default: noise of one level after the weights) or
      ``"sandwich"`` (HC3: any noise level per value, e.g. multiplicative
      noise or weights that do not follow the noise; docs/fitting.md);
    - ``start``: start vector, or ``{name: value}`` on top of the model's
      defaults (see :meth:`set_start`);
    - ``fixed``: names (or indices) of parameters to hold at their start
      value, or ``{name: bool}`` (see :meth:`set_fixed`);
    - ``fix``: ``{name: value}``, parameters to hold at these values (see
      :meth:`fix`); ``free``: names of parameters to let move (see
      :meth:`free`);
    - ``damping``: a damping policy or its name (see :meth:`set_damping`);
    - ``callback``: called after every LM iteration (see :meth:`set_callback`).

    The fit keeps its grid and model alive; close it (or use ``with``) to
    free it early. While :meth:`run` is in progress, from any thread
    (its own callbacks included), only :meth:`cancel` and :meth:`close` may
    be called: every other method raises ``BrdffitError`` ``E_INVALID_ARGUMENT``,
    and ``close()`` cancels the run and frees the fit once it has returned.
    """

    _kind = "fit"

    def __init__(self, grid, model, **options):
        self._lock = threading.RLock()
        self._running = False
        super().__init__(None)
        self._grid, self._model = grid, model
        self._parents = []
        self._callback = None
        self._callback_error = None
        self._layout = model.layout(grid.channel_count)
        self._model_name = model.name
        self._start = None  # the start vector last set, None for the defaults
        for parent in (grid, model):
            parent._acquire()
            self._parents.append(parent)
        out = ctypes.c_void_p()
        err = new_error()
        status = lib.brdffit_fit_create(ctypes.byref(out), grid._ptr, model._ptr, None,
                                        ctypes.byref(err))
        if status != Status.OK:
            self._release_parents()
            check(status, err)
        self._ptr = ctypes.c_void_p(out.value)
        self.configure(**options)

    def configure(self, pipeline=None, cap=None, weighting=None, clearcoat=None, threads=None,
                  max_iterations=None, start=None, fixed=None, callback=None, fix=None,
                  free=None, damping=None, objective=None, plausible=None, errors=None):
        """Set several options at once; None leaves an option unchanged
        (``start`` before ``fixed``, ``fix`` and ``free``)."""
        for name, value in (("pipeline", pipeline), ("cap", cap), ("weighting", weighting),
                            ("clearcoat", clearcoat), ("threads", threads),
                            ("max_iterations", max_iterations), ("objective", objective),
                            ("plausible", plausible), ("errors", errors)):
            if value is not None:
                setattr(self, name, value)
        if start is not None:
            self.set_start(start)
        if fixed is not None:
            self.set_fixed(fixed)
        if fix is not None:
            self.fix(fix)
        if free is not None:
            self.free(free)
        if damping is not None:
            self.set_damping(damping)
        if callback is not None:
            self.set_callback(callback)
        return self

    # ---- lifetime -----------------------------------------------------------

    def _release_parents(self):
        parents, self._parents = self._parents, []
        for parent in parents:
            parent._release()

    def _destroy(self):
        ptr, self._ptr = self._ptr, None
        if ptr is not None:
            lib.brdffit_fit_destroy(ptr)
        self._callback = None
        self._release_parents()

    def close(self):
        """Free the C fit. Idempotent. During :meth:`run` (from a callback or
        another thread) it cancels the run and frees the fit once ``run()``
        has returned, which then raises ``E_BAD_HANDLE``."""
        with self._lock:
            if self._closed:
                return
            self._closed = True
            if self._running:
                lib.brdffit_fit_cancel(self._ptr)
                return
        self._destroy()

    @contextlib.contextmanager
    def _idle(self):
        """The C handle, for a call that must not overlap a run (any thread)."""
        with self._lock:
            if self._running:
                raise BrdffitError(Status.E_INVALID_ARGUMENT,
                                   "the fit is running: only cancel() and close() may be "
                                   "called until run() returns")
            yield self._handle

    @property
    def grid(self):
        """The fitted :class:`~brdffit.Grid`."""
        return self._grid

    @property
    def model(self):
        """The :class:`~brdffit.Model`."""
        return self._model

    # ---- options ------------------------------------------------------------

    def _check(self, status):
        """Raise for a failed call on the fit, with the fit's message."""
        if status != Status.OK:
            msg = lib.brdffit_fit_message(self._handle).decode("utf-8", "replace")
            check(status, message=msg)

    def _set(self, setting, value):
        value = _real(value, "setting")
        with self._idle() as h:
            self._check(lib.brdffit_fit_set(h, setting, value))

    def _get(self, setting):
        v = ctypes.c_double()
        with self._idle() as h:
            self._check(lib.brdffit_fit_get(h, setting, ctypes.byref(v)))
        return v.value

    @property
    def pipeline(self):
        """``"auto"``, ``"joint"`` or ``"two-stage"``."""
        value = int(self._get(_PIPELINE))
        return {v: k for k, v in PIPELINES.items()}[value]

    @pipeline.setter
    def pipeline(self, value):
        self._set(_PIPELINE, _lookup(PIPELINES, value, "pipeline"))

    @property
    def cap(self):
        """Angle cap in radians, 0 .. pi/2."""
        return self._get(_CAP)

    @cap.setter
    def cap(self, value):
        self._set(_CAP, value)

    @property
    def weighting(self):
        """:class:`~brdffit.Weighting` flags."""
        return Weighting(int(self._get(_WEIGHTING)))

    @weighting.setter
    def weighting(self, value):
        self._set(_WEIGHTING, int(value))

    @property
    def clearcoat(self):
        """Clear-coat R0 in [0, 1); 0 switches compensation off."""
        return self._get(_CLEARCOAT)

    @clearcoat.setter
    def clearcoat(self, value):
        self._set(_CLEARCOAT, value)

    @property
    def threads(self):
        """Threads for each pass over the samples, 1 .. 64."""
        return int(self._get(_THREADS))

    @threads.setter
    def threads(self, value):
        self._set(_THREADS, value)

    @property
    def max_iterations(self):
        """Iteration limit of each LM run."""
        return int(self._get(_MAX_ITERATIONS))

    @max_iterations.setter
    def max_iterations(self, value):
        self._set(_MAX_ITERATIONS, value)

    @property
    def objective(self):
        """``"squares"``, ``"log"``, ``"cube-root"`` or ``"relative"``."""
        value = int(self._get(_OBJECTIVE))
        return {v: k for k, v in OBJECTIVES.items()}[value]

    @objective.setter
    def objective(self, value):
        self._set(_OBJECTIVE, _lookup(OBJECTIVES, value, "objective"))

    @property
    def plausible(self) -> int:
        """How auto bounds the colours by energy conservation: 0 not at
        all, 1 (default) the diffuse colour and each built-in specular
        lobe's directional albedo (from a table) at most 1, 2 every term's
        directional albedo at most 1 by the integral (slower;
        ``BRDFFIT_FIT_PLAUSIBLE``)."""
        return int(self._get(_PLAUSIBLE))

    @plausible.setter
    def plausible(self, value):
        if isinstance(value, bool):
            value = 1 if value else 0
        self._set(_PLAUSIBLE, value)

    @property
    def errors(self):
        """The covariance estimator, ``"classic"`` or ``"sandwich"``
        (``BRDFFIT_FIT_COVARIANCE``)."""
        value = int(self._get(_COVARIANCE))
        return {v: k for k, v in ESTIMATORS.items()}[value]

    @errors.setter
    def errors(self, value):
        self._set(_COVARIANCE, _lookup(ESTIMATORS, value, "errors"))

    @property
    def n_channels(self):
        """Channel count of the grid."""
        return self._layout.n_channels

    @property
    def layout(self):
        """The model's :class:`~brdffit.ParamLayout` for the grid's channels."""
        return self._layout

    def set_start(self, start):
        """Start values for the joint and two-stage pipelines (and fixed parameters).

        Args:
            start: None for the model's defaults, a full parameter vector,
                or ``{name: value}`` applied on top of the defaults.

        Raises:
            BrdffitError: ``E_RANGE`` for a value outside the model's bounds.
        """
        with self._idle() as h:
            if start is None:
                self._check(lib.brdffit_fit_set_start(h, None))
                self._start = None
                return
            if isinstance(start, dict):
                vec = self._layout.pack(start)
            else:
                vec = _lib.as_float64(start, "start").reshape(-1)
            if vec.size != self.param_count:
                raise ValueError("start has %d entries, expected %d"
                                 % (vec.size, self.param_count))
            self._check(lib.brdffit_fit_set_start(h, dptr(vec)))
            self._start = vec.copy()

    def set_fixed(self, params, fixed=True):
        """Hold parameters fixed at their start value, or free them.

        Args:
            params: a parameter name or index, an iterable of them, or a
                dict ``{name: bool}`` (then ``fixed`` is ignored).
            fixed: True to hold, False to free.
        """
        if isinstance(params, dict):
            items = params.items()
        elif isinstance(params, (str, int)):
            items = [(params, fixed)]
        else:
            items = [(p, fixed) for p in params]
        for p, f in items:
            k = self._layout.find(p) if isinstance(p, str) else int(p)
            if k < 0:
                raise ValueError("parameter index must be >= 0, got %d" % k)
            with self._idle() as h:
                self._check(lib.brdffit_fit_set_fixed(h, k, 1 if f else 0))

    def fix(self, values):
        """Hold parameters at values, in every pipeline.

        Args:
            values: ``{name: value}``; a per-channel parameter takes one
                value for every channel or one per channel. The values
                become the start values of those parameters (the others keep
                the start values last set) and the parameters are held:
                every pipeline returns them exactly, with standard error 0.

        Raises:
            BrdffitError: ``E_RANGE`` for a value outside the model's
                bounds (nothing changes then); ``E_NOT_FOUND`` for an
                unknown name.
        """
        vec = self._layout.pack(values, self._start)
        self.set_start(vec)
        self.set_fixed(list(values), True)

    def free(self, params):
        """Let parameters move (those the model holds by default too, such
        as the microfacet models' ``F0``): :meth:`set_fixed` with False.

        Args:
            params: a name or index, or an iterable of them.
        """
        self.set_fixed(params, False)

    def set_callback(self, fn):
        """Call ``fn(info)`` after every LM iteration (None removes it).

        ``info`` is an :class:`IterationInfo`. Returning a true value stops
        the fit (stop reason ``"callback"``). An exception raised by ``fn``
        also stops the fit and is re-raised by :meth:`run`.
        """
        if fn is None:
            with self._idle() as h:
                self._check(lib.brdffit_fit_set_callback(h, _lib.ITERATION_FN(), None))
                self._callback = None
            return

        def trampoline(info_p, user):
            try:
                i = info_p.contents
                x = np.ctypeslib.as_array(i.x, (i.n_params,)).copy() if i.n_params else \
                    np.empty(0)
                return 1 if fn(IterationInfo(i.iteration, bool(i.accepted), i.cost,
                                             i.lambda_, i.rho, x)) else 0
            except BaseException as exc:
                if self._callback_error is None:
                    self._callback_error = exc
                return 1

        c_fn = _lib.ITERATION_FN(trampoline)
        with self._idle() as h:
            self._check(lib.brdffit_fit_set_callback(h, c_fn, None))
            self._callback = c_fn  # kept alive while the C fit may call it

    def cancel(self):
        """Ask a running fit to stop (from any thread); stop reason ``"cancelled"``."""
        with self._lock:
            lib.brdffit_fit_cancel(self._handle)

    # ---- running ------------------------------------------------------------

    def run(self):
        """Run the fit with the current options; returns ``self``.

        The first exception raised in a Python model or in the iteration
        callback stops the run (also at a trial point and with
        ``threads > 1``) and comes back from ``run()``; Ctrl-C (SIGINT)
        during a run in the main thread cancels it and raises
        ``KeyboardInterrupt``.

        Raises:
            BrdffitError: e.g. ``E_NO_DATA`` when no sample lies inside the
                cap, ``E_MODEL_FAILED`` when the model fails (its Python
                exception, for a Python model, is the ``__cause__``);
                ``E_BAD_HANDLE`` when the fit was closed during the run.
        """
        with self._idle() as h:
            self._running = True
            self._callback_error = None
        pe = self._model._python_eval
        try:
            if pe is not None:
                pe.begin_run(h)
            with SigintCancel(lambda: lib.brdffit_fit_cancel(h)) as sigint:
                status = lib.brdffit_fit_run(h)
            msg = lib.brdffit_fit_message(h).decode("utf-8", "replace")
        finally:
            model_error = pe.end_run(h) if pe is not None else None
            with self._lock:
                self._running = False
                closed = self._closed
            if closed:
                self._destroy()
        cb_error, self._callback_error = self._callback_error, None
        self._raise_run_error(status, msg, model_error, cb_error)
        sigint.raise_if_interrupted()
        if closed:
            raise BrdffitError(Status.E_BAD_HANDLE, "the fit was closed during run()")
        check(status, message=msg)
        return self

    def _raise_run_error(self, status, msg, model_error, cb_error):
        """Re-raise the first exception of the run's Python code, if any."""
        if model_error is not None:
            if not isinstance(model_error, Exception):
                raise model_error
            if status == Status.OK:  # raised at a trial point: the run was stopped
                status = Status.E_MODEL_FAILED
                msg = "model %s raised %s: %s (the fit was stopped)" % (
                    self._model_name, type(model_error).__name__, model_error)
            raise BrdffitError(status, msg) from model_error
        if cb_error is not None:
            raise cb_error

    # ---- results ------------------------------------------------------------

    @property
    def param_count(self):
        """Length of the parameter vector."""
        with self._idle() as h:
            return lib.brdffit_fit_param_count(h)

    def _vector(self, fn):
        out = np.empty(self.param_count)
        with self._idle() as h:
            self._check(fn(h, dptr(out)))
        return out

    @property
    def params(self):
        """The fitted parameter vector (``E_NOT_READY`` before a successful run)."""
        return self._vector(lib.brdffit_fit_params)

    def params_by_name(self):
        """The fitted parameters as ``{name: float or per-channel array}``."""
        return self._layout.unpack(self.params)

    @property
    def std_errors(self):
        """Standard errors of the fitted parameters (0 for fixed or bound ones)."""
        return self._vector(lib.brdffit_fit_std_errors)

    def covariance(self) -> np.ndarray:
        """The ``(n, n)`` covariance of the fitted parameters
        (``brdffit_fit_covariance``): its diagonal is :attr:`std_errors`
        squared; rows and columns of fixed or bound parameters 0, an
        undetermined parameter ``inf`` on the diagonal and 0 beside it."""
        n = self.param_count
        out = np.empty((n, n))
        with self._idle() as h:
            self._check(lib.brdffit_fit_covariance(h, dptr(out)))
        return out

    def std_errors_by_name(self):
        """The standard errors as ``{name: float or per-channel array}``."""
        return self._layout.unpack(self.std_errors)

    def error(self, metric="rms", channel=None):
        """An error figure of the fitted parameters.

        Args:
            metric: ``"rms"`` (eq. 4.1, unweighted), ``"ngan"`` (eq. 3.5) or
                ``"cost"`` (the weighted cost the fit minimises).
            channel: a channel index, or None for all channels together.
        """
        m = _lookup(METRICS, metric, "metric")
        ch = ALL_CHANNELS if channel is None else int(channel)
        if ch < 0:
            raise ValueError("channel must be >= 0")
        v = ctypes.c_double()
        with self._idle() as h:
            self._check(lib.brdffit_fit_error(h, m, ch, ctypes.byref(v)))
        return v.value

    def shader(self):
        """The renderer form ``(Rs, cd, cs)`` (docs/definitions.md, Renderer form).

        Raises:
            BrdffitError: ``E_UNSUPPORTED`` for a model without ``cd`` and
                ``cs``; ``E_RANGE`` when max(cs) >= 1.
        """
        nc = self.n_channels
        rs = ctypes.c_double()
        cd, cs = np.empty(nc), np.empty(nc)
        with self._idle() as h:
            status = lib.brdffit_fit_shader(h, ctypes.byref(rs), dptr(cd), dptr(cs))
            if status == Status.E_UNSUPPORTED:
                check(status, message="model %s has no parameters cd and cs" % self._model_name)
            if status == Status.E_RANGE:
                check(status, message="max(cs) >= 1: no shader form exists")
            self._check(status)
        return rs.value, cd, cs

    @property
    def stop_reason(self):
        """Why the final LM run ended: one of :data:`STOP_REASONS`."""
        with self._idle() as h:
            r = lib.brdffit_fit_stop_reason(h)
        return STOP_REASONS[r] if 0 <= r < len(STOP_REASONS) else "unknown"

    @property
    def stop_reason_text(self):
        """The library's description of :attr:`stop_reason`."""
        with self._idle() as h:
            return lib.brdffit_stop_reason_string(lib.brdffit_fit_stop_reason(h)).decode()

    @property
    def iterations(self):
        """Iterations of the final LM run."""
        with self._idle() as h:
            return lib.brdffit_fit_iterations(h)

    @property
    def passes(self):
        """Passes over the samples the last run made."""
        with self._idle() as h:
            return lib.brdffit_fit_passes(h)

    def warnings(self):
        """The verdict on the last result: a list of ``(name, text)`` pairs,
        one per warning of ``brdffit_fit_warnings()`` (a parameter at a
        bound, no diffuse term, an albedo above 1, the iteration limit, a
        stalled run, ...), empty for a sound fit or before a run. ``name``
        is the short name (e.g. ``"at-bound"``), ``text`` one sentence
        naming the parameter and values."""
        out = []
        with self._idle() as h:
            bits = lib.brdffit_fit_warnings(h)
            bit = 1
            while bits >= bit:
                if bits & bit:
                    buf = ctypes.create_string_buffer(256)
                    lib.brdffit_fit_warning_text(h, bit, buf, len(buf))
                    out.append((lib.brdffit_warning_name(bit).decode(), buf.value.decode()))
                bit <<= 1
        return out

    def history(self):
        """``(cost, lambda)``: arrays of the start value and the value after
        every iteration of the final LM run (empty before a run)."""
        with self._idle() as h:
            n = lib.brdffit_fit_history(h, None, None)
            cost, lam = np.empty(n), np.empty(n)
            if n:
                lib.brdffit_fit_history(h, dptr(cost), dptr(lam))
        return cost, lam

    def converged(self):
        """Whether the last run's answer converged (``brdffit_fit_converged()``).

        True when every LM run whose result is returned (auto: the polish
        returned; joint: its run; two-stage: the mean stage and every
        channel's stage) ended on a small gradient, step or cost reduction,
        or a zero cost; False for an iteration or evaluation limit, a stall
        (stop reason ``"stalled"``), a stop by the callback, a cancel, and
        before a run. It judges the returned point as a stationary point,
        not as the global minimum.
        """
        with self._idle() as h:
            return bool(lib.brdffit_fit_converged(h))

    def stages(self):
        """Every stage of the last run in order: a list of :class:`Stage`
        (auto: ``"scan"``, then one ``"polish"`` per competing candidate;
        joint: ``"joint"``; two-stage: ``"mean"``, then one ``"channel"``
        per channel). Empty before a successful run."""
        out = []
        with self._idle() as h:
            n = lib.brdffit_fit_history_all(h, None, None, None)
            cost, lam = np.empty(n), np.empty(n)
            if n:
                lib.brdffit_fit_history_all(h, dptr(cost), dptr(lam), None)
            info = _lib.FitStage()
            for i in range(lib.brdffit_fit_stage_count(h)):
                self._check(lib.brdffit_fit_stage_info(h, i, ctypes.byref(info),
                                                       ctypes.sizeof(info)))
                part = slice(info.first, info.first + info.length)
                stop = STOP_REASONS[info.stop] if 0 <= info.stop < len(STOP_REASONS) \
                    else "unknown"
                out.append(Stage(lib.brdffit_fit_stage_name(info.kind).decode(), info.index,
                                 bool(info.kept), bool(info.converged), stop, info.iterations,
                                 info.evaluations, cost[part].copy(), lam[part].copy()))
        return out

    def __repr__(self):
        if self._closed:
            return "<brdffit.Fit (closed)>"
        return "<brdffit.Fit %s on %r>" % (self._model_name, self._grid)

    # ---- damping (appended: see brdffit/damping.py) ---------------------------

    def set_damping(self, policy):
        """Use a damping policy for every LM run of the fit.

        Args:
            policy: a :class:`~brdffit.DampingPolicy` (also one written in
                Python, :class:`~brdffit.PythonDamping`), a built-in name
                (``"nielsen"``, ``"marquardt"``, ``"thesis"``), or None for
                the default, ``"nielsen"``.

        An exception raised by a Python policy cancels the fit and is
        re-raised by :meth:`run`.
        """
        from .damping import PythonDamping, as_policy
        policy = as_policy(policy)
        self._check(lib.brdffit_fit_set_damping(
            self._handle, None if policy is None else policy._c_policy()))
        self._damping_policy = policy
        if isinstance(policy, PythonDamping):
            policy._on_error = self._damping_failed

    def _damping_failed(self):
        """A Python policy raised: keep its exception for run() and stop."""
        exc = self._damping_policy._take_error()
        if self._callback_error is None:
            self._callback_error = exc
        lib.brdffit_fit_cancel(self._handle)
