"""BRDF models: the built-in ones and models written in Python."""

import collections
import ctypes
import enum
import math
import threading

import numpy as np

from . import _lib
from ._handle import Handle
from ._lib import BATCH_ARRAYS, NO_INDEX, dptr, lib
from .errors import BrdffitError, Status, check, new_error

__all__ = ["Model", "ParamInfo", "ParamFlags", "ParamLayout", "JacobianReport"]


class ParamFlags(enum.IntFlag):
    """Parameter flags (``brdffit_param_flags``)."""
    NONE = 0
    PER_CHANNEL = 1  #: one value per channel (else shared by all channels)
    LINEAR = 2       #: the model is linear in it (per-channel parameters only)
    LOG_SCALE = 4    #: natural scale is logarithmic (needs lower > 0)
    FIXED = 8        #: held at its start value unless a fit frees it


class ParamInfo(collections.namedtuple("ParamInfo", "name flags lower upper start")):
    """Metadata of one model parameter (``brdffit_param_info``).

    Fields: ``name`` (str), ``flags`` (:class:`ParamFlags`), ``lower``,
    ``upper`` (bounds, may be +-inf) and ``start`` (default start value).
    """

    __slots__ = ()

    def __new__(cls, name, flags=ParamFlags.NONE, lower=-math.inf, upper=math.inf, start=0.0):
        return super().__new__(cls, str(name), ParamFlags(int(flags)), float(lower),
                               float(upper), float(start))

    @property
    def per_channel(self):
        """True for a parameter with one value per channel."""
        return bool(self.flags & ParamFlags.PER_CHANNEL)


#: Result of :meth:`Model.check_jacobian`: the worst relative error and where
#: it occurred (parameter index and name, channel, grid sample), with the
#: analytic and central-difference derivatives there.
JacobianReport = collections.namedtuple(
    "JacobianReport", "worst_error param param_name channel sample analytic numeric")


def _as_params(params):
    return _lib.as_float64(params, "params").reshape(-1)


def _status_of(exc):
    """The status a raised exception asks for: a BrdffitError's own failure
    status (even of a subclass that skipped ``__init__``), else
    ``E_CALLBACK_FAILED``."""
    status = getattr(exc, "status", None) if isinstance(exc, BrdffitError) else None
    if isinstance(status, int) and status in Status.__members__.values() and \
            status != Status.OK:
        return int(status)
    return int(Status.E_CALLBACK_FAILED)


def _shaped(array, shapes, what):
    """``array`` as float64 when its shape is one of ``shapes`` (a transposed
    or otherwise reshaped result of the right size is refused)."""
    a = _lib.as_float64(array, what)
    if a.shape not in shapes:
        raise ValueError("model returned %s of shape %s, expected %s"
                         % (what, a.shape, " or ".join(str(s) for s in shapes)))
    return a


class _PythonEval:
    """The C evaluation callback of a model written in Python.

    Calls ``eval_fn(batch, params, n_channels)`` and copies its results into
    the library's buffers. A Python exception becomes a failure status
    (``BRDFFIT_E_CALLBACK_FAILED``, or the status of a raised
    :class:`BrdffitError`) and is kept so that the call into the library
    that triggered it can re-raise it as the cause of its error.
    """

    def __init__(self, eval_fn, infos):
        self.eval_fn = eval_fn
        self.n_params = len(infos)
        self.per_channel = [info.per_channel for info in infos]
        self.error = None
        self._lock = threading.Lock()  # error and runs, from the library's threads
        self._runs = set()             # C fits running with this model
        self.c_function = _lib.EVAL_FN(self)

    def vector_size(self, nc):
        return sum(nc if pc else 1 for pc in self.per_channel)

    def begin_run(self, fit_ptr):
        """A fit starts running with this model: its first exception cancels it."""
        with self._lock:
            if not self._runs:
                self.error = None
            self._runs.add(fit_ptr.value)

    def end_run(self, fit_ptr):
        """The fit's run is over; returns the exception raised during it, if any."""
        with self._lock:
            self._runs.discard(fit_ptr.value)
            exc = self.error
            if not self._runs:
                self.error = None
            return exc

    def _record(self, exc):
        with self._lock:
            first = self.error is None
            if first:
                self.error = exc
            runs = list(self._runs) if first else []
        for ptr in runs:  # the first exception stops every run using the model
            lib.brdffit_fit_cancel(ptr)

    def __call__(self, batch_p, params_p, nc, values_p, jac_p, user):
        try:
            self.evaluate(batch_p.contents, params_p, nc, values_p, jac_p)
            return Status.OK
        except BaseException as exc:  # never let an exception cross into C
            try:
                self._record(exc)
                return _status_of(exc)
            except BaseException:  # pragma: no cover - last line of defence
                return Status.E_CALLBACK_FAILED

    def evaluate(self, b, params_p, nc, values_p, jac_p):
        n = b.n
        batch = {name: (np.ctypeslib.as_array(getattr(b, name), (n,)).copy() if n
                        else np.empty(0)) for name in BATCH_ARRAYS}
        batch["n"] = n
        batch["want_jacobian"] = bool(jac_p)
        params = np.ctypeslib.as_array(params_p, (self.vector_size(nc),)).copy()
        result = self.eval_fn(batch, params, nc)
        values, jac = result if isinstance(result, tuple) and len(result) == 2 else (result, None)
        values = _shaped(values, [(nc, n)] + ([(n,)] if nc == 1 else []), "values")
        if n:
            np.ctypeslib.as_array(values_p, (nc * n,))[:] = values.reshape(-1)
        if not jac_p:
            return
        if jac is None:
            raise ValueError("model returned no Jacobian although one was requested")
        k = self.n_params
        jac = _shaped(jac, [(k, nc, n)] + ([(k, n)] if nc == 1 else []), "a Jacobian")
        if n:
            np.ctypeslib.as_array(jac_p, (self.n_params * nc * n,))[:] = jac.reshape(-1)


