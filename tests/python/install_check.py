"""Run by run_install.sh from outside the source tree, with an installed
binding: import it, check that it loaded the library it was installed with,
and fit data made from known Ashikhmin-Shirley parameters."""

import math
import os
import sys

import numpy as np

prefix = os.path.realpath(sys.argv[1])

import brdffit  # noqa: E402
from brdffit import _lib  # noqa: E402


def under(path, root):
    return os.path.realpath(path).startswith(root + os.sep)


assert under(brdffit.__file__, prefix), "imported %s, not from %s" % (brdffit.__file__, prefix)
loaded = brdffit.library_path()
assert under(loaded, prefix), "loaded the library %s, not the one under %s" % (loaded, prefix)
assert "BRDFFIT_LIBRARY" not in os.environ

deg = math.pi / 180.0
axes = (np.arange(0.0, 76.0, 15.0) * deg, np.arange(0.0, 76.0, 7.5) * deg,
        np.arange(0.0, 181.0, 20.0) * deg)
ti, to, po = (a.reshape(-1) for a in np.meshgrid(*axes, indexing="ij"))
model = brdffit.Model.builtin("ashikhmin-shirley")
truth = model.pack_params({"ns": 40.0, "cd": [0.3, 0.2, 0.1], "cs": [0.05, 0.06, 0.07]}, 3)
values = model.eval_angles(ti, np.full_like(ti, math.pi), to, po, truth, 3)
grid = brdffit.Grid.from_regular(*axes, values.T)
fit = brdffit.Fit(grid, model).run()
worst = float(np.max(np.abs(fit.params - truth) / np.abs(truth)))
assert worst < 1e-6, "fitted %s, expected %s" % (fit.params, truth)
print("installed binding %s loaded %s; recovered the parameters to %.1e"
      % (os.path.dirname(brdffit.__file__), loaded, worst))
_lib  # the private module exists in the installed package too
