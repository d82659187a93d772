"""Pictures of a measurement and of a fit (image.h) as numpy arrays.

Every function returns a new ``uint8`` array of shape ``(height, width, 3)``
(red, green, blue; top row first), ready for ``PIL.Image.fromarray`` or
``matplotlib.pyplot.imshow``. Options are keyword arguments named as the
fields of ``brdffit_image_options`` (docs/definitions.md, Textures):
``gain``, ``difference_gain``, ``exposure``, ``gamma``, ``background``,
``missing``, ``foreground``, ``curve`` (RGB triples), ``scale``,
``block_columns``, ``block_gap`` and ``log_y``; the others keep the
library's defaults. Angles are radians.
"""

import ctypes
from typing import Optional, Sequence

import numpy as np

from . import _lib
from ._lib import bptr, dptr, lib
from .errors import check, new_error

__all__ = ["TEXTURE_KINDS", "options", "plot", "sphere_measured", "sphere_model", "texture",
           "texture_size"]

#: Texture kinds and their ``brdffit_texture_kind`` values.
TEXTURE_KINDS = {"measured": 0, "model": 1, "difference": 2}
_COLOURS = ("background", "missing", "foreground", "curve")
_NUMBERS = ("gain", "difference_gain", "exposure", "gamma", "scale", "block_columns",
            "block_gap", "log_y")


def options(**fields) -> _lib.ImageOptions:
    """A ``brdffit_image_options`` with the library's defaults and ``fields``
    changed (unknown names raise ``TypeError``)."""
    opts = _lib.ImageOptions()
    lib.brdffit_image_options_init(ctypes.byref(opts))
    for name, value in fields.items():
        if name in _COLOURS:
            rgb = [int(c) for c in value]
            if len(rgb) != 3 or min(rgb) < 0 or max(rgb) > 255:
                raise ValueError("%s must be three integers 0 .. 255" % name)
            setattr(opts, name, (ctypes.c_ubyte * 3)(*rgb))
        elif name in _NUMBERS:
            number = float(value)
            if name in ("scale", "block_columns", "block_gap", "log_y"):
                if number < 0 or number != int(number):
                    raise ValueError("%s must be a non-negative integer" % name)
                number = int(number)
            setattr(opts, name, number)
        else:
            raise TypeError("unknown image option %r" % name)
    return opts


def _canvas(width: int, height: int) -> np.ndarray:
    return np.zeros((height, width, 3), dtype=np.uint8)


def texture_size(grid, **opts) -> tuple:
    """``(width, height)`` of the texture of a regular grid with these options."""
    o = options(**opts)
    w, h = ctypes.c_size_t(), ctypes.c_size_t()
    err = new_error()
    check(lib.brdffit_image_texture_size(grid._handle, ctypes.byref(o), ctypes.byref(w),
                                         ctypes.byref(h), ctypes.byref(err)), err)
    return w.value, h.value


def texture(grid, kind: str = "measured", model=None, params: Optional[Sequence[float]] = None,
            **opts) -> np.ndarray:
    """The texture of a regular grid (``brdffit_image_texture``).

    One block per theta_i (stacked, or ``block_columns`` per row); inside a
    block one row per theta_o and one column per signed view azimuth.

    Args:
        grid: a regular :class:`~brdffit.Grid`.
        kind: ``"measured"`` (gain * value), ``"model"`` (gain * model
            value) or ``"difference"`` (model minus measured: red above, blue
            below).
        model, params: the :class:`~brdffit.Model` and its parameter vector
            for the grid's channels (``"model"`` and ``"difference"``; e.g.
            ``fit.model`` and ``fit.params``).

    Raises:
        BrdffitError: ``E_UNSUPPORTED`` for a scattered grid; the model's
            failures.
    """
    if kind not in TEXTURE_KINDS:
        raise ValueError("unknown texture kind %r (one of %s)" % (kind, ", ".join(TEXTURE_KINDS)))
    p = None
    if kind != "measured":
        if model is None or params is None:
            raise ValueError("a %s texture needs model and params" % kind)
        p = np.ascontiguousarray(params, dtype=np.float64).reshape(-1)
        want = model.vector_size(grid.channel_count)
        if p.size != want:
            raise ValueError("params has %d entries, expected %d" % (p.size, want))
    o = options(**opts)
    width, height = texture_size(grid, **opts)
    out = _canvas(width, height)
    err = new_error()
    check(lib.brdffit_image_texture(bptr(out), 3 * width, TEXTURE_KINDS[kind], grid._handle,
                                    None if model is None else model._handle, dptr(p),
                                    ctypes.byref(o), None, ctypes.byref(err)), err)
    return out


def _size(size: int) -> int:
    size = int(size)
    if not 1 <= size <= 32768:
        raise ValueError("size must be 1 .. 32768, got %d" % size)
    return size


def sphere_measured(grid, size: int = 256, light_theta: float = 0.0, light_phi: float = 0.0,
                    **opts) -> np.ndarray:
    """A ``size`` x ``size`` sphere with the measured BRDF of a regular grid,
    lit by a point light at ``(light_theta, light_phi)`` from the view axis
    (``brdffit_image_sphere_measured``): exposure * f * max(n.l, 0)."""
    size = _size(size)
    out = _canvas(size, size)
    o = options(**opts)
    err = new_error()
    check(lib.brdffit_image_sphere_measured(bptr(out), 3 * size, size, grid._handle,
                                            float(light_theta), float(light_phi),
                                            ctypes.byref(o), None, ctypes.byref(err)), err)
    return out


def sphere_model(model, params: Sequence[float], n_channels: Optional[int] = None,
                 size: int = 256, light_theta: float = 0.0, light_phi: float = 0.0,
                 **opts) -> np.ndarray:
    """A ``size`` x ``size`` sphere with a model BRDF at ``params``
    (``brdffit_image_sphere_model``); ``n_channels`` defaults to what the
    length of ``params`` implies."""
    p = np.ascontiguousarray(params, dtype=np.float64).reshape(-1)
    if n_channels is None:
        n_channels = next((nc for nc in range(1, p.size + 1)
                           if model.vector_size(nc) == p.size), None)
        if n_channels is None:
            raise ValueError("params of %d entries fit no channel count" % p.size)
    if p.size != model.vector_size(int(n_channels)):
        raise ValueError("params has %d entries, expected %d"
                         % (p.size, model.vector_size(int(n_channels))))
    size = _size(size)
    out = _canvas(size, size)
    o = options(**opts)
    err = new_error()
    check(lib.brdffit_image_sphere_model(bptr(out), 3 * size, size, model._handle, dptr(p),
                                         int(n_channels), float(light_theta), float(light_phi),
                                         ctypes.byref(o), None, ctypes.byref(err)), err)
    return out


def plot(values: Sequence[float], width: int = 320, height: int = 200, **opts) -> np.ndarray:
    """A line plot of a series (``brdffit_image_plot``), e.g. the cost per
    iteration from ``fit.history()[0]`` (``log_y=True`` for a log axis).
    Sizes 16 .. 32768."""
    v = np.ascontiguousarray(values, dtype=np.float64).reshape(-1)
    width, height = int(width), int(height)
    if width < 1 or height < 1:
        raise ValueError("width and height must be positive")
    out = _canvas(width, height)
    o = options(**opts)
    err = new_error()
    check(lib.brdffit_image_plot(bptr(out), 3 * width, width, height,
                                 dptr(v) if v.size else None, v.size, ctypes.byref(o),
                                 ctypes.byref(err)), err)
    return out