class ParamLayout:
    """Where each parameter of a model lives in the vector for a channel count.

    A snapshot taken from the model: it stays usable after the model is
    closed (fits keep one).

    Attributes:
        n_channels: the channel count.
        params: list of :class:`ParamInfo`.
        index: ``index[k]`` lists the vector positions of parameter ``k``
            (one for a shared parameter, ``n_channels`` for a per-channel one).
        defaults: the vector of default start values.
    """

    def __init__(self, model, n_channels):
        self.n_channels = int(n_channels)
        self.size = model.vector_size(self.n_channels)
        self.params = model.param_info
        self.index = [[model.vector_index(k, c, self.n_channels)
                       for c in range(self.n_channels if p.per_channel else 1)]
                      for k, p in enumerate(self.params)]
        self.defaults = model.default_params(self.n_channels)

    def find(self, name):
        """Declaration index of parameter ``name`` (BrdffitError E_NOT_FOUND if none)."""
        for k, p in enumerate(self.params):
            if p.name == name:
                return k
        raise BrdffitError(Status.E_NOT_FOUND, "no parameter %r" % (name,))

    def pack(self, values, base=None):
        """A vector from ``{name: value}`` on top of ``base`` (default: the defaults)."""
        vec = np.array(self.defaults if base is None else _as_params(base), dtype=np.float64)
        if vec.size != self.size:
            raise ValueError("base has %d entries, expected %d" % (vec.size, self.size))
        for name, value in values.items():
            idx = self.index[self.find(name)]
            v = np.asarray(value, dtype=np.float64).reshape(-1)
            if v.size not in (1, len(idx)):
                raise ValueError("parameter %r takes 1 or %d values, got %d"
                                 % (name, len(idx), v.size))
            vec[idx] = v
        return vec

    def unpack(self, vector):
        """``{name: float or per-channel array}`` from a vector."""
        vec = _as_params(vector)
        if vec.size != self.size:
            raise ValueError("vector has %d entries, expected %d" % (vec.size, self.size))
        return {p.name: (vec[idx].copy() if p.per_channel else float(vec[idx[0]]))
                for p, idx in zip(self.params, self.index)}


