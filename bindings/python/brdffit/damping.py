"""Damping policies of the Levenberg-Marquardt runs (``brdffit_damping``, optim.h).

A policy chooses how lambda starts and how it reacts to accepted and
rejected steps: one of the library's (``"nielsen"``, the default,
``"marquardt"``, ``"thesis"``), or one written in Python by subclassing
:class:`PythonDamping`. Give it to an :class:`~brdffit.Optimizer`
(``damping=`` or ``set_damping``) or to a :class:`~brdffit.Fit`
(``fit.set_damping``).
"""

import ctypes
from typing import Optional, Union

from . import _lib
from ._lib import lib

__all__ = ["DampingPolicy", "PythonDamping", "DAMPING_POLICIES", "as_policy"]

#: Names of the built-in damping policies.
DAMPING_POLICIES = ("nielsen", "marquardt", "thesis")


class DampingPolicy:
    """A damping policy (``brdffit_damping``): how lambda starts and how it
    reacts to accepted and rejected steps.

    Use :meth:`builtin` for the library's policies, or subclass
    :class:`PythonDamping` for one written in Python.
    """

    def __init__(self, name: str, pointer):
        self._name = name
        self._pointer = pointer

    @classmethod
    def builtin(cls, name: str) -> "DampingPolicy":
        """One of :data:`DAMPING_POLICIES`: ``"nielsen"`` (the default:
        lambda *= max(1/3, 1 - (2 rho - 1)^3) on acceptance, *= nu with nu
        doubling on rejection), ``"marquardt"`` (/10 and x10) or
        ``"thesis"`` (/2 down to 1e-4, x2 up to 1); all start at 1e-3."""
        if name not in DAMPING_POLICIES:
            raise ValueError("unknown damping policy %r (one of %s)"
                             % (name, ", ".join(DAMPING_POLICIES)))
        return cls(name, getattr(lib, "brdffit_damping_" + name)())

    @property
    def name(self) -> str:
        """The policy's short name."""
        return self._name

    def _c_policy(self):
        """A ``const brdffit_damping *`` valid while this object lives."""
        return self._pointer

    def _take_error(self):
        """The exception a Python policy raised in the last run, or None."""
        return None

    def __repr__(self):
        return "<brdffit.DampingPolicy %s>" % self._name


def as_policy(policy: Union[str, DampingPolicy, None]) -> Optional[DampingPolicy]:
    """A :class:`DampingPolicy` from a name, a policy, or None (the default)."""
    if policy is None or isinstance(policy, DampingPolicy):
        return policy
    return DampingPolicy.builtin(policy)


class PythonDamping(DampingPolicy):
    """Base class of a damping policy written in Python.

    Override :meth:`start`, :meth:`accepted` and :meth:`rejected`. The
    policy's per-run state lives in the object: :meth:`start` is called at
    the beginning of every run and resets it. So one object serves one run
    at a time: do not share it between optimizers or fits that run at the
    same time. The library keeps lambda finite and in [1e-300, 1e300].

    An exception raised by a method stops the run (it is cancelled) and is
    re-raised by ``run()``.
    """

    def __init__(self, name: str = "python"):
        self._error = None
        self._on_error = None
        self._name_bytes = name.encode()
        init = _lib.DAMPING_INIT_FN(self._c_init)
        accept = _lib.DAMPING_STEP_FN(self._c_accept)
        reject = _lib.DAMPING_STEP_FN(self._c_reject)
        self._struct = _lib.Damping(ctypes.sizeof(_lib.Damping), self._name_bytes, 0, init,
                                    accept, reject, None)
        self._callbacks = (init, accept, reject)
        super().__init__(name, ctypes.pointer(self._struct))

    def start(self) -> float:
        """The start lambda of a run (reset any per-run state here)."""
        raise NotImplementedError

    def accepted(self, rho: float, lam: float) -> float:
        """The new lambda after an accepted step with gain ratio ``rho`` > 0."""
        raise NotImplementedError

    def rejected(self, rho: float, lam: float) -> float:
        """The new lambda after a rejected step (``rho`` <= 0, or NaN for a
        trial point that could not be evaluated)."""
        raise NotImplementedError

    def _guard(self, fn, lam_p, *args):
        if self._error is not None:
            return
        try:
            lam_p[0] = float(fn(*args))
        except BaseException as exc:  # reported by run()
            self._error = exc
            if self._on_error is not None:
                self._on_error()

    def _c_init(self, state, lam_p, user):
        self._guard(self.start, lam_p)

    def _c_accept(self, state, rho, lam_p, user):
        self._guard(self.accepted, lam_p, rho, lam_p[0])

    def _c_reject(self, state, rho, lam_p, user):
        self._guard(self.rejected, lam_p, rho, lam_p[0])

    def _take_error(self):
        err, self._error = self._error, None
        return err
