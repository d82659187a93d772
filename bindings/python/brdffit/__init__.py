"""Python binding of libbrdffit: fit analytic BRDF models to measured reflectance.

The binding loads the C library's shared object with ctypes (set
``BRDFFIT_LIBRARY`` to its full path, or install it where the dynamic loader
finds it) and needs only numpy. Angles are radians, as in the C API.

Main classes:

- :class:`Grid`: a measurement (regular or scattered), from arrays or files;
- :class:`Model`: a built-in model or one written in Python;
- :class:`Fit`: fits a model to a grid and reports the result;
- :func:`fit_many`: many value sets on one geometry in one call (texel maps);
- :class:`Optimizer`: the general Levenberg-Marquardt optimizer;
- :class:`DampingPolicy`, :class:`PythonDamping`: damping policies;
- :mod:`brdffit.image`: textures, spheres and plots as numpy arrays;
- :mod:`brdffit.dask`: batch fits on a ``distributed`` cluster (needs dask);
- :class:`BrdffitError`: raised by every failing call, with ``status``,
  ``status_name`` and the library's ``message``.

Example::

    import brdffit
    grid = brdffit.Grid.load_csv("paint.csv")
    model = brdffit.Model.builtin("ashikhmin-shirley")
    fit = brdffit.Fit(grid, model).run()
    print(fit.params_by_name(), fit.error("rms"))
"""

import math

from ._lib import DEFAULT_CAP, lib as _clib
from . import image
from .damping import DAMPING_POLICIES, DampingPolicy, PythonDamping
from .errors import BrdffitError, Status, status_name, status_string
from .fit import Fit, IterationInfo, METRICS, PIPELINES, STOP_REASONS, Stage
from .grid import Grid, Weighting, default_axes
from .many import ManyResult, fit_many
from .model import JacobianReport, Model, ParamFlags, ParamInfo, ParamLayout
from .optim import Optimizer

__version__ = "0.1.0"

__all__ = ["BrdffitError", "DAMPING_POLICIES", "DEFAULT_CAP", "DampingPolicy", "Fit", "Grid",
           "IterationInfo", "JacobianReport", "METRICS", "ManyResult", "Model", "Optimizer",
           "PIPELINES", "ParamFlags", "ParamInfo", "ParamLayout", "PythonDamping",
           "STOP_REASONS", "Stage", "Status", "Weighting", "default_axes", "deg2rad", "fit_many",
           "image", "library_path", "library_version", "rad2deg", "status_name", "status_string"]


def library_version():
    """The version string of the loaded C library, e.g. ``"0.1.0"``."""
    return _clib.brdffit_version_string().decode()


def library_path():
    """The file the C library was loaded from, as given to the loader: the
    library installed with this package, ``BRDFFIT_LIBRARY``, or a name the
    dynamic loader resolved."""
    return _clib._name


def deg2rad(degrees):
    """Degrees to radians (works on floats and numpy arrays)."""
    return degrees * (math.pi / 180.0)


def rad2deg(radians):
    """Radians to degrees (works on floats and numpy arrays)."""
    return radians * (180.0 / math.pi)