class Model(Handle):
    """An immutable BRDF model (``brdffit_model``).

    Create one with :meth:`builtin` or :meth:`custom`. Parameter vectors
    hold, in declaration order, one entry per shared parameter and
    ``n_channels`` consecutive entries per per-channel parameter; use
    :meth:`pack_params` / :meth:`unpack_params` to go between vectors and
    ``{name: value}`` dictionaries. Angles are radians.
    """

    _kind = "model"

    def __init__(self, ptr, python_eval=None):
        super().__init__(ptr)
        self._python_eval = python_eval  # kept alive as long as the C model

    def _destroy_ptr(self, ptr):
        lib.brdffit_model_destroy(ptr)

    # ---- creation ---------------------------------------------------------

    @staticmethod
    def builtin_names():
        """Names of the built-in models, e.g. ``"ashikhmin-shirley"``."""
        return [lib.brdffit_model_builtin_name(i).decode()
                for i in range(lib.brdffit_model_builtin_count())]

    @classmethod
    def builtin(cls, name):
        """A built-in model by name.

        Raises:
            BrdffitError: ``E_NOT_FOUND`` for an unknown name.
        """
        out = ctypes.c_void_p()
        err = new_error()
        check(lib.brdffit_model_create(ctypes.byref(out), _lib.c_string(name, "name"), None,
                                       ctypes.byref(err)), err)
        return cls(out.value)

    @classmethod
    def custom(cls, name, params, eval_fn):
        """A model written in Python.

        Args:
            name: the model's name.
            params: a sequence of :class:`ParamInfo` (or tuples of its
                fields), in declaration order.
            eval_fn: ``eval_fn(batch, params, n_channels)`` returning
                ``(values, jacobian)``. ``batch`` is a dict of 1-D float64
                arrays of ``batch["n"]`` samples: ``lx ly lz vx vy vz``
                (light and view unit vectors), ``nl nv nh hv`` (dot products
                clamped to [1e-4, 1]), ``log_nh`` and ``rv``, plus the bool
                ``batch["want_jacobian"]``. ``params`` is the parameter
                vector. ``values`` has shape ``(n_channels, n)``;
                ``jacobian`` has shape ``(n_params, n_channels, n)``
                (derivative of channel c at sample s with respect to declared
                parameter k, its channel-c entry for a per-channel
                parameter), or None when not wanted. Raising an exception
                fails the evaluation; raise ``BrdffitError(status)`` to
                return a specific status (e.g. ``Status.E_RANGE``).

        The callback may be called from the library's worker threads (fits
        with ``threads > 1``); it then runs under the GIL, one call at a
        time.
        """
        infos = [p if isinstance(p, ParamInfo) else ParamInfo(*p) for p in params]
        if not infos:
            raise ValueError("a model needs at least one parameter")
        names = [_lib.c_string(info.name, "parameter name") for info in infos]
        c_params = (_lib.ParamInfo * len(infos))(*[
            _lib.ParamInfo(nm, int(i.flags), i.lower, i.upper, i.start)
            for nm, i in zip(names, infos)])
        python_eval = _PythonEval(eval_fn, infos)
        d = _lib.ModelDef()
        lib.brdffit_model_def_init(ctypes.byref(d))
        name_b = _lib.c_string(name, "name")
        d.name = name_b
        d.n_params = len(infos)
        d.params = c_params
        d.eval = python_eval.c_function
        out = ctypes.c_void_p()
        err = new_error()
        check(lib.brdffit_model_create_custom(ctypes.byref(out), ctypes.byref(d), None,
                                              ctypes.byref(err)), err)
        return cls(out.value, python_eval)

    # ---- metadata -----------------------------------------------------------

    @property
    def name(self):
        """The model's name."""
        return lib.brdffit_model_name(self._handle).decode()

    @property
    def param_count(self):
        """Number of declared parameters."""
        return lib.brdffit_model_param_count(self._handle)

    @property
    def param_info(self):
        """List of :class:`ParamInfo`, in declaration order."""
        out = []
        for k in range(self.param_count):
            p = lib.brdffit_model_param(self._handle, k).contents
            out.append(ParamInfo(p.name.decode(), p.flags, p.lower, p.upper, p.start))
        return out

    @property
    def param_names(self):
        """Names of the declared parameters, in order."""
        return [p.name for p in self.param_info]

    def param_index(self, name):
        """Declaration index of the parameter called ``name`` (E_NOT_FOUND if none)."""
        index = ctypes.c_size_t()
        status = lib.brdffit_model_param_find(self._handle, _lib.c_string(name, "name"),
                                              ctypes.byref(index))
        check(status, message="model %s has no parameter %r" % (self.name, name)
              if status == Status.E_NOT_FOUND else None)
        return index.value

    def _param(self, param):
        return self.param_index(param) if isinstance(param, str) else int(param)

    def vector_size(self, n_channels):
        """Length of the parameter vector for ``n_channels`` channels."""
        n = lib.brdffit_model_vector_size(self._handle, int(n_channels))
        if n == 0:
            raise BrdffitError(Status.E_INVALID_ARGUMENT,
                               "n_channels must be at least 1, got %r" % (n_channels,))
        return n

    def vector_index(self, param, channel, n_channels):
        """Position of ``param`` (name or index), channel ``channel``, in the vector."""
        i = lib.brdffit_model_vector_index(self._handle, self._param(param), int(channel),
                                           int(n_channels))
        if i == NO_INDEX:
            raise BrdffitError(Status.E_INVALID_ARGUMENT,
                               "no vector entry for parameter %r, channel %r of %r channels"
                               % (param, channel, n_channels))
        return i

    def default_params(self, n_channels):
        """The vector of every parameter's default start value."""
        out = np.empty(self.vector_size(n_channels))
        check(lib.brdffit_model_default_params(self._handle, int(n_channels), dptr(out)))
        return out

    def layout(self, n_channels):
        """The parameter layout for ``n_channels`` channels (a :class:`ParamLayout`)."""
        return ParamLayout(self, n_channels)

    def pack_params(self, values, n_channels, base=None):
        """A parameter vector from ``{name: value}``.

        A per-channel parameter takes a scalar (all channels) or
        ``n_channels`` values. Parameters not named keep their entry of
        ``base`` (default: :meth:`default_params`).
        """
        return self.layout(n_channels).pack(values, base)

    def unpack_params(self, vector, n_channels):
        """``{name: value}`` from a vector: a float for a shared parameter,
        an array of ``n_channels`` values for a per-channel one."""
        return self.layout(n_channels).unpack(vector)

    # ---- evaluation ---------------------------------------------------------

    def _run(self, fn, *args):
        """Call a library function that may run the Python callback; re-raise its error."""
        err = new_error()
        pe = self._python_eval
        if pe is not None:
            with pe._lock:
                pe.error = None
        status = fn(*args, ctypes.byref(err))
        self.raise_callback_error(status, err.message.decode("utf-8", "replace"))
        check(status, err)

    def raise_callback_error(self, status, message):
        """If ``status`` failed and the Python callback raised, re-raise that.

        A failure of the library caused by an exception in the model's
        Python code becomes a :class:`BrdffitError` (with the library's
        status and message) whose ``__cause__`` is the exception; a
        ``BaseException`` that is not an ``Exception`` (KeyboardInterrupt)
        is re-raised as is.
        """
        pe = self._python_eval
        if pe is None:
            return
        exc, pe.error = pe.error, None
        if status == Status.OK or exc is None:
            return
        if not isinstance(exc, Exception):
            raise exc
        raise BrdffitError(status, message) from exc

    def _outputs(self, count, n_channels, jacobian):
        values = np.empty((n_channels, count))
        jac = np.empty((self.param_count, n_channels, count)) if jacobian else None
        return values, jac

    def _check_vector(self, params, n_channels):
        p = _as_params(params)
        if p.size != self.vector_size(n_channels):
            raise ValueError("params has %d entries, expected %d for %d channels"
                             % (p.size, self.vector_size(n_channels), n_channels))
        return p

    def eval_grid(self, grid, params, first=0, count=None, jacobian=False):
        """Evaluate over grid samples ``[first, first + count)``.

        Returns:
            ``values`` of shape ``(n_channels, count)``, or
            ``(values, jac)`` with ``jac`` of shape
            ``(n_params, n_channels, count)`` when ``jacobian`` is True.
        """
        nc = grid.channel_count
        if count is None:
            count = grid.sample_count - first
        p = self._check_vector(params, nc)
        values, jac = self._outputs(count, nc, jacobian)
        self._run(lib.brdffit_model_eval_grid, self._handle, grid._handle, int(first),
                  int(count), dptr(p), dptr(values), dptr(jac))
        return (values, jac) if jacobian else values

    def _infer_channels(self, n_params):
        for nc in range(1, n_params + 1):
            if self.vector_size(nc) == n_params:
                return nc
        raise ValueError("no channel count gives a parameter vector of %d entries" % n_params)

    def eval_angles(self, theta_i, phi_i, theta_o, phi_o, params, n_channels=None,
                    jacobian=False):
        """Evaluate at arbitrary directions (radians; the angles broadcast).

        Args:
            params: the parameter vector.
            n_channels: channel count; None infers it from ``len(params)``.
            jacobian: also return the Jacobian.

        Returns:
            As :meth:`eval_grid`, with ``count`` the number of directions.
        """
        p = _as_params(params)
        nc = self._infer_channels(p.size) if n_channels is None else int(n_channels)
        p = self._check_vector(p, nc)
        angles = [np.ascontiguousarray(a.reshape(-1)) for a in np.broadcast_arrays(
            *[_lib.as_float64(x, "angles") for x in (theta_i, phi_i, theta_o, phi_o)])]
        count = angles[0].size
        values, jac = self._outputs(count, nc, jacobian)
        self._run(lib.brdffit_model_eval_angles, self._handle, count,
                  *[dptr(a) for a in angles], nc, dptr(p), dptr(values), dptr(jac))
        return (values, jac) if jacobian else values

    def check_jacobian(self, grid, params):
        """Compare the analytic Jacobian with central differences over ``grid``.

        Returns:
            A :class:`JacobianReport` with the worst relative error.
        """
        p = self._check_vector(params, grid.channel_count)
        rep = _lib.JacobianReport()
        rep.struct_size = ctypes.sizeof(_lib.JacobianReport)
        self._run(lib.brdffit_model_check_jacobian, self._handle, grid._handle, dptr(p),
                  ctypes.byref(rep))
        return JacobianReport(rep.worst_error, rep.param, self.param_info[rep.param].name,
                              rep.channel, rep.sample, rep.analytic, rep.numeric)

    def __repr__(self):
        if self._closed:
            return "<brdffit.Model (closed)>"
        return "<brdffit.Model %s (%s)>" % (self.name, ", ".join(self.param_names))
